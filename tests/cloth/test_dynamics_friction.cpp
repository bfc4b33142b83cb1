// Coulomb friction inside the implicit step (solve_velocities with FrictionConstraint): partial
// velocity constraints, the slide/stick threshold on an incline against g(sinθ − μcosθ), a
// pinched strip held iff the friction bound covers its weight, loose Newton steps, and the
// Schur-complement solve against the Newton iterations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "cloth/dynamics.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

namespace {

constexpr double kStep = 0.005;
constexpr double kG = 9.81;

/// A 5 cm × 30 cm strip of light cloth (3 × 16 vertices), to hang along −y.
constexpr int kStripNx = 3, kStripNy = 16;
ClothMesh strip_mesh() { return make_grid(0.05, 0.3, kStripNx, kStripNy); }
Material strip_material() {
  Material material;
  material.density = 0.15;
  material.youngs_modulus = 5e5;
  material.thickness = 1e-3;
  material.damping = 0.005;
  return material;
}

/// The strip's top two rows pinched by a still jaw (normal z), `total` [N·s] of friction bound
/// shared equally.
std::vector<FrictionConstraint> pinch_top_rows(double total) {
  std::vector<FrictionConstraint> friction;
  for (int j = kStripNy - 2; j < kStripNy; ++j)
    for (int i = 0; i < kStripNx; ++i)
      friction.push_back({j * kStripNx + i, Vec3::UnitZ(), Vec3::Zero(), total / (2.0 * kStripNx)});
  return friction;
}

/// A 6 × 6 sheet in the x–y plane on an incline of angle θ (gravity tilted), every vertex in
/// friction against a surface of normal z moving at `surface`, with bound μ·m·g·cosθ·h; after
/// `steps` solves (positions advanced between them) `state` and `outcome` are the last ones.
struct Incline {
  ClothModel model;
  ClothState state;
  FrictionOutcome outcome;
  bool ok{true};  ///< every solve succeeded
};
Incline slide_on_incline(LinearSolver solver, double mu, double theta, const Vec3& surface,
                         bool squeezed, int steps) {
  const ClothMesh mesh = make_grid(0.2, 0.2, 6, 6);
  Incline r{build_model(mesh, Material{}), {}, {}};
  r.model.solver.linear_solver = solver;
  r.model.solver.tolerance = 1e-10;
  r.state = make_state(r.model, mesh.x);
  std::vector<FrictionConstraint> friction;
  for (int i = 0; i < r.model.num_vertices(); ++i)
    friction.push_back(
        {i, Vec3::UnitZ(), surface, mu * r.model.mass[i] * kG * std::cos(theta) * kStep, squeezed});
  const Vec3 gravity(kG * std::sin(theta), 0.0, -kG * std::cos(theta));
  for (int s = 0; s < steps && r.ok; ++s) {
    r.ok = solve_velocities(r.model, r.state, kStep, gravity, {}, friction, r.outcome).ok;
    advance_positions(r.state, kStep);
  }
  return r;
}

/// Coulomb on the incline of tan θ = ratio·μ after `steps` steps, in the plane: every vertex
/// slides along x at steps·h·g(sinθ − μcosθ) when ratio > 1 and sticks otherwise, with no
/// motion along y.
void expect_coulomb_in_plane(const Incline& r, double ratio, double mu, double theta, int steps) {
  const double expected =
      ratio > 1.0 ? steps * kStep * kG * (std::sin(theta) - mu * std::cos(theta)) : 0.0;
  for (int i = 0; i < r.model.num_vertices(); ++i) {
    EXPECT_NEAR(r.state.v(i, 0), expected, 1e-9 + 1e-6 * expected) << ratio << " vertex " << i;
    EXPECT_NEAR(r.state.v(i, 1), 0.0, 1e-9);
    EXPECT_EQ(r.outcome.sticking[static_cast<std::size_t>(i)], ratio > 1.0 ? 0 : 1);
  }
}

}  // namespace

TEST(DynamicsFriction, PartialConstraintPrescribesOnlyTheTangentialVelocity) {
  const ClothMesh mesh = make_grid(0.2, 0.2, 5, 5);
  for (LinearSolver solver : {LinearSolver::pcg, LinearSolver::cholesky}) {
    ClothModel model = build_model(mesh, Material{});
    model.solver.linear_solver = solver;
    model.solver.tolerance = 1e-10;
    ClothState state = make_state(model, mesh.x);
    const Vec3 n = Vec3(1.0, 0.0, 1.0).normalized();
    const Vec3 target(0.1, -0.2, 0.3);
    const std::vector<VelocityConstraint> c = {{12, target, n}};
    ASSERT_TRUE(solve_velocities(model, state, kStep, Vec3(0, 0, -kG), c).ok);
    const Vec3 v = state.v.row(12).transpose();
    const Vec3 dt = (v - target) - n.dot(v - target) * n;  // tangential error
    EXPECT_LT(dt.norm(), 1e-12);
    // The free direction is solved, not prescribed: it differs from the target's component, and
    // the constraint's impulse has no component along it.
    EXPECT_GT(std::abs(n.dot(v - target)), 1e-3);
    const Vec3 J = state.constraint_impulse.row(12).transpose();
    EXPECT_LT(std::abs(J.dot(n)), 1e-8 * J.norm());
    EXPECT_GT(J.norm(), 0.0);
  }
}

TEST(DynamicsFriction, SheetOnAnInclineSticksIffTanThetaBelowMu) {
  // A sheet in the x–y plane with gravity tilted by θ: each vertex's friction bound is
  // μ·m·g·cosθ·h. Uniform motion loads no spring, so each step Δv_x = g(sinθ − μcosθ)h when
  // tanθ > μ, and 0 otherwise.
  const double mu = 0.4;
  const int steps = 20;
  for (double ratio : {0.8, 0.99, 1.01, 1.5}) {
    const double theta = std::atan(ratio * mu);
    for (LinearSolver solver : {LinearSolver::pcg, LinearSolver::cholesky}) {
      const Incline r = slide_on_incline(solver, mu, theta, Vec3::Zero(), false, steps);
      ASSERT_TRUE(r.ok);
      expect_coulomb_in_plane(r, ratio, mu, theta, steps);
      for (int i = 0; i < r.model.num_vertices(); ++i)
        EXPECT_NEAR(r.state.v(i, 2), -steps * kStep * kG * std::cos(theta), 1e-8);
      EXPECT_LE(r.outcome.iterations, 6);
    }
  }
}

TEST(DynamicsFriction, SqueezedVerticesMoveWithTheirSurfaceAlongTheNormal) {
  // The incline again, every vertex squeezed between surfaces rising at 2 cm/s along the normal:
  // the normal velocity is theirs exactly (gravity's normal part no longer shows), while the
  // tangential motion keeps Coulomb's threshold: stuck below tanθ = μ, sliding at
  // g(sinθ − μcosθ) above it.
  const double mu = 0.4, rise = 0.02;
  const int steps = 20;
  for (double ratio : {0.8, 1.5}) {
    const double theta = std::atan(ratio * mu);
    for (LinearSolver solver : {LinearSolver::pcg, LinearSolver::cholesky}) {
      const Incline r = slide_on_incline(solver, mu, theta, Vec3(0.0, 0.0, rise), true, steps);
      ASSERT_TRUE(r.ok);
      expect_coulomb_in_plane(r, ratio, mu, theta, steps);
      for (int i = 0; i < r.model.num_vertices(); ++i) EXPECT_NEAR(r.state.v(i, 2), rise, 1e-12);
    }
  }
}

TEST(DynamicsFriction, PinchedStripHeldIffTheBoundCoversItsWeight) {
  // A 5 cm × 30 cm strip hanging along −y, its top two rows pinched (normal z, a still jaw).
  // Σ bounds = factor·W·h. Held (factor 1.5): after the load settles on the pinch the pinched
  // vertices stop, all stick, and the friction impulses carry the weight. Dropped (factor 0.8):
  // they slide at about (1 − 0.8)·g.
  const ClothMesh mesh = strip_mesh();
  for (double factor : {1.5, 0.8}) {
    ClothModel model = build_model(mesh, strip_material());
    ClothState state = make_state(model, mesh.x);
    const double weight = model.mass.sum() * kG;
    const std::vector<FrictionConstraint> friction = pinch_top_rows(factor * weight * kStep);
    FrictionOutcome outcome;
    const auto pinched_mean_y = [&] {
      double y = 0.0;
      for (const FrictionConstraint& f : friction) y += state.x(f.vertex, 1);
      return y / static_cast<double>(friction.size());
    };
    const double y0 = pinched_mean_y();
    double y_settled = 0.0;
    for (int s = 0; s < 400; ++s) {
      ASSERT_TRUE(solve_velocities(model, state, kStep, Vec3(0, -kG, 0), {}, friction, outcome).ok);
      advance_positions(state, kStep);
      if (s == 199) y_settled = pinched_mean_y();
    }
    if (factor > 1.0) {
      // Micro-slip while the load moves up the pinch, then none over the last second.
      EXPECT_LT(y0 - y_settled, 1e-3);
      EXPECT_LT(std::abs(pinched_mean_y() - y_settled), 1e-6);
      Vec3 total = Vec3::Zero();
      for (std::size_t k = 0; k < friction.size(); ++k) {
        EXPECT_EQ(outcome.sticking[k], 1) << k;
        EXPECT_LE(outcome.impulse[k].norm(), friction[k].max_impulse * (1.0 + 1e-9));
        total += outcome.impulse[k];
      }
      EXPECT_NEAR(total.y(), weight * kStep, 1e-3 * weight * kStep);
    } else {
      // 2 s at (1 − 0.8)·g would be 3.9 m; the strip's stretch waves slow it a little.
      EXPECT_GT(y0 - pinched_mean_y(), 0.5 * 0.5 * 0.2 * kG * 4.0);
      for (std::size_t k = 0; k < friction.size(); ++k) EXPECT_EQ(outcome.sticking[k], 0);
    }
  }
}

TEST(DynamicsFriction, LooseNewtonStepsReachTheSameAnswer) {
  // Far from the answer the friction Newton steps solve loosely; the velocities reached must
  // be those of accurate steps throughout. A strip pinched at its top rows with a bound just
  // above its weight, swung sideways so its vertices change between sliding and sticking.
  const ClothMesh mesh = strip_mesh();
  const auto run = [&](double newton_tolerance, double stop) {
    ClothModel model = build_model(mesh, strip_material());
    model.solver.linear_solver = LinearSolver::pcg;  // the loose steps are PCG's
    model.solver.tolerance = 1e-9;
    ClothState state = make_state(model, mesh.x);
    const std::vector<FrictionConstraint> friction =
        pinch_top_rows(1.1 * model.mass.sum() * kG * kStep);
    FrictionSettings settings;
    settings.max_schur_vertices = 0;  // the Newton iterations, each a linear solve
    settings.newton_tolerance = newton_tolerance;
    settings.tolerance = stop;
    settings.max_iterations = 40;
    FrictionOutcome outcome;
    for (int s = 0; s < 100; ++s) {
      const Vec3 gravity(s < 50 ? 3.0 : -3.0, -kG, 0.0);
      EXPECT_TRUE(
          solve_velocities(model, state, kStep, gravity, {}, friction, outcome, settings).ok);
      advance_positions(state, kStep);
    }
    return state.x;
  };
  // Against Newton converged 100 times tighter, loose steps err no more than accurate ones.
  const Points reference = run(0.0, 0.01), accurate = run(0.0, 1.0), loose = run(1e-3, 1.0);
  const double accurate_error = (accurate - reference).cwiseAbs().maxCoeff();
  const double loose_error = (loose - reference).cwiseAbs().maxCoeff();
  EXPECT_LT(loose_error, 2.0 * accurate_error + 1e-9);
  EXPECT_GT(accurate.col(1).maxCoeff() - accurate.col(1).minCoeff(), 0.2);  // it hangs
}

namespace {

/// The strip solved directly, and friction settings for comparing the Schur complement (up to
/// `max_schur_vertices` friction vertices) with Newton iterations over the whole cloth, those
/// converged 100 times tighter than usual.
ClothModel direct_strip_model() {
  ClothModel model = build_model(strip_mesh(), strip_material());
  model.solver.linear_solver = LinearSolver::cholesky;
  return model;
}
FrictionSettings comparison_settings(int max_schur_vertices) {
  FrictionSettings settings;
  settings.max_schur_vertices = max_schur_vertices;
  settings.tolerance = 0.01;
  settings.max_iterations = 60;
  return settings;
}

}  // namespace

TEST(DynamicsFriction, SchurComplementAndNewtonIterationsReachTheSameStep) {
  // The two ways of solving the friction (on the friction vertices' Schur complement, or by
  // Newton iterations over the whole cloth) minimise the same objective, so they must give the
  // same velocities. The strip pinched at its top rows, bound just above its weight, swung
  // sideways so its vertices change between sliding and sticking, two of them squeezed, its
  // bottom corner led sideways by a handle. The Newton iterations are converged 100 times
  // tighter than usual.
  const ClothMesh mesh = strip_mesh();
  const auto run = [&](int max_schur_vertices) {
    const ClothModel model = direct_strip_model();
    ClothState state = make_state(model, mesh.x);
    std::vector<FrictionConstraint> friction = pinch_top_rows(1.1 * model.mass.sum() * kG * kStep);
    friction[0].squeezed = friction[1].squeezed = true;
    const std::vector<VelocityConstraint> handle = {{0, Vec3(0.02, 0.0, 0.0)}};
    const FrictionSettings settings = comparison_settings(max_schur_vertices);
    FrictionOutcome outcome;
    int stuck = 0, slid = 0, schur_solves = 0;
    for (int s = 0; s < 100; ++s) {
      const Vec3 gravity(s < 50 ? 3.0 : -3.0, -kG, 0.0);
      EXPECT_TRUE(
          solve_velocities(model, state, kStep, gravity, handle, friction, outcome, settings).ok);
      advance_positions(state, kStep);
      for (char c : outcome.sticking) {
        if (c) {
          ++stuck;
        } else {
          ++slid;
        }
      }
      schur_solves += outcome.linear_solves == 1 ? 1 : 0;
    }
    EXPECT_GT(stuck, 0);
    EXPECT_GT(slid, 0);
    if (max_schur_vertices > 0) {
      EXPECT_EQ(schur_solves, 100);  // one factorisation per step
    }
    return state.v;
  };
  const Points schur = run(200), newton = run(0);
  EXPECT_LT((schur - newton).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_GT(schur.cwiseAbs().maxCoeff(), 0.01);
}

TEST(DynamicsFriction, SchurComplementOfASinglePrecisionFactorRefinesToTheSameStep) {
  // The Schur complement's path with a float factor, each step's friction problem solved again
  // for the correction of its residual, against the double factor's: the strip of the test
  // above, its vertices sticking and sliding. A float factor alone leaves ~1e-6; one correction
  // reaches 1e-11 to 1e-14 but where the Newton iterations stop at their objective's rounding,
  // as with the double factor (up to 1.3e-8 in this run with OpenBLAS's Haswell kernels, 2.1e-8
  // with its SkylakeX ones: OPENBLAS_CORETYPE=SkylakeX).
  const ClothMesh mesh = strip_mesh();
  const auto run = [&](Precision precision, int& refined, int& reached,
                       double refine_tolerance = SolverSettings{}.refine_tolerance) {
    ClothModel model = direct_strip_model();
    model.solver.factor_precision = precision;
    model.solver.refine_tolerance = refine_tolerance;
    ClothState state = make_state(model, mesh.x);
    std::vector<FrictionConstraint> friction = pinch_top_rows(1.1 * model.mass.sum() * kG * kStep);
    friction[0].squeezed = friction[1].squeezed = true;
    const std::vector<VelocityConstraint> handle = {{0, Vec3(0.02, 0.0, 0.0)}};
    const FrictionSettings settings = comparison_settings(200);
    FrictionOutcome outcome;
    refined = reached = 0;
    for (int s = 0; s < 100; ++s) {
      const Vec3 gravity(s < 50 ? 3.0 : -3.0, -kG, 0.0);
      const DynamicsReport r =
          solve_velocities(model, state, kStep, gravity, handle, friction, outcome, settings);
      EXPECT_TRUE(r.ok) << r.message;
      EXPECT_LE(r.residual, std::max(5e-8, refine_tolerance));
      reached += r.residual <= model.solver.refine_tolerance ? 1 : 0;
      advance_positions(state, kStep);
      refined += outcome.linear_solves > 1 ? 1 : 0;
    }
    return state.v;
  };
  int refined_double = 0, refined_single = 0, reached_double = 0, reached_single = 0;
  const Points exact = run(Precision::double_precision, refined_double, reached_double);
  const Points single = run(Precision::single_precision, refined_single, reached_single);
  EXPECT_EQ(refined_double, 0);
  EXPECT_GT(refined_single, 90);
  EXPECT_GE(reached_single, 95);
  EXPECT_LT((exact - single).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(exact.cwiseAbs().maxCoeff(), 0.01);
  // Refined only to the 1e-5 pcg is accepted at (the demo scenes' solver.refine_tolerance): the
  // float factor's 6e-8 to 5e-6 need no round, and the velocities stay within 1e-8 m/s of the
  // double factor's (measured 5.9e-10).
  int refined_loose = 0, reached_loose = 0;
  const Points loose = run(Precision::single_precision, refined_loose, reached_loose, 1e-5);
  EXPECT_EQ(refined_loose, 0);
  EXPECT_EQ(reached_loose, 100);
  EXPECT_LT((exact - loose).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(DynamicsFriction, SchurComplementAndNewtonAgreeAcrossChangingContactsAndTwoPlanes) {
  // As above, with what contacts do to the Schur complement's unknowns: vertices with two
  // contact planes (their three coordinates all slip), one with a squeezed normal, and a contact
  // set that changes every few steps, so friction vertices come, go and come back.
  const ClothMesh mesh = strip_mesh();
  const auto run = [&](int max_schur_vertices) {
    const ClothModel model = direct_strip_model();
    ClothState state = make_state(model, mesh.x);
    const std::vector<FrictionConstraint> all = pinch_top_rows(1.1 * model.mass.sum() * kG * kStep);
    const Vec3 tilted = Vec3(0.0, std::sin(0.5), std::cos(0.5));
    const std::vector<VelocityConstraint> handle = {{0, Vec3(0.02, 0.0, 0.0)}};
    const FrictionSettings settings = comparison_settings(max_schur_vertices);
    FrictionOutcome outcome;
    int two_planes = 0;
    for (int s = 0; s < 90; ++s) {
      // Every tenth step a different third of the pinched vertices lets go.
      std::vector<FrictionConstraint> friction;
      for (std::size_t k = 0; k < all.size(); ++k)
        if (static_cast<int>(k % 3) != (s / 10) % 3) friction.push_back(all[k]);
      for (std::size_t k = 0; k < friction.size(); k += 4) {
        FrictionConstraint second = friction[k];
        second.normal = tilted;
        second.surface_velocity = Vec3(0.0, 0.0, 0.01);
        friction.push_back(second);
        ++two_planes;
      }
      friction[1].squeezed = true;  // (a squeezed vertex touches one plane only)
      const Vec3 gravity(s < 45 ? 3.0 : -3.0, -kG, 0.0);
      EXPECT_TRUE(
          solve_velocities(model, state, kStep, gravity, handle, friction, outcome, settings).ok);
      advance_positions(state, kStep);
    }
    EXPECT_GT(two_planes, 0);
    return state.v;
  };
  // Newton stops once no velocity changes by tolerance·ε = 1e-6 m/s; a tenth of that.
  const Points schur = run(200), newton = run(0);
  EXPECT_LT((schur - newton).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_GT(schur.cwiseAbs().maxCoeff(), 0.01);
}
