#pragma once
/// Keyframed rigid motion: a timeline of world poses with smooth (C¹) interpolation.
#include <vector>

#include "core/types.hpp"

namespace dexcloth::rigid {

/// One keyframe: at time `t` [s] the frame F has pose `X_WF` in world.
struct PoseKeyframe {
  double t{};                                            ///< time [s]
  Eigen::Isometry3d X_WF{Eigen::Isometry3d::Identity()};  ///< pose of the frame in world
};

/// A sampled pose with its velocity, both in world coordinates.
struct PoseSample {
  Eigen::Isometry3d X_WF{Eigen::Isometry3d::Identity()};  ///< pose in world
  Vec3 v_W{Vec3::Zero()};                                ///< velocity of the frame origin [m/s]
  Vec3 w_W{Vec3::Zero()};                                ///< angular velocity [rad/s]
};

/// Interpolates `keys` (sorted by strictly increasing t, at least one) at time `t` [s]:
/// translation and rotation (slerp) follow the smoothstep s = 3u² − 2u³ between neighbouring
/// keys, so velocity is zero at every key and continuous. Before the first key and after the
/// last the pose is held with zero velocity.
PoseSample sample_pose(const std::vector<PoseKeyframe>& keys, double t);

/// Smoothstep weight and its time derivative for the segment [t0, t1] at `t`:
/// returns {s, ds/dt} with s in [0, 1].
std::pair<double, double> smoothstep(double t0, double t1, double t);

}  // namespace dexcloth::rigid
