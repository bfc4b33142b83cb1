/// Cost of the implicit cloth step (no collisions) on a sheet pinned at its two top corners under
/// gravity in its plane, at 33×33, 65×65 and 129×129 vertices (2k, 8k, 32k triangles):
///   BM_ClothStep      a whole step_dynamics (assembly + linear solve + position update),
///   BM_ClothAssembly  building A·Δv = b only (element Hessians, scatter, constraints),
///   BM_ClothSolve     the linear solve only, warm-started from the previous step's Δv, by the
///                     model's default (sparse Cholesky) and, with a third argument 1, by the
///                     block-Jacobi PCG (LinearSolver::pcg), with 2 by the Cholesky factor in
///                     single precision refined in double (SolverSettings::factor_precision;
///                     its counter pcg_iterations then counts the solves);
///   BM_ClothSubstitution  the forward and back substitution of that solve alone, through the
///                     factor of the step's matrix (a third argument 1: a single-precision
///                     factor);
///   BM_ClothFactorisation  the factorisation alone, a third argument 1 in single precision
///                     (counter solves: those the refined solve took);
///   BM_ClothSolveIncompleteCholesky  the same solve by conjugate gradient preconditioned with
///                     Eigen's incomplete Cholesky (AMD order, its default fill and shift),
///                     recomputed for each step's matrix (included), warm-started alike, to the
///                     PCG's tolerance: the issue-18 lever "PCG with incomplete Cholesky".
///   BM_ClothReanalysis  the analysis the Schur complement's friction path redoes whenever its
///                     set of friction vertices changes (93 times in pinch_move's 640 steps):
///                     the sheet's vertices in fill order, those of a k×k patch last, with the
///                     patch's last vertex alternately in the patch and out of it.
///   BM_ClothFriction  a step with Coulomb friction on a square patch of k×k vertices in the
///                     middle of the 65×65 sheet (a surface dragging it sideways; bounds from
///                     1/4 to 7/4 of what would stop each vertex, so some stick and some slide):
///                     arguments k and 1 for the Schur complement (friction_schur.cpp), 0 for
///                     Newton over the whole cloth (friction_newton.cpp). Counters:
///                     friction_ms (the friction's own time per step), newton (its iterations).
/// Arguments: vertices per side, SolverSettings::threads. Counters: PCG iterations per step,
/// triangles, vertices; for the direct solve the factorisation's MFLOP, the entries of L and the
/// share of the flops in the subtrees the threads share out. Run (Release):
///   build/bench/bench_cloth_dynamics
/// The sheet is first simulated for kSettleSteps steps so that the timed steps see a deformed,
/// moving sheet rather than the flat rest state.
#include <benchmark/benchmark.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <vector>

#include "cloth/dynamics.hpp"
#include "cloth/dynamics_workspace.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"
#include "cloth/state.hpp"

namespace {

using namespace dexcloth;

constexpr double kStep = 0.005;  // time step [s]
constexpr int kSettleSteps = 20;

/// A 1 m × 1 m sheet of n×n vertices in the x-y plane, pinned at its top corners, after
/// kSettleSteps steps under gravity along −y.
struct PinnedSheet {
  cloth::ClothModel model;
  cloth::ClothState state;
  std::vector<cloth::VelocityConstraint> pins;
  Vec3 gravity{0.0, -9.81, 0.0};

  PinnedSheet(int n, int threads) {
    const cloth::ClothMesh mesh = cloth::make_grid(1.0, 1.0, n, n);
    model = cloth::build_model(mesh, cloth::Material{});
    model.solver.threads = threads;
    state = cloth::make_state(model, mesh.x);
    pins = {{n * (n - 1), Vec3::Zero()}, {n * n - 1, Vec3::Zero()}};
    for (int k = 0; k < kSettleSteps; ++k) cloth::step_dynamics(model, state, kStep, gravity, pins);
  }
};

void set_size_counters(benchmark::State& bench, const cloth::ClothModel& model) {
  bench.counters["triangles"] = static_cast<double>(model.faces.rows());
  bench.counters["vertices"] = static_cast<double>(model.num_vertices());
}

void BM_ClothStep(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)));
  double iterations = 0.0;
  for (auto _ : bench) {
    const cloth::DynamicsReport r =
        cloth::step_dynamics(s.model, s.state, kStep, s.gravity, s.pins);
    if (!r.ok) bench.SkipWithError(r.message.c_str());
    iterations += r.iterations;
  }
  bench.counters["pcg_iterations"] =
      benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  set_size_counters(bench, s.model);
}

void BM_ClothAssembly(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)));
  cloth::DynamicsWorkspace& ws = s.state.scratch.get();
  for (auto _ : bench) {
    cloth::assemble_system(s.model, s.state, kStep, s.gravity, s.pins, ws);
    benchmark::DoNotOptimize(ws.rhs.data());
    benchmark::ClobberMemory();
  }
  set_size_counters(bench, s.model);
}

void BM_ClothSolve(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)));
  if (bench.range(2) == 1) s.model.solver.linear_solver = cloth::LinearSolver::pcg;
  if (bench.range(2) == 2) s.model.solver.factor_precision = cloth::Precision::single_precision;
  cloth::DynamicsWorkspace& ws = s.state.scratch.get();
  cloth::assemble_system(s.model, s.state, kStep, s.gravity, s.pins, ws);
  // Every solve starts from the same warm start: the previous step's Δv (copy included in time,
  // ~1 µs per 1k vertices).
  const Eigen::VectorXd warm_start = ws.dv;
  double iterations = 0.0;
  for (auto _ : bench) {
    ws.dv = warm_start;
    const cloth::DynamicsReport r = cloth::solve_system(s.model, s.pins, ws);
    if (!r.ok) bench.SkipWithError(r.message.c_str());
    iterations += r.iterations;
  }
  bench.counters["pcg_iterations"] =
      benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  if (s.model.solver.linear_solver == cloth::LinearSolver::cholesky) {
    const cloth::SparseCholesky& factor = ws.direct.cholesky;
    bench.counters["factor_mflop"] = factor.factor_flops() / 1e6;
    bench.counters["factor_nnz"] = static_cast<double>(factor.factor_nonzeros());
    bench.counters["parallel_share"] = factor.parallel_share();
  }
  set_size_counters(bench, s.model);
}

void BM_ClothFactorisation(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)));
  if (bench.range(2) == 1) s.model.solver.factor_precision = cloth::Precision::single_precision;
  cloth::DynamicsWorkspace& ws = s.state.scratch.get();
  cloth::assemble_system(s.model, s.state, kStep, s.gravity, s.pins, ws);
  const cloth::DynamicsReport r = cloth::solve_system(s.model, s.pins, ws);  // analyses
  if (!r.ok) bench.SkipWithError(r.message.c_str());
  for (auto _ : bench) {
    if (!cloth::factorise(ws.blocks, ws.direct).ok) bench.SkipWithError("pivot");
  }
  bench.counters["solves"] = r.iterations;
  set_size_counters(bench, s.model);
}

void BM_ClothSubstitution(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), static_cast<int>(bench.range(1)));
  if (bench.range(2) == 1) s.model.solver.factor_precision = cloth::Precision::single_precision;
  cloth::DynamicsWorkspace& ws = s.state.scratch.get();
  cloth::assemble_system(s.model, s.state, kStep, s.gravity, s.pins, ws);
  const cloth::DynamicsReport r = cloth::solve_system(s.model, s.pins, ws);  // factorises
  if (!r.ok) bench.SkipWithError(r.message.c_str());
  const cloth::SparseCholesky& factor = ws.direct.cholesky;
  std::vector<double> x(static_cast<std::size_t>(ws.rhs.size()));
  for (auto _ : bench) {
    std::copy(ws.rhs.begin(), ws.rhs.end(), x.begin());
    factor.solve_in_place(x);
    benchmark::DoNotOptimize(x.data());
  }
  bench.counters["factor_nnz"] = static_cast<double>(factor.factor_nonzeros());
  set_size_counters(bench, s.model);
}

void BM_ClothReanalysis(benchmark::State& bench) {
  const int n = static_cast<int>(bench.range(0)), k = 12;
  PinnedSheet s(n, static_cast<int>(bench.range(1)));
  std::vector<char> in_patch(static_cast<std::size_t>(n * n), 0);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j)
      in_patch[static_cast<std::size_t>((n - k) / 2 + i + n * ((n - k) / 2 + j))] = 1;
  const auto order = [&](bool last_in) {
    std::vector<int> dofs, tail;
    const int last = (n - k) / 2 + k - 1 + n * ((n - k) / 2 + k - 1);
    for (int v : s.model.pattern.fill_order) {
      const bool patch = in_patch[static_cast<std::size_t>(v)] && (last_in || v != last);
      for (int c = 0; c < 3; ++c) (patch ? tail : dofs).push_back(3 * v + c);
    }
    dofs.insert(dofs.end(), tail.begin(), tail.end());
    return dofs;
  };
  const std::vector<int> orders[2] = {order(true), order(false)};
  cloth::DirectSystem d;
  int which = 0;
  for (auto _ : bench) {
    cloth::analyse_unknowns(s.model.pattern, orders[which], s.model.solver.threads, d);
    which = 1 - which;
  }
  bench.counters["factor_nnz"] = static_cast<double>(d.cholesky.factor_nonzeros());
  set_size_counters(bench, s.model);
}

void BM_ClothFriction(benchmark::State& bench) {
  constexpr int n = 65;
  PinnedSheet s(n, 1);
  const int k = static_cast<int>(bench.range(0));
  const Vec3 surface_velocity(0.05, 0.0, 0.0);
  std::vector<cloth::FrictionConstraint> friction;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const int v = (n - k) / 2 + i + n * ((n - k) / 2 + j);
      const double share = 0.25 + 1.5 * static_cast<double>(i * k + j) / (k * k);
      const double stop = s.model.mass[v] * surface_velocity.norm();
      friction.push_back({v, Vec3::UnitZ(), surface_velocity, share * stop, false});
    }
  }
  cloth::FrictionSettings settings;
  settings.max_schur_vertices = bench.range(1) == 1 ? k * k : 0;
  cloth::FrictionOutcome outcome;
  double seconds = 0.0, iterations = 0.0;
  for (auto _ : bench) {
    const cloth::DynamicsReport r = cloth::solve_velocities(s.model, s.state, kStep, s.gravity,
                                                            s.pins, friction, outcome, settings);
    if (!r.ok) {
      bench.SkipWithError(r.message.c_str());
      return;
    }
    cloth::advance_positions(s.state, kStep);
    seconds += outcome.seconds;
    iterations += outcome.iterations;
  }
  bench.counters["friction_ms"] =
      benchmark::Counter(1e3 * seconds, benchmark::Counter::kAvgIterations);
  bench.counters["newton"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  bench.counters["friction_vertices"] = static_cast<double>(k * k);
}

/// The assembled system as an Eigen sparse matrix (both triangles).
Eigen::SparseMatrix<double> to_sparse(const cloth::SystemPattern& p,
                                      const std::vector<Mat3>& blocks) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(9 * blocks.size());
  for (int j = 0; j < p.num_vertices; ++j) {
    for (int b = p.col_start[static_cast<std::size_t>(j)];
         b < p.col_start[static_cast<std::size_t>(j) + 1]; ++b) {
      const int i = p.row[static_cast<std::size_t>(b)];
      const Mat3& a = blocks[static_cast<std::size_t>(b)];  // A(i, j)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) entries.emplace_back(3 * i + r, 3 * j + c, a(r, c));
    }
  }
  Eigen::SparseMatrix<double> a(3 * p.num_vertices, 3 * p.num_vertices);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

void BM_ClothSolveIncompleteCholesky(benchmark::State& bench) {
  PinnedSheet s(static_cast<int>(bench.range(0)), 1);
  cloth::DynamicsWorkspace& ws = s.state.scratch.get();
  cloth::assemble_system(s.model, s.state, kStep, s.gravity, s.pins, ws);
  const Eigen::SparseMatrix<double> a = to_sparse(s.model.pattern, ws.blocks);
  const Eigen::VectorXd warm_start = ws.dv;
  // The direct solve's answer, to check the iterative one against.
  cloth::solve_system(s.model, s.pins, ws);
  const Eigen::VectorXd exact = ws.dv;
  using Preconditioner = Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>>;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Preconditioner>
      cg;
  cg.setTolerance(s.model.solver.tolerance);
  cg.setMaxIterations(s.model.solver.max_iterations);
  double iterations = 0.0;
  Eigen::VectorXd dv;
  double compute_seconds = 0.0;
  for (auto _ : bench) {
    const auto start = std::chrono::steady_clock::now();
    cg.compute(a);
    compute_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    dv = cg.solveWithGuess(ws.rhs, warm_start);
    if (cg.info() != Eigen::Success) {
      bench.SkipWithError("incomplete-Cholesky CG did not converge");
      return;
    }
    iterations += static_cast<double>(cg.iterations());
  }
  bench.counters["pcg_iterations"] =
      benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  bench.counters["factor_ms"] =
      benchmark::Counter(1e3 * compute_seconds, benchmark::Counter::kAvgIterations);
  bench.counters["error_vs_direct"] = (dv - exact).norm() / exact.norm();
  set_size_counters(bench, s.model);
}

}  // namespace

/// 2k, 8k and 32k triangles, on one and on two threads.
void sizes(benchmark::internal::Benchmark* b) {
  for (const int threads : {1, 2}) {
    for (const int n : {33, 65, 129}) b->Args({n, threads});
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

/// The same, then the block-Jacobi PCG (third argument 1) on one thread.
void solve_sizes(benchmark::internal::Benchmark* b) {
  for (const int threads : {1, 2}) {
    for (const int n : {33, 65, 129}) b->Args({n, threads, 0});
    for (const int n : {33, 65, 129}) b->Args({n, threads, 2});
  }
  for (const int n : {33, 65, 129}) b->Args({n, 1, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_ClothStep)->Apply(sizes);
BENCHMARK(BM_ClothAssembly)->Apply(sizes);
BENCHMARK(BM_ClothSolve)->Apply(solve_sizes);
BENCHMARK(BM_ClothSubstitution)
    ->ArgsProduct({{33, 65, 129}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ClothFactorisation)
    ->ArgsProduct({{33, 65, 129}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ClothReanalysis)->Apply(sizes);
BENCHMARK(BM_ClothSolveIncompleteCholesky)
    ->Arg(33)
    ->Arg(65)
    ->Arg(129)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_ClothFriction)
    ->ArgsProduct({{8, 12, 17, 20}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
