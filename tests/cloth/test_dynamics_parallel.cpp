// The parallel solvers are deterministic: the same step gives bitwise the same velocities run to
// run and for any thread count (PCG: reductions are summed per fixed chunk, then in chunk order;
// Cholesky: each front is factorised by one thread, whichever).
#include <gtest/gtest.h>

#include <vector>

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
