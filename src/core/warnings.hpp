#pragma once
/// Numerical trouble met mid-run, recorded with its step instead of aborting (STYLE.md, Errors).
#include <string>
#include <vector>

namespace dexcloth {

/// One recorded problem: the step it happened at and what happened.
struct Warning {
  long step{};
  std::string message;
};

/// Warnings of a run, with a cap so a persistent problem cannot grow memory without bound.
class WarningLog {
 public:
  /// Records `message` at `step`; past the cap only the count grows.
  void add(long step, std::string message);
  /// Recorded warnings (at most `capacity()`).
  const std::vector<Warning>& entries() const { return m_entries; }
  /// Total number of warnings reported, including those past the cap.
  long count() const { return m_count; }
  static constexpr std::size_t capacity() { return 1000; }

 private:
  std::vector<Warning> m_entries;
  long m_count{};
};

}  // namespace dexcloth
