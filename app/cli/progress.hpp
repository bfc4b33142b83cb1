#pragma once
/// A one-line progress bar on stderr (steps, sim time, ms/step, ETA), only on a terminal.
#include <chrono>

namespace dexcloth::app {

class ProgressBar {
 public:
  /// Shows nothing when `enabled` is false (--quiet, or stderr is not a terminal).
  ProgressBar(long total_steps, double dt, bool enabled);
  /// Redraws at most a few times per second.
  void update(long step, double last_step_ms);
  /// Ends the line.
  void finish();

 private:
  long m_total{};
  double m_dt{};
  bool m_enabled{};
  std::chrono::steady_clock::time_point m_start;
  std::chrono::steady_clock::time_point m_last_draw;
};

/// True when stderr is an interactive terminal.
bool stderr_is_terminal();

}  // namespace dexcloth::app
