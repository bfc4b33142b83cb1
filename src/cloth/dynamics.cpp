#include "cloth/dynamics.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "cloth/bending.hpp"
#include "cloth/dynamics_workspace.hpp"
#include "cloth/stretching.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

/// Sizes the workspace for `model` (first step only).
void prepare(const ClothModel& model, DynamicsWorkspace& ws) {
  if (ws.num_vertices == model.num_vertices()) return;
  const int nv = model.num_vertices();
  ws = DynamicsWorkspace{};
  ws.num_vertices = nv;
  ws.blocks.assign(static_cast<std::size_t>(model.pattern.num_blocks()), Mat3::Zero());
  ws.rhs = Eigen::VectorXd::Zero(3 * nv);
  ws.dv = Eigen::VectorXd::Zero(3 * nv);
  ws.work = Eigen::VectorXd::Zero(3 * nv);
  ws.constrained.assign(static_cast<std::size_t>(nv), 0);
}

}  // namespace

void analyse(const SystemPattern& p, std::span<const int> order, int threads, DirectSystem& d,
             Precision precision) {
  const auto nv = static_cast<std::size_t>(p.num_vertices);
  DEXCLOTH_DEMAND(order.size() == nv);
  std::vector<int> dofs(3 * nv);
  for (std::size_t k = 0; k < nv; ++k)
    for (int c = 0; c < 3; ++c) dofs[3 * k + static_cast<std::size_t>(c)] = 3 * order[k] + c;
  analyse_unknowns(p, dofs, threads, d, precision);
  d.order.assign(order.begin(), order.end());
}

void analyse_unknowns(const SystemPattern& p, std::span<const int> dofs, int threads,
                      DirectSystem& d, Precision precision) {
  const int n = 3 * p.num_vertices;
  DEXCLOTH_DEMAND(dofs.size() == static_cast<std::size_t>(n));
  d.order.clear();
  d.dof.assign(dofs.begin(), dofs.end());
  // Groups: runs of a vertex's unknowns in increasing coordinate order (all three, or a
  // friction vertex's other coordinates and, later, its slip ones). Each group's vertex and
  // first coordinate, and each vertex's groups in order.
  std::vector<int> groups, group_vertex, group_coordinate;
  std::vector<std::array<int, 3>> vertex_groups(static_cast<std::size_t>(p.num_vertices),
                                                {-1, -1, -1});
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    const int u = dofs[static_cast<std::size_t>(k)];
    DEXCLOTH_DEMAND(u >= 0 && u < n && !seen[static_cast<std::size_t>(u)]);  // a permutation
    seen[static_cast<std::size_t>(u)] = 1;
    if (k > 0 && u == dofs[static_cast<std::size_t>(k) - 1] + 1 && u % 3 != 0) continue;
    std::array<int, 3>& own = vertex_groups[static_cast<std::size_t>(u / 3)];
    *std::find(own.begin(), own.end(), -1) = static_cast<int>(groups.size());
    groups.push_back(k);
    group_vertex.push_back(u / 3);
    group_coordinate.push_back(u % 3);
  }
  groups.push_back(n);
  // The blocks of group g (vertex j): for each block (i, j) of the pattern, one per group h ≤ g
  // of vertex i, its values at 9b + 3·(g's first coordinate) + (h's), columns 3 apart (Mat3 is
  // column-major).
  std::vector<int> block_start(1, 0), block_row, block_source;
  for (std::size_t g = 0; g + 1 < groups.size(); ++g) {
    const int j = group_vertex[g];
    for (int b = p.col_start[static_cast<std::size_t>(j)];
         b < p.col_start[static_cast<std::size_t>(j) + 1]; ++b) {
      for (const int h :
           vertex_groups[static_cast<std::size_t>(p.row[static_cast<std::size_t>(b)])]) {
        if (h < 0 || h > static_cast<int>(g)) continue;
        block_row.push_back(h);
        block_source.push_back(9 * b + 3 * group_coordinate[g] +
                               group_coordinate[static_cast<std::size_t>(h)]);
      }
    }
    block_start.push_back(static_cast<int>(block_row.size()));
  }
  d.cholesky.analyze_blocks(groups, block_start, block_row, block_source, 3, threads, precision);
}

WorkerPool* solver_pool(int threads, DynamicsWorkspace& ws) {
  return lent_or_own(ws.lent_pool, ws.pool, threads);
}

DynamicsReport factorise(const std::vector<Mat3>& blocks, DirectSystem& d, WorkerPool* pool) {
  DynamicsReport report;
  report.iterations = 1;
  d.cholesky.lend_pool(pool);
  const std::span<const double> base(blocks.data()->data(), 9 * blocks.size());
  if (const int col = d.cholesky.factorize(base); col >= 0) {
    report.ok = false;
    report.message = "Cholesky pivot not positive at unknown " +
                     std::to_string(d.dof[static_cast<std::size_t>(col)]) +
                     " (system not positive definite or not finite)";
  }
  return report;
}

namespace {

/// Adds c·H (element Hessian, n vertices) into the system blocks and h·(−g − (h + β)·H·v_e) into
/// the right-hand side, only the rows and blocks that `part` owns.
template <int N>
void scatter(const std::array<int, N * N>& block_of, const std::array<int, N>& verts,
             const Eigen::Matrix<double, 3 * N, 1>& grad,
             const Eigen::Matrix<double, 3 * N, 3 * N>& hess, const Points& v, double c_stiff,
             double c_rhs_force, double c_rhs_damp, const AssemblyPart& part,
             DynamicsWorkspace& ws) {
  Eigen::Matrix<double, 3 * N, 1> ve;
  for (int a = 0; a < N; ++a)
    ve.template segment<3>(3 * a) = v.row(verts[static_cast<std::size_t>(a)]).transpose();
  // H·v_e column by column from zero: bitwise what Eigen's matrix–vector kernel sums, without
  // its call (17 % of the assembly's stack samples).
  Eigen::Matrix<double, 3 * N, 1> hv = Eigen::Matrix<double, 3 * N, 1>::Zero();
  for (int j = 0; j < 3 * N; ++j) hv += hess.col(j) * ve(j);
  const Eigen::Matrix<double, 3 * N, 1> r = -c_rhs_force * grad - c_rhs_damp * hv;
  for (int a = 0; a < N; ++a) {
    const int i = verts[static_cast<std::size_t>(a)];
    if (i >= part.first_vertex && i < part.end_vertex)
      ws.rhs.template segment<3>(3 * i) += r.template segment<3>(3 * a);
    for (int b = 0; b < N; ++b) {
      const int k = block_of[static_cast<std::size_t>(N * a + b)];
      if (k >= part.first_block && k < part.end_block)
        ws.blocks[static_cast<std::size_t>(k)] += c_stiff * hess.template block<3, 3>(3 * a, 3 * b);
    }
  }
}

/// What an assembly reads: positions, velocities, external forces, h and gravity.
struct AssemblyView {
  const Points &x, &v, &f_ext;
  double h;
  const Vec3& gravity;
};

/// The assembly of A = M + (h² + hβ)K and b = h(f + f_ext + Mg − (h + β)Kv) (assemble) that
/// `part` owns. Each entry gets its terms in the serial assembly's order: faces, hinges, mass.
void assemble_part(const ClothModel& model, const AssemblyView& in, const AssemblyPart& part,
                   DynamicsWorkspace& ws) {
  const double h = in.h;
  const double beta = model.material.damping;
  const double c_stiff = h * h + h * beta;
  const double c_damp = h * (h + beta);
  std::fill(ws.blocks.begin() + part.first_block, ws.blocks.begin() + part.end_block, Mat3::Zero());
  ws.rhs.segment(3 * part.first_vertex, 3 * (part.end_vertex - part.first_vertex)).setZero();

  // Stretching, per face.
  Vec9 g9;
  Mat9 H9;
  for (int f : part.faces) {
    const std::array<int, 3> vs = {model.faces(f, 0), model.faces(f, 1), model.faces(f, 2)};
    stretch_gradient_hessian_psd(
        in.x.row(vs[0]).transpose(), in.x.row(vs[1]).transpose(), in.x.row(vs[2]).transpose(),
        model.Dm_inv[static_cast<std::size_t>(f)], model.rest_area[static_cast<std::size_t>(f)],
        model.stretch, g9, H9);
    scatter<3>(model.pattern.face_blocks[static_cast<std::size_t>(f)], vs, g9, H9, in.v, c_stiff, h,
               c_damp, part, ws);
  }

  // Bending, per hinge.
  Vec12 g12;
  Mat12 H12;
  if (model.bending_k > 0.0) {
    for (int e : part.hinges) {
      const Hinge& hg = model.hinges[static_cast<std::size_t>(e)];
      bending_gradient_hessian_psd(in.x.row(hg.v[0]).transpose(), in.x.row(hg.v[1]).transpose(),
                                   in.x.row(hg.v[2]).transpose(), in.x.row(hg.v[3]).transpose(),
                                   hg.rest_angle, hg.weight, model.bending_k, g12, H12);
      scatter<4>(model.pattern.hinge_blocks[static_cast<std::size_t>(e)], hg.v, g12, H12, in.v,
                 c_stiff, h, c_damp, part, ws);
    }
  }

  // Mass, gravity and external forces.
  for (int i = part.first_vertex; i < part.end_vertex; ++i) {
    const double m = model.mass[i];
    ws.blocks[static_cast<std::size_t>(model.pattern.diagonal[static_cast<std::size_t>(i)])]
        .diagonal()
        .array() += m;
    ws.rhs.segment<3>(3 * i) += h * (in.f_ext.row(i).transpose() + m * in.gravity);
  }
}

// Cloths with fewer faces are assembled in one piece (waking workers costs more); larger ones
// on several threads in kPiecesPerThread pieces a thread, which threads take as they come free
// (so that a thread busy with other work for a while, as the coupling's rigid step, holds up
// no other). Elements across two pieces are evaluated by both: more pieces cost more.
constexpr int kParallelAssemblyFaces = 2000;
constexpr int kPiecesPerThread = 2;

}  // namespace

void split_assembly(const ClothModel& model, int pieces, DynamicsWorkspace& ws) {
  DEXCLOTH_DEMAND(pieces >= 1 && pieces <= 64);
  const SystemPattern& p = model.pattern;
  const int nv = model.num_vertices();
  ws.assembly_parts.assign(static_cast<std::size_t>(pieces), AssemblyPart{});
  std::vector<int> part_of(static_cast<std::size_t>(nv));
  int v = 0;
  for (int t = 0; t < pieces; ++t) {
    AssemblyPart& part = ws.assembly_parts[static_cast<std::size_t>(t)];
    const auto blocks_before =
        static_cast<int>(static_cast<long long>(p.num_blocks()) * (t + 1) / pieces);
    part.first_vertex = v;
    while (v < nv && (t + 1 == pieces || p.col_start[static_cast<std::size_t>(v)] < blocks_before))
      part_of[static_cast<std::size_t>(v++)] = t;
    part.end_vertex = v;
    part.first_block = p.col_start[static_cast<std::size_t>(part.first_vertex)];
    part.end_block = p.col_start[static_cast<std::size_t>(part.end_vertex)];
  }
  // Each element goes to every part owning one of its vertices, in element order.
  const auto add = [&](std::vector<int> AssemblyPart::*list, int element,
                       std::span<const int> verts) {
    std::uint64_t parts = 0;  // bit t: part t owns a vertex (pieces ≤ 64)
    for (int i : verts) parts |= std::uint64_t{1} << part_of[static_cast<std::size_t>(i)];
    for (int t = 0; t < pieces; ++t)
      if (parts & (std::uint64_t{1} << t))
        (ws.assembly_parts[static_cast<std::size_t>(t)].*list).push_back(element);
  };
  for (int f = 0; f < model.faces.rows(); ++f) {
    const std::array<int, 3> vs = {model.faces(f, 0), model.faces(f, 1), model.faces(f, 2)};
    add(&AssemblyPart::faces, f, vs);
  }
  for (std::size_t e = 0; e < model.hinges.size(); ++e)
    add(&AssemblyPart::hinges, static_cast<int>(e), model.hinges[e].v);
}

namespace {

/// Splits the assembly into its pieces unless split already; returns their number.
int assembly_pieces(const ClothModel& model, DynamicsWorkspace& ws) {
  if (ws.assembly_parts.empty())
    split_assembly(model,
                   model.faces.rows() >= kParallelAssemblyFaces && model.solver.threads > 1
                       ? std::min(64, kPiecesPerThread * model.solver.threads)
                       : 1,
                   ws);
  return static_cast<int>(ws.assembly_parts.size());
}

/// Keeps the inputs of an assembly of `state` (bitwise copies).
void keep_inputs(const ClothState& state, double h, const Vec3& gravity, AssemblyInputs& in) {
  in.x = state.x;
  in.v = state.v;
  in.f_ext = state.f_ext;
  in.h = h;
  in.gravity = gravity;
}

bool same_bits(const Points& a, const Points& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

/// Whether `in` holds bitwise the inputs `state`, h and gravity.
bool same_inputs(const AssemblyInputs& in, const ClothState& state, double h, const Vec3& gravity) {
  return same_bits(in.x, state.x) && same_bits(in.v, state.v) && same_bits(in.f_ext, state.f_ext) &&
         std::memcmp(&in.h, &h, sizeof h) == 0 &&
         std::memcmp(in.gravity.data(), gravity.data(), sizeof(double) * 3) == 0;
}

/// Assembles A = M + (h² + hβ)K and b = h(f + f_ext + Mg − (h + β)Kv) into the workspace, its
/// pieces on the model's threads for a large cloth, unless an assembly ahead (begin_assembly) of
/// bitwise these inputs is complete. Every entry sums the same terms in the same order however
/// the pieces are run, so the system is bitwise the same.
void assemble(const ClothModel& model, const ClothState& state, double h, const Vec3& gravity,
              DynamicsWorkspace& ws) {
  const bool ahead =
      std::find(ws.piece_done.begin(), ws.piece_done.end(), 0) == ws.piece_done.end() &&
      !ws.piece_done.empty() && same_inputs(ws.assembly_inputs, state, h, gravity);
  ws.piece_done.clear();  // an assembly ahead serves one solve
  if (ahead) return;
  const int pieces = assembly_pieces(model, ws);
  const AssemblyView in{state.x, state.v, state.f_ext, h, gravity};
  for_each_index(solver_pool(pieces > 1 ? model.solver.threads : 1, ws),
                 static_cast<std::size_t>(pieces),
                 [&](std::size_t k) { assemble_part(model, in, ws.assembly_parts[k], ws); });
}

}  // namespace

/// The projector S onto a constraint's free directions: n·nᵀ for a free direction n, I − d·dᵀ
/// for a fixed direction d, else 0.
Mat3 free_projector(const VelocityConstraint& c) {
  if (c.fixed_direction.squaredNorm() > 0.0)
    return Mat3::Identity() - c.fixed_direction * c.fixed_direction.transpose();
  return c.free_direction.squaredNorm() > 0.0
             ? Mat3(c.free_direction * c.free_direction.transpose())
             : Mat3(Mat3::Zero());
}

/// Eliminates the constrained unknowns. With S_i the projector onto vertex i's free directions
/// and z_i = (I − S_i)(v*_i − v_i) its prescribed change, Δv_i = z_i + S_i·y_i: A·z moves to the
/// right-hand side, row and column i are projected by S_i and the constrained directions get
/// M_i·(I − S_i)·Δv_i = M_i·z_i, so the system stays SPD and its pattern never changes.
void eliminate_constraints(const ClothModel& model, const ClothState& state,
                           std::span<const VelocityConstraint> constraints, DynamicsWorkspace& ws) {
  const SystemPattern& p = model.pattern;
  std::fill(ws.constrained.begin(), ws.constrained.end(), 0);
  // Keep the constrained rows as assembled, before any of them is eliminated, so the impulse each
  // constraint applies can be recovered after the solve (constraint_impulses).
  ws.saved_rows.clear();
  ws.saved_rhs.clear();
  for (const VelocityConstraint& c : constraints) {
    const auto i = static_cast<std::size_t>(c.vertex);
    for (int b = p.col_start[i]; b < p.col_start[i + 1]; ++b)
      ws.saved_rows.push_back(
          ws.blocks[static_cast<std::size_t>(p.transpose[static_cast<std::size_t>(b)])]);
    ws.saved_rhs.push_back(ws.rhs.segment<3>(3 * c.vertex));
  }
  for (const VelocityConstraint& c : constraints) {
    const int i = c.vertex;
    const Mat3 S = free_projector(c);
    const Mat3 fixed = Mat3::Identity() - S;
    const Vec3 z = fixed * (c.velocity - state.v.row(i).transpose());
    const auto diag = static_cast<std::size_t>(p.diagonal[static_cast<std::size_t>(i)]);
    for (int b = p.col_start[static_cast<std::size_t>(i)];
         b < p.col_start[static_cast<std::size_t>(i) + 1]; ++b) {
      const int j = p.row[static_cast<std::size_t>(b)];
      if (j == i) continue;
      Mat3& A_ji = ws.blocks[static_cast<std::size_t>(b)];
      Mat3& A_ij = ws.blocks[static_cast<std::size_t>(p.transpose[static_cast<std::size_t>(b)])];
      ws.rhs.segment<3>(3 * j) -= A_ji * z;
      A_ji = (A_ji * S).eval();
      A_ij = (S * A_ij).eval();
    }
    const double m = model.mass[i];
    Mat3& A_ii = ws.blocks[diag];
    const Vec3 rhs_i = ws.rhs.segment<3>(3 * i) - A_ii * z;
    ws.rhs.segment<3>(3 * i) = S * rhs_i + m * z;
    A_ii = S * A_ii * S + m * fixed;
    ws.constrained[static_cast<std::size_t>(i)] = 1;
  }
}

namespace {

/// Fills `impulses` (|V|×3, zero for free vertices) with the impulse [N·s] each velocity
/// constraint applied over the step: the residual A_i·Δv − b_i of its row as assembled.
void constraint_impulses(const ClothModel& model, std::span<const VelocityConstraint> constraints,
                         const DynamicsWorkspace& ws, Points& impulses) {
  const SystemPattern& p = model.pattern;
  impulses.setZero(model.num_vertices(), 3);
  std::size_t row = 0;
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const auto i = static_cast<std::size_t>(constraints[k].vertex);
    Vec3 J = -ws.saved_rhs[k];
    for (int b = p.col_start[i]; b < p.col_start[i + 1]; ++b) {
      const int j = p.row[static_cast<std::size_t>(b)];
      J += ws.saved_rows[row++] * ws.dv.segment<3>(3 * j);
    }
    impulses.row(static_cast<Eigen::Index>(i)) = J.transpose();
  }
}

/// Direct solve into ws.dv; returns the report.
DynamicsReport solve_direct(const ClothModel& model, DynamicsWorkspace& ws) {
  DirectSystem& d = ws.direct;
  const SolverSettings& solver = model.solver;
  if (d.order.empty() || d.cholesky.precision() != solver.factor_precision)
    analyse(model.pattern, model.pattern.fill_order, solver.threads, d, solver.factor_precision);
  DynamicsReport report = factorise(ws.blocks, d, solver_pool(solver.threads, ws));
  if (!report.ok) return report;
  // Solve in the permuted order.
  const auto n = static_cast<std::size_t>(ws.rhs.size());
  for (std::size_t k = 0; k < n; ++k) ws.work[static_cast<Eigen::Index>(k)] = ws.rhs[d.dof[k]];
  d.cholesky.solve_in_place(std::span<double>(ws.work.data(), n));
  for (std::size_t k = 0; k < n; ++k) ws.dv[d.dof[k]] = ws.work[static_cast<Eigen::Index>(k)];
  return report;
}

/// Relative residual ‖A·Δv − b‖/‖b‖ of the solution in ws.dv, its product on the solver's pool
/// (OpenMP's workers would spin after it, 7.8 % of a two-thread pinch_move run, beside the
/// factorisation's and the collision searches' threads).
double direct_residual(const ClothModel& model, DynamicsWorkspace& ws) {
  block_multiply(model.pattern, ws.blocks, ws.dv, ws.work, solver_pool(model.solver.threads, ws));
  ws.work -= ws.rhs;
  const double b_norm = ws.rhs.norm();
  return ws.work.norm() / (b_norm > 0.0 ? b_norm : 1.0);
}

/// Iterative refinement of ws.dv in double (a single-precision factor's solve): Δv += A⁻¹·r
/// through the factor, r = b − A·Δv, until the relative residual is below the settings'
/// refine_tolerance or stalls. Returns the residual reached; counts the extra solves in
/// `rounds`.
double refine_direct(const ClothModel& model, DynamicsWorkspace& ws, double residual, int& rounds) {
  const SolverSettings& solver = model.solver;
  const DirectSystem& d = ws.direct;
  const auto n = static_cast<std::size_t>(ws.rhs.size());
  ws.correction.resize(ws.rhs.size());
  for (rounds = 0; residual > solver.refine_tolerance && rounds < solver.max_refinements;
       ++rounds) {
    for (std::size_t k = 0; k < n; ++k)
      ws.correction[static_cast<Eigen::Index>(k)] = -ws.work[d.dof[k]];
    d.cholesky.solve_in_place(std::span<double>(ws.correction.data(), n));
    for (std::size_t k = 0; k < n; ++k)
      ws.dv[d.dof[k]] += ws.correction[static_cast<Eigen::Index>(k)];
    const double last = residual;
    residual = direct_residual(model, ws);
    if (residual > last) {  // rounding: keep the better one
      for (std::size_t k = 0; k < n; ++k)
        ws.dv[d.dof[k]] -= ws.correction[static_cast<Eigen::Index>(k)];
      residual = last;
    }
    if (residual > last / kRefinementGain) break;
  }
  return residual;
}

/// solve_direct and its relative residual, refined when the factor is in single precision
/// (the report's iterations count the solves).
DynamicsReport solve_direct_refined(const ClothModel& model, DynamicsWorkspace& ws) {
  DynamicsReport report = solve_direct(model, ws);
  if (!report.ok) return report;
  report.residual = direct_residual(model, ws);
  if (model.solver.factor_precision == Precision::single_precision) {
    int rounds = 0;
    report.residual = refine_direct(model, ws, report.residual, rounds);
    report.iterations += rounds;
  }
  return report;
}

/// v̄ = v + Δv; constrained vertices take their prescribed velocity exactly in their constrained
/// directions.
void take_velocities(const ClothModel& model, std::span<const VelocityConstraint> constraints,
                     const DynamicsWorkspace& ws, ClothState& state) {
  state.v += Points::Map(ws.dv.data(), model.num_vertices(), 3);
  for (const VelocityConstraint& c : constraints) {
    const Mat3 S = free_projector(c);
    const Vec3 v = S * state.v.row(c.vertex).transpose() + (Mat3::Identity() - S) * c.velocity;
    state.v.row(c.vertex) = v.transpose();
  }
}

/// Checks the inputs every solve_velocities takes (programmer errors, always on).
void demand_inputs(const ClothModel& model, const ClothState& state, double h,
                   std::span<const VelocityConstraint> constraints) {
  const int nv = model.num_vertices();
  DEXCLOTH_DEMAND(h > 0.0);
  DEXCLOTH_DEMAND(model.solver.threads >= 1);
  DEXCLOTH_DEMAND(state.x.rows() == nv && state.v.rows() == nv && state.f_ext.rows() == nv);
  for (const VelocityConstraint& c : constraints)
    DEXCLOTH_DEMAND(
        c.vertex >= 0 && c.vertex < nv &&
        (c.free_direction.squaredNorm() == 0.0 || c.fixed_direction.squaredNorm() == 0.0));
}

/// Flags the active friction constraints (ws.active) and keeps their vertices among the
/// vertices ordered last for the Schur complement (ws.schur_vertices, ws.schur_slot); returns
/// how many distinct vertices have friction. The set changing means a new analysis of the
/// factorisation, so vertices that lose their friction stay in it, as plain unknowns of the
/// dense problem, until it holds twice the friction vertices (then it restarts from them).
int schur_vertices(std::span<const FrictionConstraint> friction, DynamicsWorkspace& ws) {
  const std::size_t nv = ws.held.size();
  if (ws.schur_slot.size() != nv) {
    ws.schur_slot.assign(nv, -1);
    ws.schur_vertices.clear();
  }
  ws.active.assign(friction.size(), 0);
  ws.schur_mark.assign(nv, 0);
  int count = 0;
  for (std::size_t k = 0; k < friction.size(); ++k) {
    const auto v = static_cast<std::size_t>(friction[k].vertex);
    if (ws.held[v]) continue;
    ws.active[k] = 1;
    if (!ws.schur_mark[v]) ++count;
    ws.schur_mark[v] = 1;
  }
  if (static_cast<int>(ws.schur_vertices.size()) > 2 * count + 8) {
    for (int v : ws.schur_vertices) {
      ws.schur_slot[static_cast<std::size_t>(v)] = -1;
      if (!ws.schur_count.empty()) ws.schur_count[static_cast<std::size_t>(v)] = 0;
    }
    ws.schur_vertices.clear();
  }
  for (std::size_t k = 0; k < friction.size(); ++k) {
    int& slot = ws.schur_slot[static_cast<std::size_t>(friction[k].vertex)];
    if (!ws.active[k] || slot >= 0) continue;
    slot = static_cast<int>(ws.schur_vertices.size());
    ws.schur_vertices.push_back(friction[k].vertex);
  }
  return count;
}

}  // namespace

Vec3 friction_gradient(const Vec3& w, double bound, double eps) {
  const double s = w.norm();
  return s < eps ? Vec3(bound / eps * w) : Vec3(bound / s * w);
}

void assemble_system(const ClothModel& model, const ClothState& state, double h,
                     const Vec3& gravity, std::span<const VelocityConstraint> constraints,
                     DynamicsWorkspace& ws) {
  prepare(model, ws);
  assemble(model, state, h, gravity, ws);
  eliminate_constraints(model, state, constraints, ws);
}

int begin_assembly(const ClothModel& model, ClothState& state, double h, const Vec3& gravity) {
  DynamicsWorkspace& ws = state.scratch.get();
  prepare(model, ws);
  const int pieces = assembly_pieces(model, ws);
  keep_inputs(state, h, gravity, ws.assembly_inputs);
  ws.piece_done.assign(static_cast<std::size_t>(pieces), 0);
  return pieces;
}

void lend_solver_pool(ClothState& state, WorkerPool* pool) {
  DynamicsWorkspace& ws = state.scratch.get();
  ws.lent_pool = pool;
  // The factors take their pool from each factorisation (factorise): none keeps one lent before.
  ws.direct.cholesky.lend_pool(nullptr);
  ws.schur.cholesky.lend_pool(nullptr);
}

void assemble_piece(const ClothModel& model, ClothState& state, int k) {
  DynamicsWorkspace& ws = state.scratch.get();
  DEXCLOTH_DEMAND(k >= 0 && static_cast<std::size_t>(k) < ws.piece_done.size());
  const AssemblyInputs& kept = ws.assembly_inputs;
  const AssemblyView in{kept.x, kept.v, kept.f_ext, kept.h, kept.gravity};
  assemble_part(model, in, ws.assembly_parts[static_cast<std::size_t>(k)], ws);
  ws.piece_done[static_cast<std::size_t>(k)] = 1;
}

DynamicsReport solve_system(const ClothModel& model,
                            std::span<const VelocityConstraint> constraints, DynamicsWorkspace& ws,
                            double tolerance) {
  DynamicsReport report;
  SolverSettings settings = model.solver;
  settings.tolerance = std::max(settings.tolerance, tolerance);
  if (settings.linear_solver == LinearSolver::cholesky) {
    report = solve_direct_refined(model, ws);
    if (!report.ok) return report;
  } else {
    if (!ws.pcg_ready) {
      ws.pcg.resize(model.num_vertices());
      ws.pcg_ready = true;
    }
    // Warm start from the last Δv, with the constrained unknowns at their known values.
    for (const VelocityConstraint& c : constraints) {
      const Mat3 S = free_projector(c);
      ws.dv.segment<3>(3 * c.vertex) =
          S * ws.dv.segment<3>(3 * c.vertex) +
          (Mat3::Identity() - S) * ws.rhs.segment<3>(3 * c.vertex) / model.mass[c.vertex];
    }
    const PcgResult r = ws.pcg.solve(model.pattern, ws.blocks, ws.rhs, ws.dv, settings.tolerance,
                                     settings.max_iterations, settings.threads);
    report.iterations = r.iterations;
    report.residual = r.residual;
    if (!r.converged) {
      // Fall back to the direct solver for this step.
      const std::string why = "PCG did not converge (relative residual " +
                              std::to_string(r.residual) + " after " +
                              std::to_string(r.iterations) + " iterations)";
      report = solve_direct_refined(model, ws);
      if (!report.ok) {
        report.message = why + "; " + report.message;
        ws.dv.setZero();
        return report;
      }
      report.iterations += r.iterations;
      report.message = why + "; solved with Cholesky";
    }
  }
  if (!ws.dv.allFinite() || !(report.residual <= std::max(settings.tolerance, 1e-6))) {
    report.ok = false;
    report.message =
        "linear solve produced a non-finite or inaccurate velocity (relative residual " +
        std::to_string(report.residual) + ")";
    ws.dv.setZero();
  }
  return report;
}

DynamicsReport solve_velocities(const ClothModel& model, ClothState& state, double h,
                                const Vec3& gravity,
                                std::span<const VelocityConstraint> constraints) {
  demand_inputs(model, state, h, constraints);

  // Assemble A·Δv = b, then solve it.
  DynamicsWorkspace& ws = state.scratch.get();
  assemble_system(model, state, h, gravity, constraints, ws);
  const DynamicsReport report = solve_system(model, constraints, ws);
  if (!report.ok) return report;

  // Impulse J_i = A_i·Δv − b_i each constraint applied (its unsatisfied row of the system).
  constraint_impulses(model, constraints, ws, state.constraint_impulse);
  // v̄ = v + Δv; constrained vertices take their velocity exactly.
  take_velocities(model, constraints, ws, state);
  return report;
}

DynamicsReport solve_velocities(const ClothModel& model, ClothState& state, double h,
                                const Vec3& gravity,
                                std::span<const VelocityConstraint> constraints,
                                std::span<const FrictionConstraint> friction,
                                FrictionOutcome& outcome, const FrictionSettings& settings) {
  const int nv = model.num_vertices();
  demand_inputs(model, state, h, constraints);
  DEXCLOTH_DEMAND(settings.stick_velocity > 0.0 && settings.max_iterations >= 1);
  for (const FrictionConstraint& f : friction)
    DEXCLOTH_DEMAND(f.vertex >= 0 && f.vertex < nv && f.max_impulse >= 0.0 &&
                    std::abs(f.normal.norm() - 1.0) < 1e-6);

  DynamicsWorkspace& ws = state.scratch.get();
  prepare(model, ws);
  assemble(model, state, h, gravity, ws);
  // Vertices held by `constraints` keep those, without friction.
  ws.held.assign(static_cast<std::size_t>(nv), 0);
  for (const VelocityConstraint& c : constraints) ws.held[static_cast<std::size_t>(c.vertex)] = 1;
  // A squeezed vertex moves with its surfaces along their normal: every plane it touches is that
  // one (the Schur complement's slip coordinates leave its normal to the elimination).
  ws.squeezed_normal.resize(static_cast<std::size_t>(nv), Vec3::Zero());  // zero between solves
  for (const FrictionConstraint& f : friction)
    if (f.squeezed) ws.squeezed_normal[static_cast<std::size_t>(f.vertex)] = f.normal;
  for (const FrictionConstraint& f : friction) {
    const Vec3& n = ws.squeezed_normal[static_cast<std::size_t>(f.vertex)];
    DEXCLOTH_DEMAND(n.squaredNorm() == 0.0 || n.cross(f.normal).norm() < 1e-6);
  }
  for (const FrictionConstraint& f : friction)
    ws.squeezed_normal[static_cast<std::size_t>(f.vertex)] = Vec3::Zero();
  const std::size_t nf = friction.size();
  const double eps = settings.stick_velocity;
  const auto active = [&](std::size_t k) {
    return !ws.held[static_cast<std::size_t>(friction[k].vertex)];
  };
  // Squeezed vertices' normal velocities join the constraints (after `constraints`, whose
  // impulses are read back in order).
  ws.solve_constraints.assign(constraints.begin(), constraints.end());
  for (std::size_t k = 0; k < nf; ++k)
    if (friction[k].squeezed && active(k))
      ws.solve_constraints.push_back(
          {friction[k].vertex, friction[k].surface_velocity, Vec3::Zero(), friction[k].normal});
  // Relative tangential velocity of friction vertex k at the velocity change `dv`.
  const auto slip = [&](std::size_t k, const Eigen::VectorXd& dv) {
    return tangential_slip(friction[k], state, dv);
  };

  // Newton iterations from the last step's Δv (a warm start for the linear solves too; a vertex
  // that stuck starts stuck when its motion repeats).
  ws.dv_iterate = ws.dv;
  for (const VelocityConstraint& c : ws.solve_constraints) {  // start feasible
    const Mat3 S = free_projector(c);
    ws.dv_iterate.segment<3>(3 * c.vertex) =
        S * ws.dv_iterate.segment<3>(3 * c.vertex) +
        (Mat3::Identity() - S) * (c.velocity - state.v.row(c.vertex).transpose());
  }
  DynamicsReport report;
  outcome.iterations = 0;
  outcome.seconds = 0.0;
  const int friction_vertices = schur_vertices(friction, ws);
  // Few friction vertices: their Schur complement; else Newton iterations over the cloth.
  report = friction_vertices > 0 && friction_vertices <= settings.max_schur_vertices
               ? solve_friction_schur(model, state, friction, settings, ws, outcome)
               : solve_friction_newton(model, state, friction, settings, ws, outcome);
  if (!report.ok) return report;

  // Outcome: sticking vertices move with their surface (the smoothing's creep below ε removed),
  // friction impulses −B·φ'(s)·ŵ.
  outcome.sticking.assign(nf, 0);
  outcome.impulse.assign(nf, Vec3::Zero());
  ws.all_constraints.assign(constraints.begin(), constraints.end());
  constraint_impulses(model, constraints, ws, state.constraint_impulse);
  for (std::size_t k = 0; k < nf; ++k) {
    if (!active(k)) continue;
    const FrictionConstraint& f = friction[k];
    const Vec3 w = slip(k, ws.dv);
    outcome.impulse[k] = -friction_gradient(w, f.max_impulse, eps);
    outcome.sticking[k] = w.norm() < eps ? 1 : 0;
    if (outcome.sticking[k])
      ws.all_constraints.push_back(
          {f.vertex, f.surface_velocity, f.squeezed ? Vec3::Zero() : f.normal, Vec3::Zero()});
    else if (f.squeezed)
      ws.all_constraints.push_back({f.vertex, f.surface_velocity, Vec3::Zero(), f.normal});
    state.constraint_impulse.row(f.vertex) = outcome.impulse[k].transpose();
  }
  take_velocities(model, ws.all_constraints, ws, state);
  return report;
}

void advance_positions(ClothState& state, double h) { state.x += h * state.v; }

DynamicsReport step_dynamics(const ClothModel& model, ClothState& state, double h,
                             const Vec3& gravity, std::span<const VelocityConstraint> constraints) {
  DynamicsReport report = solve_velocities(model, state, h, gravity, constraints);
  if (report.ok) advance_positions(state, h);
  return report;
}

}  // namespace dexcloth::cloth
