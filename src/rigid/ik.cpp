#include "rigid/ik.hpp"

#include <algorithm>

#include "core/assert.hpp"

namespace dexcloth::rigid {

IkResult solve_ik(RigidWorld& world, SkeletonId skeleton, const std::vector<IkTarget>& targets,
                  const IkOptions& options) {
  DEXCLOTH_DEMAND(!targets.empty() && options.damping > 0.0);
  const Eigen::VectorXd q0 = world.positions(skeleton);
  const Eigen::VectorXd lo = world.position_lower_limits(skeleton);
  const Eigen::VectorXd hi = world.position_upper_limits(skeleton);
  // Free DOFs.
  std::vector<int> dofs = options.dofs;
  if (dofs.empty()) {
    for (int i = world.root_dofs(skeleton); i < world.num_dofs(skeleton); ++i) dofs.push_back(i);
  }
  const auto m = static_cast<Eigen::Index>(3 * targets.size());
  const auto n = static_cast<Eigen::Index>(dofs.size());
  Eigen::MatrixXd J(m, n);
  Eigen::VectorXd e(m);
  IkResult result;
  result.q = q0;
  auto evaluate = [&](bool with_jacobian) {
    double max_error = 0.0;
    for (std::size_t t = 0; t < targets.size(); ++t) {
      const auto& target = targets[t];
      const Vec3 err = target.x_W - world.point_W(target.body, target.p_B);
      max_error = std::max(max_error, err.norm());
      const auto row = static_cast<Eigen::Index>(3 * t);
      e.segment<3>(row) = target.weight * err;
      if (!with_jacobian) continue;
      const Eigen::MatrixXd Jp = world.point_jacobian_W(target.body, target.p_B);
      for (Eigen::Index k = 0; k < n; ++k) J.block<3, 1>(row, k) = target.weight * Jp.col(dofs[static_cast<std::size_t>(k)]);
    }
    return max_error;
  };
  // Damped least squares: Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e, clipped per DOF, projected onto limits.
  double error = evaluate(true);
  for (result.iterations = 0; result.iterations < options.max_iterations; ++result.iterations) {
    if (error <= options.tolerance) break;
    const Eigen::MatrixXd A = J * J.transpose() + options.damping * options.damping * Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd dq = J.transpose() * A.ldlt().solve(e);
    const double biggest = dq.cwiseAbs().maxCoeff();
    if (biggest > options.max_step) dq *= options.max_step / biggest;
    for (Eigen::Index k = 0; k < n; ++k) {
      const int i = dofs[static_cast<std::size_t>(k)];
      result.q[i] = std::clamp(result.q[i] + dq[k], lo[i], hi[i]);
    }
    world.set_positions(skeleton, result.q);
    error = evaluate(true);
  }
  result.max_error = error;
  result.converged = error <= options.tolerance;
  world.set_positions(skeleton, q0);
  return result;
}

}  // namespace dexcloth::rigid
