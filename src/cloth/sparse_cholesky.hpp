#pragma once
/// Sparse Cholesky factorisation A = L·Lᵀ of a symmetric positive definite matrix by the
/// multifrontal method on supernodes (Duff & Reid 1983; Liu, "The multifrontal method for sparse
/// matrix solution", SIAM Review 1992): columns with the same structure in L form dense fronts,
/// factorised and updated with BLAS-3 kernels (Debian's OpenBLAS). The unknowns keep the
/// caller's order. The pattern is analysed once; factorisations and solves after that reuse
/// the buffers `analyze` allocated.
#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "core/scratch_array.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::cloth {

/// The numeric factor's precision. A single-precision factor moves half the bytes and runs the
/// kernels twice as wide; its solves leave relative residuals of 1e-6 to 1e-3 on a cloth's
/// system, so a caller refines them in double (dynamics.cpp, friction_schur.cpp). The analysis,
/// the inputs and the solves' vectors are the same in both.
enum class Precision { double_precision, single_precision };

class SparseCholesky {
 public:
  /// Symbolic analysis of an n×n pattern given by its upper triangle (diagonal included) in
  /// compressed-column form: `col_start` (n+1) and `row` (one entry per stored value, row ≤
  /// column, any order within a column). The unknowns are eliminated in their given order.
  /// Factorisations run on `threads` threads: independent subtrees of the elimination tree in
  /// parallel, the top serially; the factor is bitwise the same for any thread count.
  void analyze(int n, std::span<const int> col_start, std::span<const int> row, int threads = 1,
               Precision precision = Precision::double_precision);
  /// The same for a pattern of dense blocks between groups of consecutive unknowns (a cloth
  /// vertex's velocities): `groups` (G + 1 increasing starts, from 0), the blocks above and on
  /// the diagonal by column (`block_start`, G + 1, and `block_row`: for group g the groups
  /// h ≤ g with a block A(h, g), g itself included, each once), and where each block's values
  /// lie in the array factorize reads: A(h₀ + a, g₀ + k) = values[block_source[q] + a +
  /// column_stride·k] for block q (only a ≤ k on the diagonal). The analysis runs on the
  /// groups' pattern and the factorisation gathers A by blocks; the factor is bitwise the one
  /// `analyze` gives for the same pattern.
  void analyze_blocks(std::span<const int> groups, std::span<const int> block_start,
                      std::span<const int> block_row, std::span<const int> block_source,
                      int column_stride, int threads = 1,
                      Precision precision = Precision::double_precision);
  /// Runs the factorisations and solves that follow on `pool` (the caller's, with the analysed
  /// number of threads; it must outlive them or be replaced) instead of a pool of this object's
  /// own, created when first needed; null or another size: the own one. A caller whose pool
  /// also runs the work around the solves spares its workers a sleep and a wake-up between them.
  void lend_pool(WorkerPool* pool) { m_lent_pool = pool; }
  Precision precision() const { return m_precision; }

  /// Numeric factorisation with `values` aligned with the analysed `row` (by `analyze`) or
  /// read through the blocks' sources (by `analyze_blocks`). Returns −1 on success, else the
  /// first column whose pivot is not positive and finite.
  int factorize(std::span<const double> values);
  /// The same with value k of A read as base[source[k]] (`source` aligned with the analysed
  /// `row`; not after `analyze_blocks`): the gather runs inside the fronts, on their threads.
  int factorize(std::span<const double> base, std::span<const int> source);

  /// Solves A·x = b in place (`b` of size n holds x on return). Requires a successful factorize.
  /// The solves run on the factorisation's threads, bitwise the same for any thread count.
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
  std::size_t factor_nonzeros() const { return m_panel_start.back() - m_unused_upper; }
  /// Floating-point operations of one factorisation.
  double factor_flops() const { return m_flops; }
  /// Number of supernodes.
  int supernodes() const { return static_cast<int>(m_first.size()) - 1; }
  /// Share of the factorisation's flops in the subtrees the threads share out (the rest, the
  /// top of the tree, runs on one thread); 1 for one thread.
  double parallel_share() const { return m_parallel_share; }

 private:
  int m_n{};
  // Supernodes s: columns [m_first[s], m_first[s+1]); front rows m_rows[m_row_start[s] ..]
  // (its columns first, then the rows below, increasing); L panel (front rows × columns,
  // column-major) at m_panel_start[s] of the panels (Numeric below).
  std::vector<int> m_first, m_row_start, m_rows, m_super_of;
  std::vector<std::size_t> m_panel_start;
  std::size_t m_unused_upper{};  // entries above the diagonal of the panels' pivot blocks
  double m_flops{};
  double m_parallel_share{1.0};
  /// The analysis's settings (both analyses).
  void begin_analysis(int threads, Precision precision);
  /// The analysis shared by both, up to the schedule: the elimination tree and column counts of
  /// the groups' pattern (`group_start`, `group_row`: for group g the groups h < g with entries
  /// in its columns) spread over their unknowns, the supernodes, fronts and schedule. A group's
  /// unknowns are alike (a dense block of A, the same rows before it): they stay alike through
  /// the elimination, a chain of the elimination tree within one supernode, so the analysis of
  /// the groups' pattern is that of A's. `group_of`: each unknown's group.
  void analyze_groups(std::span<const int> groups, const std::vector<int>& group_start,
                      const std::vector<int>& group_row, std::vector<int>& group_of);
  /// Builds the multifrontal schedule (see the members below) from the supernodal tree
  /// (`sparent`, −1 for roots) and each front's flops.
  void schedule(const std::vector<int>& sparent, const std::vector<double>& work);
  /// Assembles and partially factorises supernode s's front (its update matrix built in place
  /// on the stack), A's value k being base[k], or base[source[k]] when `source` is not empty,
  /// or A gathered by blocks after `analyze_blocks`; returns −1, or the column of a failed pivot.
  template <class T>
  int factor_front(int s, std::span<const double> base, std::span<const int> source);
  template <class T>
  int factorize_in(std::span<const double> base, std::span<const int> source);

  // Multifrontal schedule: supernodes children first (a postorder), each one's update matrix
  // at m_stack_offset[s] of the stack (two stacks: even and odd depths of the tree); its
  // children's update rows land at m_relmap positions (per supernode, one per row below its
  // columns) of the parent's front. Thread t factorises the subtrees m_tasks[t] (their
  // supernodes in m_task_order[t], update matrices in its own region of the stack), then the
  // supernodes above them, m_top_order, are done serially.
  std::vector<int> m_postorder, m_child_start, m_children, m_relmap, m_top_order;
  std::vector<std::vector<int>> m_tasks, m_task_order;
  std::vector<std::size_t> m_stack_offset;
  struct Entry {
    int entry{};           ///< index of the value in A
    std::size_t offset{};  ///< its place in its supernode's panel
  };
  std::vector<Entry> m_entries;  // A's values, grouped by supernode (after `analyze`)
  /// A block of A in a panel (after `analyze_blocks`): values[source + a + stride·k] lands at
  /// offset + a·f + k (f the front's rows), a < columns, k < rows (k ≥ a on the diagonal).
  struct Block {
    std::size_t offset{};
    int source{};
    int columns{}, rows{};
    bool diagonal{};
  };
  std::vector<Block> m_blocks;                     // grouped by supernode
  int m_column_stride{};                           // the blocks' (0 after `analyze`)
  std::size_t m_values{};                          // the values a factorisation reads (at least)
  std::vector<std::size_t> m_entry_start;          // per supernode, its first entry or block
  std::vector<int> m_failure;                      // per thread: a failed pivot's column, or −1
  int m_threads{1};                                // threads of the analysis
  WorkerPool* m_lent_pool{};                       // lend_pool's
  mutable std::unique_ptr<WorkerPool> m_own_pool;  // created when first needed, if nothing is lent
  /// The pool to run on: the lent one when it has m_threads threads, else the own one; null for
  /// one thread.
  WorkerPool* pool() const;

  // Solves on the threads (large factors only): task t's supernodes in column order
  // (m_solve_order[t]); whether a supernode is in the top; per subtree supernode, its updates of
  // rows in the top, kept in m_deferred[m_deferred_start[s] ..] by the forward solve until the
  // top's turn.
  bool m_threaded_solves{};
  std::vector<std::vector<int>> m_solve_order;
  std::vector<char> m_in_top;
  std::vector<std::size_t> m_deferred_start;

  /// The numeric buffers of one precision: the panels of L, the update matrices' stacks; the
  /// solves' deferred updates and per-thread scratch; in single precision only, the solve's
  /// vector.
  template <class T>
  struct Numeric {
    BasicScratchArray<T> panel, stack;
    mutable std::vector<T> deferred, x;
    mutable std::vector<std::vector<T>> gather, product;
  };
  Precision m_precision{Precision::double_precision};
  Numeric<double> m_double;
  Numeric<float> m_single;
  template <class T>
  Numeric<T>& numeric();
  template <class T>
  const Numeric<T>& numeric() const;
  std::size_t m_stack_size{};  // entries of the update matrices' stack
  /// Sizes the buffers of the analysed precision and frees the other's.
  void size_buffers();
  /// Entry k of supernode s's panel, in double.
  double entry(int s, std::size_t k) const;
  /// The solves' schedule (above) from the factorisation's.
  void schedule_solves(const std::vector<char>& in_top);
  /// Forward substitution through supernode s; its updates of the top's rows go to `deferred`
  /// when given.
  template <class T>
  void forward_front(int s, T* x, T* product, T* deferred) const;
  /// Back substitution through supernode s's columns before `lead`.
  template <class T>
  void backward_front(int s, T* x, int lead, T* gather) const;
  template <class T>
  void forward_in(T* x) const;
  template <class T>
  void backward_in(T* x, int lead) const;
};

}  // namespace dexcloth::cloth
