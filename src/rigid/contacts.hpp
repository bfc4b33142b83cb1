#pragma once
/// Contact points with forces, per rigid body, as the rigid step solved them (paper §4.1).
#include <vector>

#include "core/types.hpp"

namespace dexcloth::rigid {

/// Index of a body node in a RigidWorld (stable for the world's lifetime).
struct BodyId {
  int index{-1};
  bool valid() const { return index >= 0; }
  friend bool operator==(BodyId, BodyId) = default;
};

/// Index of a skeleton in a RigidWorld (stable for the world's lifetime).
struct SkeletonId {
  int index{-1};
  bool valid() const { return index >= 0; }
  friend bool operator==(SkeletonId, SkeletonId) = default;
};

/// One contact point as seen from one body ("this body"), from the last rigid step.
/// Convention: `n_W` points from the other body into this body, i.e. along the normal force
/// that pushes this body; `f_W` is the whole contact force (normal + friction) on this body.
struct ContactPoint {
  Vec3 p_W{Vec3::Zero()};  ///< contact point in world [m]
  Vec3 n_W{Vec3::Zero()};  ///< unit normal in world, from the other body into this body
  Vec3 f_W{Vec3::Zero()};  ///< contact force on this body in world [N] (normal + friction)
  double f_n{};            ///< normal force magnitude max(0, f_W·n_W) [N]
  double depth{};          ///< penetration depth reported by the detector [m]
  BodyId other;            ///< the other body
};

}  // namespace dexcloth::rigid
