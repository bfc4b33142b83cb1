#pragma once
/// Internal to the dynamics: the buffers of the implicit step, allocated on the first step.
#include <memory>
#include <span>
#include <vector>

#include "cloth/block_pcg.hpp"
#include "cloth/dynamics.hpp"
#include "cloth/sparse_cholesky.hpp"
#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::cloth {

/// A direct solver for the system: the factorisation of its blocks in an elimination order of
/// the vertices (or of the scalar unknowns, a vertex's consecutive ones analysed as a group).
struct DirectSystem {
  std::vector<int> order;      ///< vertex eliminated k-th (empty before a first analysis by vertex)
  std::vector<int> dof;        ///< permuted unknown k is original unknown dof[k]
  SparseCholesky cholesky;
};

/// One piece of the assembly: the rows of the right-hand side of vertices
/// [first_vertex, end_vertex), the blocks of their columns [first_block, end_block), and the
/// elements that touch those vertices (an element across two parts is evaluated by both).
struct AssemblyPart {
  int first_vertex{}, end_vertex{};
  int first_block{}, end_block{};
  std::vector<int> faces, hinges;  ///< in increasing order, as the serial assembly visits them
};

/// The inputs an assembly was made from (bitwise copies), for the pieces of an assembly ahead
/// (begin_assembly) and the solve's check that they still hold.
struct AssemblyInputs {
  Points x, v, f_ext;
  double h{};
  Vec3 gravity{Vec3::Zero()};
};

/// Buffers of solve_velocities (see dynamics.cpp). Sized for one model on the first step.
struct DynamicsWorkspace {
  int num_vertices{-1};           ///< |V| the buffers are sized for; −1 before the first step
  std::vector<Mat3> blocks;       ///< values of the system matrix, one per pattern block
  Eigen::VectorXd rhs;            ///< 3|V| right-hand side
  Eigen::VectorXd dv;             ///< 3|V| velocity change (PCG warm start)
  Eigen::VectorXd work;           ///< 3|V| scratch (residual, permuted vectors)
  Eigen::VectorXd correction;     ///< 3|V| scratch: a refinement's correction of Δv
  std::vector<char> constrained;  ///< |V| flags of velocity-constrained vertices
  std::vector<Mat3> saved_rows;   ///< constrained rows' blocks A(i, j) before elimination
  std::vector<Vec3> saved_rhs;    ///< constrained rows' right-hand sides before elimination
  // Friction rounds: the assembled system before elimination (Newton over the cloth only), and
  // the round's constraints.
  std::vector<Mat3> base_blocks;
  Eigen::VectorXd base_rhs;
  std::vector<VelocityConstraint> all_constraints;
  std::vector<VelocityConstraint> solve_constraints;  ///< a friction solve's, squeezed normals too
  std::vector<Vec3> last_slip;  ///< each friction vertex's slip at the last Newton iterate
  std::vector<char> held;       ///< |V| flags of vertices held by the caller's velocity constraints
  std::vector<Vec3> squeezed_normal;  ///< |V| scratch: a squeezed vertex's normal, else zero
  std::vector<char> active;           ///< per friction constraint: 1 unless its vertex is held
  Eigen::VectorXd dv_iterate;         ///< friction Newton: current iterate
  Eigen::VectorXd dv_step;            ///< friction Newton: step to the next iterate
  DirectSystem direct;                ///< the direct solver, in the pattern's fill-reducing order
  /// Friction through a Schur complement: the direct solver with the friction vertices' slip
  /// coordinates last, in their frames.
  DirectSystem schur;
  std::vector<int>
      schur_vertices;             ///< vertices ordered last: the friction vertices and recent ones
  std::vector<int> schur_slot;    ///< |V|: position of a friction vertex in schur_vertices, or −1
  std::vector<int> schur_order;   ///< the unknowns' elimination order with their slip ones last
  std::vector<char> schur_mark;   ///< |V| scratch: vertices with friction this step
  std::vector<char> schur_count;  ///< |V|: slip coordinates (2 or 3) of a vertex while in F
  std::vector<char> schur_planes;  ///< per friction vertex: its contact planes (0, 1, 2 = more)
  std::vector<Mat3> schur_frame;   ///< per friction vertex: its frame (slip axes first)
  std::vector<int> schur_yoff;     ///< per friction vertex: offset of its slip coordinates; total
  std::vector<int> schur_qoff;     ///< per friction vertex: offset in the Newton problem, or −1
  std::vector<int> schur_fidx, schur_ridx;  ///< tail coordinates with friction now, and the rest
  std::vector<std::pair<int, Mat3>> schur_saved_blocks;  ///< blocks before the frames' rotation
  std::vector<std::pair<int, Vec3>> schur_saved_rhs;     ///< right-hand sides before it
  Eigen::MatrixXd schur_L, schur_S, schur_K;  ///< trailing factor, Schur complement, Newton
  Eigen::MatrixXd schur_Sxx, schur_Lr, schur_W;  ///< S condensed on x; S_rr = L_r·L_rᵀ; L_r⁻¹·S_rx
  Eigen::VectorXd schur_c, schur_cx, schur_zr, schur_tail;
  // Refinement of a single-precision factor's solve: a round's correction of Δv (3|V|), the
  // friction gradients at its start (q).
  Eigen::VectorXd schur_delta, schur_g0;
  Eigen::VectorXd schur_x, schur_r, schur_step, schur_trial;
  // Assembly in pieces, on several threads, or ahead of the solve.
  std::vector<AssemblyPart> assembly_parts;
  /// The solver's threads (assembly pieces, factorisations and solves, residual products);
  /// none for one thread (solver_pool). A caller may lend its own pool for a while instead
  /// (lent_pool, see lend_solver_pool).
  std::unique_ptr<WorkerPool> pool;
  WorkerPool* lent_pool{};
  AssemblyInputs assembly_inputs;
  std::vector<char> piece_done;  ///< per piece of an assembly ahead: assembled; empty: none

  // Iterative solver.
  bool pcg_ready{false};
  BlockPcg pcg;
};

/// Splits the assembly into `pieces` (1 to 64) pieces of consecutive vertices with about as many
/// blocks each (a block (i, j) belongs to its column j's piece). Any split assembles bitwise the
/// same system; the first assembly makes the default one.
void split_assembly(const ClothModel& model, int pieces, DynamicsWorkspace& ws);

/// Analyses the system's blocks in the vertex elimination `order` for factorisations on
/// `threads` threads (SparseCholesky::analyze_blocks, each vertex's unknowns a group).
void analyse(const SystemPattern& pattern, std::span<const int> order, int threads, DirectSystem& d,
             Precision precision = Precision::double_precision);
/// The same in an elimination order of the scalar unknowns: `dofs[k]` = 3v + c is unknown c of
/// vertex v, eliminated k-th (a permutation of 0 .. 3|V| − 1). d.order is left empty.
void analyse_unknowns(const SystemPattern& pattern, std::span<const int> dofs, int threads,
                      DirectSystem& d, Precision precision = Precision::double_precision);

/// The solver's pool for `threads`: ws.lent_pool when it has that many threads, else ws.pool
/// (created on first use); null for one thread.
WorkerPool* solver_pool(int threads, DynamicsWorkspace& ws);

/// Factorises `blocks` in `d`'s order, on `pool` (SparseCholesky::lend_pool; null: the
/// factor's own threads), which its solves then use too; on failure the report names the
/// unknown whose pivot failed.
DynamicsReport factorise(const std::vector<Mat3>& blocks, DirectSystem& d,
                         WorkerPool* pool = nullptr);

/// A sliding vertex's slip has settled (Newton's Hessian is used) when it turned by less than
/// acos(0.9) ≈ 26° since the last iteration.
constexpr double kSettledCos = 0.9;

/// Iterative refinement of a single-precision factor's solves stops when a round reduces the
/// residual by less than this factor (rounding reached; a float factor gains ~1e3 a round).
constexpr double kRefinementGain = 10.0;

/// The projector onto a velocity constraint's free directions.
Mat3 free_projector(const VelocityConstraint& c);

/// Eliminates the constrained unknowns from ws.blocks and ws.rhs (see dynamics.cpp).
void eliminate_constraints(const ClothModel& model, const ClothState& state,
                           std::span<const VelocityConstraint> constraints, DynamicsWorkspace& ws);

/// Tangential slip of friction constraint f at the velocity change `dv`: the vertex's velocity
/// v + Δv relative to its surface, projected on the contact plane.
inline Vec3 tangential_slip(const FrictionConstraint& f, const ClothState& state,
                            const Eigen::VectorXd& dv) {
  const Vec3 w =
      state.v.row(f.vertex).transpose() + dv.segment<3>(3 * f.vertex) - f.surface_velocity;
  return w - f.normal.dot(w) * f.normal;
}

/// Gradient of B·φ(‖w‖) in the slip w, φ the norm smoothed below ε (s²/2ε + ε/2 there): the
/// friction impulse is its negative.
Vec3 friction_gradient(const Vec3& w, double bound, double eps);

/// Friction of solve_velocities through the Schur complement of the friction vertices (inputs
/// as for solve_friction_newton): the assembled system, turned into the contact frames of the
/// vertices of ws.schur_vertices, is factorised with their slip coordinates last, the friction
/// problem is solved on the Schur complement of those coordinates by Newton's method
/// (reweighted least squares until a slip settles), and one back substitution gives the
/// other velocities. Leaves Δv in ws.dv; outcome.seconds gets the time of the friction's own
/// work (ordering, Schur complement, dense Newton), outcome.iterations its dense iterations.
DynamicsReport solve_friction_schur(const ClothModel& model, const ClothState& state,
                                    std::span<const FrictionConstraint> friction,
                                    const FrictionSettings& settings, DynamicsWorkspace& ws,
                                    FrictionOutcome& outcome);

/// Friction of solve_velocities by Newton's method over the whole cloth, each iteration a
/// linear solve (reweighted-least-squares steps while the solves are loose or a slip still
/// turns), from ws.dv_iterate. The assembled system is in ws.blocks and ws.rhs (kept in
/// ws.base_blocks and ws.base_rhs), the constraints (squeezed normals too) in
/// ws.solve_constraints, the active friction constraints flagged in ws.active. Leaves Δv in
/// ws.dv; fills outcome.iterations, linear_solves, seconds.
DynamicsReport solve_friction_newton(const ClothModel& model, const ClothState& state,
                                     std::span<const FrictionConstraint> friction,
                                     const FrictionSettings& settings, DynamicsWorkspace& ws,
                                     FrictionOutcome& outcome);

/// First half of solve_velocities: sizes `ws` for `model` (first step only) and assembles the
/// implicit step's system A·Δv = b into ws.blocks and ws.rhs, with the constrained unknowns
/// eliminated. Exposed so that benchmarks can time assembly and solve separately.
void assemble_system(const ClothModel& model, const ClothState& state, double h,
                     const Vec3& gravity, std::span<const VelocityConstraint> constraints,
                     DynamicsWorkspace& ws);

/// Second half of solve_velocities: solves the assembled system into ws.dv (PCG warm-started
/// from the Δv already in ws.dv, or Cholesky, per model.solver), PCG to the larger of the model's
/// tolerance and `tolerance`. On failure ws.dv is zeroed.
DynamicsReport solve_system(const ClothModel& model,
                            std::span<const VelocityConstraint> constraints, DynamicsWorkspace& ws,
                            double tolerance = 0.0);

}  // namespace dexcloth::cloth
