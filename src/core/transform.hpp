#pragma once
/// Rigid placements shared by scene compilation and mesh loading.
#include <numbers>

#include "core/types.hpp"

namespace dexcloth {

/// Rotation matrix for Euler angles `deg` [deg] applied about x, then y, then z (extrinsic,
/// fixed world axes): R = Rz(deg.z) · Ry(deg.y) · Rx(deg.x). Returns a 3×3 proper rotation.
inline Mat3 rotation_xyz_deg(const Vec3& deg) {
  const Vec3 rad = deg * (std::numbers::pi / 180.0);
  return (Eigen::AngleAxisd(rad.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rad.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rad.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace dexcloth
