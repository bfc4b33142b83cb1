#pragma once
/// Allocation-free sparse LDLᵀ for symmetric positive definite systems: an up-looking
/// factorisation (elimination tree + row patterns, as in T. Davis, "Algorithm 849: a concise
/// sparse Cholesky factorization package", 2005). The pattern is analysed once; every later
/// factorisation and solve reuses the buffers allocated by `analyze`.
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

namespace dexcloth::cloth {

/// LDLᵀ factorisation of an n×n symmetric matrix given by its upper triangle (diagonal
/// included) in compressed-column form. The caller orders the unknowns (no permutation here).
class SparseLdlt {
 public:
  /// Symbolic analysis of the pattern: `col_start` (n+1) and `row` (one entry per stored
  /// value, row ≤ column). Allocates every buffer the factorisation needs.
  /// With `block` = 3 the pattern must consist of dense 3×3 blocks (unknowns 3v..3v+2 of a
  /// vertex v, upper triangle of the diagonal blocks): the elimination tree and column counts
  /// then come from the block pattern, nine times smaller.
  void analyze(int n, std::span<const int> col_start, std::span<const int> row, int block = 1);

  /// Numeric factorisation with `values` aligned with the analysed `row`. Returns −1 on success,
  /// else the first column whose pivot is not positive and finite (matrix not SPD or NaN).
  int factorize(std::span<const double> values);

  /// Solves A·x = b in place (`b` of size n holds x on return). Requires a successful factorize.
  void solve_in_place(std::span<double> b) const;

  /// The solve in two halves around the last `tail` unknowns, whose values another problem may
  /// settle (a Schur complement): forward_in_place turns b into z = L⁻¹·b; the tail of the
  /// solution then satisfies L₂₂·D₂·L₂₂ᵀ·x₂ = L₂₂·z₂ (trailing_factor); with x₂ written over
  /// the tail of z, backward_in_place finishes the leading unknowns.
  void forward_in_place(std::span<double> b) const;
  void backward_in_place(std::span<double> b, int tail) const;

  /// The trailing tail×tail block of the factor: unit lower L₂₂ and D₂. L₂₂·D₂·L₂₂ᵀ is the
  /// Schur complement of the leading unknowns in A.
  void trailing_factor(int tail, Eigen::MatrixXd& L22, Eigen::VectorXd& D2) const;

  /// Nonzeros of the strictly lower factor L.
  std::size_t factor_nonzeros() const { return m_Li.size(); }

 private:
  int m_n{};
  std::vector<int> m_Ap, m_Ai;             // analysed pattern of A (upper triangle)
  std::vector<int> m_parent, m_Lp, m_Lnz;  // elimination tree, column starts and counts of L
  std::vector<int> m_Li;                   // row indices of L
  std::vector<double> m_Lx, m_D;           // values of L and of the diagonal D
  std::vector<double> m_y;                 // scratch: dense row of the matrix being eliminated
  std::vector<int> m_flag, m_pattern;      // scratch: visited marks and the row pattern
};

}  // namespace dexcloth::cloth
