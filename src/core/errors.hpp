#pragma once
/// Input errors: every problem found in a user's file, each with where it is (STYLE.md, Errors).
#include <stdexcept>
#include <string>
#include <vector>

namespace dexcloth {

/// One problem in an input file: `file: pointer: message`.
struct InputError {
  std::string file;     ///< path of the file as the user gave it
  std::string pointer;  ///< JSON pointer (or other locator) inside the file, "" for the whole file
  std::string message; ///< what is wrong, e.g. "must be > 0, got -1"

  /// "scene.json: /cloths/0/material/density: must be > 0, got -1"
  std::string to_string() const;
};

/// Collects every problem found while validating an input, so all are reported at once.
class ErrorList {
 public:
  void add(std::string file, std::string pointer, std::string message);
  bool empty() const { return m_errors.empty(); }
  std::size_t size() const { return m_errors.size(); }
  const std::vector<InputError>& errors() const { return m_errors; }
  /// All problems, one per line.
  std::string to_string() const;

 private:
  std::vector<InputError> m_errors;
};

/// Thrown when an input cannot be used; carries every problem found.
class InputRejected : public std::runtime_error {
 public:
  explicit InputRejected(ErrorList errors)
      : std::runtime_error(errors.to_string()), m_errors(std::move(errors)) {}
  const ErrorList& errors() const { return m_errors; }

 private:
  ErrorList m_errors;
};

}  // namespace dexcloth
