#pragma once
/// Products with the block-sparse system matrix and a block-Jacobi preconditioned conjugate
/// gradient solver whose buffers are allocated once.
#include <span>
#include <vector>

#include "cloth/system_pattern.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// y = A·x for the symmetric matrix A with pattern `p` and 3×3 `blocks` (one per pattern
/// block); x and y of size 3|V|.
void block_multiply(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& x,
                    Eigen::VectorXd& y);

/// Outcome of one PCG solve.
struct PcgResult {
  int iterations{};       ///< iterations taken
  double residual{};      ///< final relative residual ‖b − A·x‖ / ‖b‖ [-]
  bool converged{false};  ///< residual ≤ tolerance
};

/// Conjugate gradient with the inverse 3×3 diagonal blocks as preconditioner.
class BlockPcg {
 public:
  /// Allocates the buffers for systems of `num_vertices` 3×3 block rows.
  void resize(int num_vertices);

  /// Solves A·x = b for SPD A (pattern `p`, `blocks`), starting from the given `x` (warm start),
  /// until the relative residual is ≤ `tolerance` or `max_iterations` are done.
  PcgResult solve(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, double tolerance, int max_iterations);

 private:
  std::vector<Mat3> m_inv_diag;
  Eigen::VectorXd m_r, m_z, m_p, m_q;
};

}  // namespace dexcloth::cloth
