#include "core/worker_pool.hpp"

#include <chrono>

#include "core/assert.hpp"

namespace dexcloth {
namespace {

/// How long a thread waiting on its pool (a worker for its next task, the caller for the
/// workers' end) polls before it sleeps on a condition variable. Waking a sleeping thread took
/// 20–100 µs on the 2-core VM, and a `pinch_move` step dispatches about 15 tasks.
constexpr double kPollSeconds = 1e-3;

/// Dispatches so far, of every pool.
std::atomic<long> g_dispatches{0};

/// Polls `ready` for up to kPollSeconds, yielding between polls (so that with more threads than
/// cores a woken thread gets this one's core), and stops early when any pool dispatches a task
/// (its woken worker may need this core); whether `ready` became true.
template <class Ready>
bool poll(Ready ready) {
  const long dispatches = g_dispatches.load(std::memory_order_acquire);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(kPollSeconds);
  for (;;) {
    if (ready()) return true;
    if (g_dispatches.load(std::memory_order_acquire) != dispatches ||
        std::chrono::steady_clock::now() >= until)
      return ready();
    std::this_thread::yield();
  }
}

}  // namespace

WorkerPool* lent_or_own(WorkerPool* lent, std::unique_ptr<WorkerPool>& own, int threads) {
  if (threads <= 1) return nullptr;
  if (lent != nullptr && lent->threads() == threads) return lent;
  if (!own || own->threads() != threads) own = std::make_unique<WorkerPool>(threads);
  return own.get();
}

WorkerPool::WorkerPool(int threads) {
  DEXCLOTH_DEMAND(threads >= 1);
  for (int t = 1; t < threads; ++t) m_workers.emplace_back([this, t] { work(t); });
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard lock(m_mutex);
    m_stop = true;
  }
  m_start.notify_all();
  for (std::thread& w : m_workers) w.join();
}

void WorkerPool::dispatch(void (*function)(void*, int), void* context) {
  if (m_workers.empty()) {
    function(context, 0);
    return;
  }
  {
    const std::lock_guard lock(m_mutex);
    m_function = function;
    m_context = context;
    m_running.store(static_cast<int>(m_workers.size()), std::memory_order_relaxed);
    m_generation.fetch_add(1, std::memory_order_release);
  }
  g_dispatches.fetch_add(1, std::memory_order_acq_rel);
  m_start.notify_all();
  function(context, 0);
  const auto finished = [this] { return m_running.load(std::memory_order_acquire) == 0; };
  if (poll(finished)) return;
  std::unique_lock lock(m_mutex);
  m_done.wait(lock, finished);
}

void WorkerPool::work(int t) {
  long seen = 0;
  for (;;) {
    void (*function)(void*, int) = nullptr;
    void* context = nullptr;
    const auto dispatched = [&] { return m_generation.load(std::memory_order_acquire) != seen; };
    if (poll(dispatched)) {
      // The dispatch wrote the task before its release of the generation.
      seen = m_generation.load(std::memory_order_acquire);
      function = m_function;
      context = m_context;
    } else {
      std::unique_lock lock(m_mutex);
      m_start.wait(lock, [&] { return m_stop || dispatched(); });
      if (m_stop) return;
      seen = m_generation.load(std::memory_order_relaxed);
      function = m_function;
      context = m_context;
    }
    function(context, t);
    // The last worker wakes the caller if it sleeps; under the mutex, so that the caller cannot
    // be between its check and its wait.
    if (m_running.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      const std::lock_guard lock(m_mutex);
      m_done.notify_one();
    }
  }
}

}  // namespace dexcloth
