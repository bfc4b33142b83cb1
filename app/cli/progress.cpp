#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace dexcloth::app {

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(long total_steps, double dt, bool enabled)
    : m_total(total_steps), m_dt(dt), m_enabled(enabled),
      m_start(std::chrono::steady_clock::now()), m_last_draw(m_start) {}

void ProgressBar::update(long step, double last_step_ms) {
  if (!m_enabled) return;
  const auto now = std::chrono::steady_clock::now();
  if (step < m_total && now - m_last_draw < std::chrono::milliseconds(200)) return;
  m_last_draw = now;
  const double elapsed = std::chrono::duration<double>(now - m_start).count();
  const double fraction = m_total > 0 ? static_cast<double>(step) / m_total : 1.0;
  const double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width);
  std::fprintf(stderr, "\r[");
  for (int i = 0; i < width; ++i) std::fputc(i < filled ? '#' : '.', stderr);
  std::fprintf(stderr, "] %ld/%ld steps  t=%.3f s  %.1f ms/step  ETA %.0f s   ", step, m_total,
               step * m_dt, last_step_ms, eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (m_enabled) std::fprintf(stderr, "\n");
}

}  // namespace dexcloth::app
