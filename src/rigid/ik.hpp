#pragma once
/// Inverse kinematics: joint positions that bring body points to world targets (damped least
/// squares on DART's point Jacobians, joint limits respected by projection).
#include <vector>

#include "rigid/world.hpp"

namespace dexcloth::rigid {

/// Bring point p_B of `body` to x_W.
struct IkTarget {
  BodyId body;
  Vec3 p_B{Vec3::Zero()};  ///< point in the body frame [m]
  Vec3 x_W{Vec3::Zero()};  ///< target in world [m]
  double weight{1.0};      ///< relative weight of this target's error
};

struct IkOptions {
  /// DOFs allowed to move (indices into the skeleton's generalized vector); empty: every DOF
  /// except the root joint's.
  std::vector<int> dofs;
  int max_iterations{300};
  double damping{1.0e-2};     ///< λ of (JJᵀ + λ²I)⁻¹ [m]
  double tolerance{1.0e-4};   ///< stop when every target is within this distance [m]
  double max_step{0.2};       ///< largest change of one DOF per iteration [rad or m]
};

struct IkResult {
  Eigen::VectorXd q;          ///< full generalized positions of the skeleton
  double max_error{};         ///< largest target distance at q [m]
  int iterations{};
  bool converged{false};
};

/// Solves from the skeleton's current positions. The skeleton's positions are restored before
/// returning (velocities untouched); the result is in IkResult::q.
IkResult solve_ik(RigidWorld& world, SkeletonId skeleton, const std::vector<IkTarget>& targets,
                  const IkOptions& options = {});

}  // namespace dexcloth::rigid
