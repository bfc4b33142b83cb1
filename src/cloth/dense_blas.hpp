#pragma once
/// Dense symmetric algebra on Eigen's column-major matrices through OpenBLAS (blas.hpp), whose
/// kernels use the vector units of the CPU at hand; Eigen's own, without -march, use SSE2 only.
/// Used where the cloth's dense problems are large: the friction's Schur complement.
#include <Eigen/Core>

namespace dexcloth::cloth {

/// S = L·Lᵀ (full, symmetric) for the lower-triangular part of the square `l`.
void lower_times_transpose(const Eigen::MatrixXd& l, Eigen::MatrixXd& s);

/// In place, the lower triangle of the square `a` becomes its Cholesky factor L (a = L·Lᵀ); the
/// strict upper triangle is left as it was. False when `a` is not positive definite.
bool cholesky_lower(Eigen::MatrixXd& a);

/// x = (L·Lᵀ)⁻¹·b in place of `b`, L the lower triangle of `l` (cholesky_lower).
void cholesky_solve(const Eigen::MatrixXd& l, Eigen::VectorXd& b);

/// b = L⁻¹·b in place, L the lower triangle of `l`; b a vector or a matrix of as many rows.
void solve_lower(const Eigen::MatrixXd& l, Eigen::MatrixXd& b);
void solve_lower(const Eigen::MatrixXd& l, Eigen::VectorXd& b);
/// b = L⁻ᵀ·b in place.
void solve_lower_transposed(const Eigen::MatrixXd& l, Eigen::VectorXd& b);

/// c −= wᵀ·w for the symmetric `c` (kept full).
void subtract_gram(const Eigen::MatrixXd& w, Eigen::MatrixXd& c);

}  // namespace dexcloth::cloth
