// The parallel solvers are deterministic: the same step gives bitwise the same velocities run to
// run and for any thread count (PCG: reductions are summed per fixed chunk, then in chunk order;
// Cholesky: each front is factorised by one thread, whichever).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "cloth/block_pcg.hpp"
#include "cloth/dynamics.hpp"
#include "cloth/dynamics_workspace.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

namespace {

/// Velocities after 4 steps of a 40×40 sheet (large enough for the parallel path) pinned at two
/// corners, falling under gravity, with `solver` on SolverSettings::threads = `threads`.
Points velocities_after_steps(int threads, LinearSolver solver = LinearSolver::pcg) {
  const int n = 40;
  const ClothMesh mesh = make_grid(0.5, 0.5, n, n);
  ClothModel model = build_model(mesh, Material{});
  model.solver.linear_solver = solver;
  model.solver.threads = threads;
  ClothState state = make_state(model, mesh.x);
  const std::vector<VelocityConstraint> pins = {{n * (n - 1), Vec3::Zero()},
                                                {n * n - 1, Vec3::Zero()}};
  for (int k = 0; k < 4; ++k) {
    const DynamicsReport r = step_dynamics(model, state, 0.005, Vec3(0, 0, -9.81), pins);
    EXPECT_TRUE(r.ok) << r.message;
    if (solver == LinearSolver::pcg) {
      EXPECT_GT(r.iterations, 1);
    }
  }
  return state.v;
}

}  // namespace

TEST(DynamicsParallel, ResultsAreBitwiseIdenticalRunToRunAndAcrossThreadCounts) {
  const Points one = velocities_after_steps(1);
  ASSERT_GT(one.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(velocities_after_steps(2), one);
  EXPECT_EQ(velocities_after_steps(2), velocities_after_steps(2));
}

TEST(DynamicsParallel, CholeskyIsBitwiseIdenticalAcrossThreadCounts) {
  const Points one = velocities_after_steps(1, LinearSolver::cholesky);
  ASSERT_GT(one.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(velocities_after_steps(2, LinearSolver::cholesky), one);
  EXPECT_EQ(velocities_after_steps(3, LinearSolver::cholesky), one);
}

TEST(DynamicsParallel, TwoThreadsShareMostOfASheetsFactorisation) {
  // A 40×40 sheet in nested-dissection order: the two halves below the top separators are
  // factorised in parallel, most of the work.
  const ClothMesh mesh = make_grid(0.5, 0.5, 40, 40);
  const ClothModel model = build_model(mesh, Material{});
  DirectSystem d;
  analyse(model.pattern, model.pattern.fill_order, 2, d);
  EXPECT_GT(d.cholesky.parallel_share(), 0.5);
  analyse(model.pattern, model.pattern.fill_order, 1, d);
  EXPECT_EQ(d.cholesky.parallel_share(), 1.0);
}

namespace {

/// A 50×50 sheet, crumpled and moving, its vertices numbered at random so that most elements
/// span the assembly's pieces.
std::pair<ClothModel, ClothState> shuffled_moving_sheet() {
  const int n = 50;
  ClothMesh mesh = make_grid(0.5, 0.5, n, n);
  const auto nv = static_cast<int>(mesh.x.rows());
  std::vector<int> new_index(static_cast<std::size_t>(nv));
  for (int i = 0; i < nv; ++i) new_index[static_cast<std::size_t>(i)] = i;
  std::uint32_t seed = 7u;
  const auto next = [&] { return seed = seed * 1664525u + 1013904223u; };
  for (int i = nv - 1; i > 0; --i)
    std::swap(new_index[static_cast<std::size_t>(i)],
              new_index[static_cast<std::size_t>(next() % static_cast<std::uint32_t>(i + 1))]);
  Points x(nv, 3);
  for (int i = 0; i < nv; ++i) x.row(new_index[static_cast<std::size_t>(i)]) = mesh.x.row(i);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      mesh.faces(f, k) = new_index[static_cast<std::size_t>(mesh.faces(f, k))];
  mesh.x = x;
  ClothModel model = build_model(mesh, Material{});
  EXPECT_GE(model.faces.rows(), 2000);  // the size assembled in pieces
  ClothState state = make_state(model, mesh.x);
  for (int i = 0; i < nv; ++i) {
    const double s = static_cast<double>(i);
    state.x.row(i) += 2e-3 * Vec3(std::sin(s), std::cos(1.3 * s), std::sin(0.7 * s)).transpose();
    state.v.row(i) = Vec3(std::cos(s), 0.5 * std::sin(s), -1.0).transpose();
  }
  return {std::move(model), std::move(state)};
}

}  // namespace

TEST(DynamicsParallel, AssemblyIsBitwiseIdenticalInAnyPiecesOnAnyNumberOfThreads) {
  // Every block and right-hand side entry must sum the same terms in the same order whatever
  // the split into pieces and whichever threads assemble them.
  auto [model, state] = shuffled_moving_sheet();
  const std::vector<VelocityConstraint> pins = {{0, Vec3::Zero()}};
  const auto assembled = [&](int threads, int pieces) {
    model.solver.threads = threads;
    DynamicsWorkspace ws;
    if (pieces > 0) split_assembly(model, pieces, ws);  // else the default split
    assemble_system(model, state, 0.005, Vec3(0, 0, -9.81), pins, ws);
    return std::pair{ws.blocks, ws.rhs};
  };
  const auto [blocks, rhs] = assembled(1, 1);
  ASSERT_GT(rhs.cwiseAbs().maxCoeff(), 0.0);
  for (int threads : {1, 2, 3})
    for (int pieces : {0, 2, 3, 13}) {
      const auto [b, r] = assembled(threads, pieces);
      ASSERT_EQ(b.size(), blocks.size());
      for (std::size_t k = 0; k < b.size(); ++k)
        ASSERT_TRUE(b[k] == blocks[k])
            << "block " << k << ", " << pieces << " pieces on " << threads << " threads";
      EXPECT_TRUE(r == rhs) << pieces << " pieces on " << threads << " threads";
    }
}

TEST(DynamicsParallel, TheSystemProductOnAPoolIsBitwiseTheOneThreadProduct) {
  // The residual's product A·x runs on the solver's pool in chunks that threads take as they
  // come free; every row sums its blocks in the same order whichever thread takes it. Checked
  // against the one-thread product bitwise and against the dense matrix.
  auto [model, state] = shuffled_moving_sheet();
  DynamicsWorkspace ws;
  assemble_system(model, state, 0.005, Vec3(0, 0, -9.81), {}, ws);
  const int n = 3 * model.num_vertices();
  ASSERT_GE(model.num_vertices(), 512);  // large enough for the pool
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0).array().sin();
  Eigen::VectorXd serial(n), pooled(n);
  block_multiply(model.pattern, ws.blocks, x, serial, nullptr);
  for (int threads : {2, 3}) {
    WorkerPool pool(threads);
    pooled.setConstant(std::nan(""));
    block_multiply(model.pattern, ws.blocks, x, pooled, &pool);
    EXPECT_TRUE(pooled == serial) << threads << " threads";
  }
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  const SystemPattern& p = model.pattern;
  for (int j = 0; j < model.num_vertices(); ++j)
    for (int b = p.col_start[static_cast<std::size_t>(j)];
         b < p.col_start[static_cast<std::size_t>(j) + 1]; ++b)
      dense.block<3, 3>(3 * p.row[static_cast<std::size_t>(b)], 3 * j) =
          ws.blocks[static_cast<std::size_t>(b)];
  EXPECT_LE((dense * x - serial).norm(), 1e-12 * (dense * x).norm());
}

TEST(DynamicsParallel, ASolveUsesTheSystemAssembledAheadOnlyForItsInputs) {
  auto [model, state] = shuffled_moving_sheet();
  model.solver.linear_solver = LinearSolver::cholesky;
  model.solver.threads = 2;
  const double h = 0.005;
  const Vec3 g(0, 0, -9.81);
  const std::vector<VelocityConstraint> pins = {{0, Vec3::Zero()}};
  // v̄ of a fresh solve of `s` over `step`.
  const auto fresh = [&](const ClothState& s, double step) {
    ClothState copy = s;  // a copy starts with an empty workspace
    EXPECT_TRUE(solve_velocities(model, copy, step, g, pins).ok);
    return copy.v;
  };
  // v̄ of a solve after an assembly ahead of `s` whose pieces `skip` are left out, with the
  // assembled matrix then marked (a solve that uses it gives another v̄) unless `clean`, and
  // `change` applied to the state between the assembly and the solve.
  const auto ahead = [&](int skip, bool clean, const std::function<void(ClothState&)>& change) {
    ClothState s = state;
    const int pieces = begin_assembly(model, s, h, g);
    EXPECT_GT(pieces, 1);
    for (int k = pieces - 1; k >= 0; --k)  // any order
      if (k != skip) assemble_piece(model, s, k);
    if (!clean) s.scratch.get().blocks[model.pattern.diagonal[7]] *= 2.0;
    change(s);
    const ClothState before = s;
    EXPECT_TRUE(solve_velocities(model, s, h, g, pins).ok);
    return std::pair{s.v, fresh(before, h)};
  };
  const auto nothing = [](ClothState&) {};
  const Points reference = fresh(state, h);
  // Used when complete and the inputs hold: bitwise the fresh solve's v̄, and the marked matrix
  // shows it is the one solved.
  EXPECT_EQ(ahead(-1, true, nothing).first, reference);
  EXPECT_NE(ahead(-1, false, nothing).first, reference);
  // Not used with a piece missing, or after any input changed.
  EXPECT_EQ(ahead(3, false, nothing).first, reference);
  for (const auto& change : std::vector<std::function<void(ClothState&)>>{
           [](ClothState& s) { s.x(5, 2) += 1e-9; }, [](ClothState& s) { s.v(9, 0) = -s.v(9, 0); },
           [](ClothState& s) { s.f_ext(11, 1) = 1e-3; }}) {
    const auto [v, expected] = ahead(-1, false, change);
    EXPECT_EQ(v, expected);
    EXPECT_NE(v, reference);
  }
  // Not used for another time step.
  ClothState s = state;
  const int pieces = begin_assembly(model, s, h, g);
  for (int k = 0; k < pieces; ++k) assemble_piece(model, s, k);
  s.scratch.get().blocks[model.pattern.diagonal[7]] *= 2.0;
  ASSERT_TRUE(solve_velocities(model, s, 0.5 * h, g, pins).ok);
  EXPECT_EQ(s.v, fresh(state, 0.5 * h));
}
