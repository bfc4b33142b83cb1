#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "core/worker_pool.hpp"

using dexcloth::WorkerPool;

namespace {

// A pause long enough for the pool's threads to be back asleep on their condition variables
// when the next task comes (they poll for 1 ms first).
void let_workers_sleep() { std::this_thread::sleep_for(std::chrono::milliseconds(3)); }

}  // namespace

TEST(WorkerPool, RunsEachThreadIndexOnceAtEveryDispatch) {
  for (int threads : {1, 2, 3}) {
    WorkerPool pool(threads);
    ASSERT_EQ(pool.threads(), threads);
    for (int round = 0; round < 2000; ++round) {
      std::array<std::atomic<int>, 3> calls{};
      std::atomic<int> on_caller{-1};
      const std::thread::id caller = std::this_thread::get_id();
      auto task = [&](int t) {
        calls[static_cast<std::size_t>(t)]++;
        if (std::this_thread::get_id() == caller) on_caller = t;
      };
      pool.run(task);
      for (int t = 0; t < 3; ++t)
        EXPECT_EQ(calls[static_cast<std::size_t>(t)], t < threads ? 1 : 0);
      EXPECT_EQ(on_caller, 0);                      // task 0 runs on the calling thread
      if (round % 500 == 499) let_workers_sleep();  // after a pause too, not only back to back
    }
    EXPECT_EQ(pool.dispatched(), threads > 1 ? 2000 : 0);  // the workers' dispatches
  }
}

TEST(WorkerPool, EveryTaskHasFinishedWhenRunReturns) {
  WorkerPool pool(2);
  for (int round = 0; round < 200; ++round) {
    std::atomic<int> finished{0};
    auto task = [&](int t) {
      // On odd rounds the worker's part outlasts the caller's, which must wait for it.
      if (t == 1 && round % 2 == 1) std::this_thread::sleep_for(std::chrono::microseconds(150));
      finished++;
    };
    pool.run(task);
    EXPECT_EQ(finished, 2);
    if (round % 3 == 0) let_workers_sleep();
  }
}

TEST(WorkerPool, ForEachIndexCallsEveryIndexOnceOnUnevenWork) {
  WorkerPool pool(2);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> calls(97);
    std::array<std::atomic<int>, 2> firsts{};  // first(t) once on each thread t
    dexcloth::for_each_index_after(
        &pool, [&](int t) { firsts[static_cast<std::size_t>(t)]++; }, calls.size(),
        [&](std::size_t k) {
          volatile double sink = 0.0;  // uneven work: index k takes ~k units
          for (std::size_t i = 0; i < 200 * k; ++i) sink = sink + static_cast<double>(i);
          calls[k]++;
        });
    EXPECT_EQ(firsts[0], 1);
    EXPECT_EQ(firsts[1], 1);
    for (std::size_t k = 0; k < calls.size(); ++k) EXPECT_EQ(calls[k], 1) << "index " << k;
  }
}

TEST(WorkerPool, APoolRunsBesideAnotherPoolsTask) {
  // The coupling step's pattern: a task of one pool (the search beside the dynamics) while the
  // caller's own task drives a second pool (the factorisation's).
  WorkerPool outer(2), inner(2);
  for (int round = 0; round < 300; ++round) {
    std::atomic<int> inner_calls{0}, outer_calls{0};
    auto outer_task = [&](int t) {
      if (t == 0) {
        for (int k = 0; k < 5; ++k) {
          auto inner_task = [&](int) { inner_calls++; };
          inner.run(inner_task);
        }
      }
      outer_calls++;
    };
    outer.run(outer_task);
    EXPECT_EQ(outer_calls, 2);
    EXPECT_EQ(inner_calls, 10);
  }
}

TEST(WorkerPool, JoinsItsThreadsRightAfterATaskOrAsleep) {
  // A destructor that missed a worker would hang here (CTest's timeout).
  for (bool asleep : {false, true}) {
    std::atomic<int> calls{0};
    {
      WorkerPool pool(3);
      auto task = [&](int) { calls++; };
      pool.run(task);
      if (asleep) let_workers_sleep();
    }
    EXPECT_EQ(calls, 3);
  }
}
