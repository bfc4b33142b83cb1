#pragma once
/// Products with the block-sparse system matrix and a block-Jacobi preconditioned conjugate
/// gradient solver whose buffers are allocated once.
///
/// Parallelism: the vector work is split into fixed chunks of kPcgChunkVertices block rows that
/// OpenMP threads share; reductions (dot products) are summed per chunk and then over the chunks
/// in chunk order, so results are bitwise identical run to run and for any thread count.
#include <span>
#include <vector>

#include "cloth/system_pattern.hpp"
#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::cloth {

/// Block rows (vertices) per chunk of the parallel vector work.
inline constexpr int kPcgChunkVertices = 64;

/// y = A·x for the symmetric matrix A with pattern `p` and 3×3 `blocks` (one per pattern
/// block); x and y of size 3|V|. Large systems run on `pool`'s threads (null: the calling
/// thread), in fixed chunks that threads take as they come free: bitwise the same on any.
void block_multiply(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& x,
                    Eigen::VectorXd& y, WorkerPool* pool = nullptr);

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
  /// until the relative residual is ≤ `tolerance` or `max_iterations` are done, on up to
  /// `threads` OpenMP threads (the result does not depend on `threads`).
  PcgResult solve(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, double tolerance, int max_iterations, int threads = 1);

 private:
  std::vector<Mat3> m_inv_diag;
  Eigen::VectorXd m_r, m_z, m_p, m_q;
  /// Per-chunk partial sums of the reductions, kPartials per chunk.
  std::vector<double> m_partial;
};

}  // namespace dexcloth::cloth
