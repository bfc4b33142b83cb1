#pragma once
/// A fixed set of worker threads for coarse parallel tasks (a factorisation's subtrees, a
/// collision pass's halves). A thread waiting on the pool polls for a millisecond, yielding its
/// core between polls, then sleeps on a condition variable: tasks that follow each other closely
/// (a step's dozen) find the workers awake, while idle threads cost nothing for long on a
/// machine shared with other jobs (OpenMP's spinning waits did). Running a task allocates
/// nothing.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace dexcloth {

class WorkerPool {
 public:
  /// A pool running tasks on `threads` threads in all: the caller and threads − 1 workers.
  explicit WorkerPool(int threads = 1);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Threads a task runs on (≥ 1).
  int threads() const { return static_cast<int>(m_workers.size()) + 1; }
  /// Tasks run so far on more than the calling thread (none when there are no workers).
  long dispatched() const { return m_generation.load(std::memory_order_acquire); }

  /// Calls task(t) for t = 0 .. threads() − 1, t = 0 on the calling thread, and returns when
  /// every call has. Calls must not throw. Not reentrant.
  template <typename Task>
  void run(Task& task) {
    dispatch([](void* context, int t) { (*static_cast<Task*>(context))(t); }, &task);
  }

 private:
  void dispatch(void (*function)(void*, int), void* context);
  void work(int t);

  std::vector<std::thread> m_workers;
  std::mutex m_mutex;
  std::condition_variable m_start, m_done;
  void (*m_function)(void*, int){};
  void* m_context{};
  std::atomic<long> m_generation{0};  ///< tasks dispatched so far
  std::atomic<int> m_running{0};      ///< workers still on the current task
  bool m_stop{};
};

/// The pool to run `threads` threads on: `lent` when it has that many, else `own` (made, or
/// remade, with that many); null for one thread. For a caller that may be lent its caller's.
WorkerPool* lent_or_own(WorkerPool* lent, std::unique_ptr<WorkerPool>& own, int threads);

/// Calls first(t) on each of `pool`'s threads t (t = 0 the calling thread) and body(k) for
/// k = 0 .. count − 1, each k on whichever thread is free (for pieces of uneven work): a thread
/// joins the indices when its first(t) returns. With a null `pool`, all on the calling thread,
/// first(0) first. Whatever the threads, each k is called once; results written per k do not
/// depend on them.
template <typename First, typename Body>
void for_each_index_after(WorkerPool* pool, First first, std::size_t count, Body body) {
  if (pool == nullptr) {
    first(0);
    for (std::size_t k = 0; k < count; ++k) body(k);
    return;
  }
  std::atomic<std::size_t> next{0};
  auto task = [&](int t) {
    first(t);
    for (std::size_t k = next++; k < count; k = next++) body(k);
  };
  pool->run(task);
}

/// for_each_index_after with nothing first.
template <typename Body>
void for_each_index(WorkerPool* pool, std::size_t count, Body body) {
  for_each_index_after(
      pool, [](int) {}, count, body);
}

}  // namespace dexcloth
