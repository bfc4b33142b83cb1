#include "rigid/patch_pool.hpp"

#include <dart/dynamics/FreeJoint.hpp>

#include "core/assert.hpp"
#include "rigid/detail/world_impl.hpp"

namespace dexcloth::rigid {

int PatchPool::capacity() const { return static_cast<int>(m_world->patches.size()); }

void PatchPool::set(int i, const PatchState& state) {
  DEXCLOTH_DEMAND(i >= 0 && i < capacity());
  if (!state.active) {
    m_world->park_patch(i);
    return;
  }
  DEXCLOTH_DEMAND(state.extents.minCoeff() > 0.0 && state.thickness > 0.0 && state.mass > 0.0);
  DEXCLOTH_DEMAND(state.v_W.allFinite() && state.w_W.allFinite() && state.X_WP.matrix().allFinite());
  detail::PatchRecord& p = m_world->patches[static_cast<std::size_t>(i)];
  p.active = true;
  p.layer = state.layer;
  // Geometry and inertia of a thin box (paper §5: thickness = cloth thickness).
  m_world->resize_patch(i, Vec3(state.extents.x(), state.extents.y(), state.thickness));
  auto& skel = *m_world->skeletons[static_cast<std::size_t>(p.skeleton)].skel;
  dart::dynamics::BodyNode* body = skel.getBodyNode(0);
  body->setInertia(dart::dynamics::Inertia(state.mass, Vec3::Zero(), p.box->computeInertia(state.mass)));
  skel.setGravity(m_world->patch_gravity ? m_world->world->getGravity() : Vec3::Zero());
  detail::set_free_root_state(skel, state.X_WP, state.v_W, state.w_W);
}

void PatchPool::deactivate_all() {
  for (int i = 0; i < capacity(); ++i) {
    if (active(i)) m_world->park_patch(i);
  }
}

bool PatchPool::active(int i) const { return m_world->patches.at(static_cast<std::size_t>(i)).active; }

BodyId PatchPool::body(int i) const { return BodyId{m_world->patches.at(static_cast<std::size_t>(i)).body}; }

const std::vector<ContactPoint>& PatchPool::contacts(int i) const {
  return m_world->bodies[static_cast<std::size_t>(body(i).index)].contacts;
}

Vec3 PatchPool::contact_force_W(int i) const {
  Vec3 f = Vec3::Zero();
  for (const auto& c : contacts(i)) f += c.f_W;
  return f;
}

void PatchPool::set_gravity(bool on) { m_world->patch_gravity = on; }

}  // namespace dexcloth::rigid
