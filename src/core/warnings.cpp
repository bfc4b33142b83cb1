#include "core/warnings.hpp"

namespace dexcloth {

void WarningLog::add(long step, std::string message) {
  ++m_count;
  if (m_entries.size() < capacity()) m_entries.push_back({step, std::move(message)});
}

}  // namespace dexcloth
