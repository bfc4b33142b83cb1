#pragma once
/// Keyframed rigid motion (translation + rotation) with smooth interpolation, shared by cloth
/// handles, scene obstacles and controller targets.
#include <vector>

#include "core/types.hpp"

namespace dexcloth {

/// One key: at time t [s], an offset translation [m] and rotation (degrees about x, y, z).
struct Key {
  double t{};
  Vec3 translation{Vec3::Zero()};
  Vec3 rotation_deg{Vec3::Zero()};
};

/// Piecewise cubic Hermite track through keys with Catmull–Rom tangents (C¹, no overshoot at the
/// ends: tangents are zero at the first and last key), rotation by quaternion slerp with smoothstep
/// timing. Before the first key the first pose holds; after the last, the last pose holds. An empty
/// track is the identity.
class KeyTrack {
 public:
  KeyTrack() = default;
  /// Keys must have strictly increasing t (validated by the scene parser).
  explicit KeyTrack(std::vector<Key> keys);

  bool empty() const { return m_keys.empty(); }
  /// Offset translation at time t [m].
  Vec3 translation(double t) const;
  /// Offset rotation at time t.
  Eigen::Quaterniond rotation(double t) const;
  /// Offset pose at time t (rotation then translation).
  Eigen::Isometry3d pose(double t) const;

 private:
  std::vector<Key> m_keys;
  std::vector<Eigen::Quaterniond> m_rotations;
  /// Index of the segment [k, k+1] holding t, and the local parameter s in [0,1].
  void locate(double t, std::size_t& k, double& s) const;
};

}  // namespace dexcloth
