#include "core/errors.hpp"

namespace dexcloth {

std::string InputError::to_string() const {
  std::string s = file;
  if (!pointer.empty()) s += ": " + pointer;
  return s + ": " + message;
}

void ErrorList::add(std::string file, std::string pointer, std::string message) {
  m_errors.push_back({std::move(file), std::move(pointer), std::move(message)});
}

std::string ErrorList::to_string() const {
  std::string s;
  for (const auto& e : m_errors) s += e.to_string() + "\n";
  return s;
}

}  // namespace dexcloth
