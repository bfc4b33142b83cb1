#pragma once
/// Rigid cloth patches (paper §5): a fixed pool of thin free boxes whose state the coupling
/// sets every step; they take part in the rigid step and report the forces the hand puts on
/// the cloth. Patches never collide with each other; inactive patches collide with nothing.
#include <vector>

#include "core/types.hpp"
#include "rigid/contacts.hpp"

namespace dexcloth::rigid {

namespace detail {
struct WorldImpl;
}

/// State of one patch for the coming rigid step. Frame P: centre of the box, local z along the
/// patch normal, local x/y along the rectangle's sides.
struct PatchState {
  bool active{false};
  Vec2 extents{0.01, 0.01};                             ///< side lengths along P's x, y [m]
  double thickness{1.0e-3};                             ///< box size along P's z [m], > 0
  Eigen::Isometry3d X_WP{Eigen::Isometry3d::Identity()}; ///< pose of the patch in world
  Vec3 v_W{Vec3::Zero()};                               ///< velocity of the centre [m/s]
  Vec3 w_W{Vec3::Zero()};                               ///< angular velocity [rad/s]
  double mass{1.0e-3};                                  ///< [kg], > 0
  /// Patches of the same layer never collide with each other; of different layers they do
  /// (the coupling gives each cloth its own layer, so held stacked sheets keep their patches
  /// apart and fingers cannot close through the stack).
  int layer{0};
};

/// The pool, owned by a RigidWorld (RigidWorld::patches()). Capacity is fixed at construction.
class PatchPool {
 public:
  explicit PatchPool(detail::WorldImpl& world) : m_world(&world) {}

  /// Number of patches in the pool.
  int capacity() const;
  /// Sets patch `i` (0 ≤ i < capacity()) for the next step. Sizes and mass must be > 0.
  void set(int i, const PatchState& state);
  /// Makes every patch inactive (parked far away, no collisions, no gravity).
  void deactivate_all();
  /// Whether patch `i` is active.
  bool active(int i) const;
  /// The body node of patch `i` (named "patches/patch_<i>").
  BodyId body(int i) const;
  /// Contacts on patch `i` from the last step (see ContactPoint for the normal convention).
  const std::vector<ContactPoint>& contacts(int i) const;
  /// Sum of contact forces on patch `i` from the last step, in world [N].
  Vec3 contact_force_W(int i) const;
  /// Whether patch gravity is on for active patches (default true: a patch weighs what its
  /// cloth weighs while in the rigid step).
  void set_gravity(bool on);

 private:
  detail::WorldImpl* m_world;
};

}  // namespace dexcloth::rigid
