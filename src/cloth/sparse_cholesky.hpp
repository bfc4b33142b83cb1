#pragma once
/// Sparse Cholesky factorisation A = L·Lᵀ of a symmetric positive definite matrix by the
/// multifrontal method on supernodes (Duff & Reid 1983; Liu, "The multifrontal method for sparse
/// matrix solution", SIAM Review 1992): columns with the same structure in L form dense fronts,
/// factorised and updated with BLAS-3 kernels (Debian's OpenBLAS). The unknowns keep the
/// caller's order. The pattern is analysed once; factorisations and solves after that reuse
/// the buffers `analyze` allocated.
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

namespace dexcloth::cloth {

class SparseCholesky {
 public:
  /// Symbolic analysis of an n×n pattern given by its upper triangle (diagonal included) in
  /// compressed-column form: `col_start` (n+1) and `row` (one entry per stored value, row ≤
  /// column, any order within a column). The unknowns are eliminated in their given order.
  void analyze(int n, std::span<const int> col_start, std::span<const int> row);

  /// Numeric factorisation with `values` aligned with the analysed `row`. Returns −1 on
  /// success, else the first column whose pivot is not positive and finite.
  int factorize(std::span<const double> values);

  /// Solves A·x = b in place (`b` of size n holds x on return). Requires a successful factorize.
  void solve_in_place(std::span<double> b) const;

  /// The solve in two halves around the last `tail` unknowns, whose values another problem may
  /// settle (a Schur complement): forward_in_place turns b into z = L⁻¹·b; the tail of the
  /// solution then satisfies L₂₂·L₂₂ᵀ·x₂ = L₂₂·z₂ (trailing_factor); with x₂ written over the
  /// tail of z, backward_in_place finishes the leading unknowns: L₁₁ᵀ·x₁ = z₁ − L₂₁ᵀ·x₂.
  void forward_in_place(std::span<double> b) const;
  void backward_in_place(std::span<double> b, int tail) const;

  /// The trailing tail×tail block L₂₂ of the factor (lower triangular); L₂₂·L₂₂ᵀ is the Schur
  /// complement of the leading unknowns in A.
  void trailing_factor(int tail, Eigen::MatrixXd& L22) const;

  /// Entries of L stored (diagonal included; relaxed supernodes store some zeros).
  std::size_t factor_nonzeros() const { return m_panel.size() - m_unused_upper; }
  /// Floating-point operations of one factorisation.
  double factor_flops() const { return m_flops; }
  /// Number of supernodes.
  int supernodes() const { return static_cast<int>(m_first.size()) - 1; }

 private:
  int m_n{};
  // Supernodes s: columns [m_first[s], m_first[s+1]); front rows m_rows[m_row_start[s] ..]
  // (its columns first, then the rows below, increasing); L panel (front rows × columns,
  // column-major) at m_panel[m_panel_start[s] ..].
  std::vector<int> m_first, m_row_start, m_rows, m_super_of;
  std::vector<std::size_t> m_panel_start;
  std::vector<double> m_panel;
  std::size_t m_unused_upper{};  // entries above the diagonal of the panels' pivot blocks
  double m_flops{};
  // Multifrontal schedule: supernodes children first (a postorder), each one's update matrix
  // at m_stack_offset[s] of the stack; its children's update rows land at m_relmap positions
  // (per supernode, one per row below its columns) of the parent's front.
  std::vector<int> m_postorder, m_child_start, m_children, m_relmap;
  std::vector<std::size_t> m_stack_offset;
  std::vector<std::size_t> m_entry_dest;  // each value of A: its offset in m_panel
  std::vector<double> m_stack, m_front;
  mutable std::vector<double> m_gather, m_product;  // solve scratch
};

}  // namespace dexcloth::cloth
