#include "cloth/state.hpp"

#include "cloth/dynamics_workspace.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {

DynamicsScratch::DynamicsScratch() = default;
DynamicsScratch::~DynamicsScratch() = default;
DynamicsScratch::DynamicsScratch(const DynamicsScratch&) {}
DynamicsScratch& DynamicsScratch::operator=(const DynamicsScratch& other) {
  if (this != &other) m_workspace.reset();
  return *this;
}
DynamicsScratch::DynamicsScratch(DynamicsScratch&&) noexcept = default;
DynamicsScratch& DynamicsScratch::operator=(DynamicsScratch&&) noexcept = default;

DynamicsWorkspace& DynamicsScratch::get() {
  if (!m_workspace) m_workspace = std::make_unique<DynamicsWorkspace>();
  return *m_workspace;
}

ClothState make_state(const ClothModel& model, const Points& x0) {
  DEXCLOTH_DEMAND(x0.rows() == model.num_vertices());
  ClothState s;
  s.x = x0;
  s.v = Points::Zero(x0.rows(), 3);
  s.f_ext = Points::Zero(x0.rows(), 3);
  s.constraint_impulse = Points::Zero(x0.rows(), 3);
  return s;
}

}  // namespace dexcloth::cloth
