#include "core/worker_pool.hpp"

#include "core/assert.hpp"

namespace dexcloth {

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
    m_running = static_cast<int>(m_workers.size());
    ++m_generation;
  }
  m_start.notify_all();
  function(context, 0);
  std::unique_lock lock(m_mutex);
  m_done.wait(lock, [this] { return m_running == 0; });
}

void WorkerPool::work(int t) {
  long seen = 0;
  for (;;) {
    void (*function)(void*, int) = nullptr;
    void* context = nullptr;
    {
      std::unique_lock lock(m_mutex);
      m_start.wait(lock, [&] { return m_stop || m_generation != seen; });
      if (m_stop) return;
      seen = m_generation;
      function = m_function;
      context = m_context;
    }
    function(context, t);
    {
      const std::lock_guard lock(m_mutex);
      --m_running;
    }
    m_done.notify_one();
  }
}

}  // namespace dexcloth
