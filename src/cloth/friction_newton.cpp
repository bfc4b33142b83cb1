// Friction in the implicit step by Newton's method over the whole cloth: each iteration one
// linear solve of the cloth's system with the friction linearised at the iterate. Used when the
// friction vertices are too many for their Schur complement (friction_schur.cpp).
#include <algorithm>
#include <chrono>

#include "cloth/block_pcg.hpp"
#include "cloth/dynamics_workspace.hpp"

namespace dexcloth::cloth {

DynamicsReport solve_friction_newton(const ClothModel& model, const ClothState& state,
                                     std::span<const FrictionConstraint> friction,
                                     const FrictionSettings& settings, DynamicsWorkspace& ws,
                                     FrictionOutcome& outcome) {
  const std::size_t nf = friction.size();
  const double eps = settings.stick_velocity;
  const auto active = [&](std::size_t k) { return ws.active[k] != 0; };
  // The assembled system, kept: each iteration adds its linearised friction to a copy.
  ws.base_blocks = ws.blocks;
  ws.base_rhs = ws.rhs;
  // Relative tangential velocity of friction vertex k at the velocity change `dv`.
  const auto slip = [&](std::size_t k, const Eigen::VectorXd& dv) {
    return tangential_slip(friction[k], state, dv);
  };
  // The objective whose minimiser is the step: ½Δvᵀ A Δv − bᵀΔv + Σ B_k φ(‖w_k‖), φ the norm
  // smoothed below ε (φ = s²/2ε + ε/2 there).
  const auto objective = [&](const Eigen::VectorXd& dv) {
    block_multiply(model.pattern, ws.base_blocks, dv, ws.work,
                   solver_pool(model.solver.threads, ws));
    double e = 0.5 * dv.dot(ws.work) - ws.base_rhs.dot(dv);
    for (std::size_t k = 0; k < nf; ++k) {
      if (!active(k)) continue;
      const double sl = slip(k, dv).norm();
      e += friction[k].max_impulse * (sl < eps ? 0.5 * sl * sl / eps + 0.5 * eps : sl);
    }
    return e;
  };
  DynamicsReport report;
  const auto started = std::chrono::steady_clock::now();
  double e_current = objective(ws.dv_iterate);
  // Far from the answer the Newton steps solve loosely (their direction only has to descend,
  // and a PCG truncated from the iterate does); near it, to the solver's tolerance.
  bool loose = true;
  int accurate_solves = 0;
  ws.last_slip.assign(nf, Vec3::Zero());
  for (int it = 0; it <= settings.max_iterations; ++it) {
    if (it == settings.max_iterations) {
      if (!loose) break;
      loose = false;  // the cap reached on loose solves: one accurate solve at the iterate
    }
    // Friction's gradient and Hessian at the iterate: B/ε·T sticking, B/s·(T − ŵŵᵀ) sliding.
    ws.blocks = ws.base_blocks;
    ws.rhs = ws.base_rhs;
    for (std::size_t k = 0; k < nf; ++k) {
      if (!active(k)) continue;
      const FrictionConstraint& f = friction[k];
      const Vec3 w = slip(k, ws.dv_iterate);
      const double sl = w.norm();
      const Mat3 T = Mat3::Identity() - f.normal * f.normal.transpose();
      // Newton's Hessian has no curvature along a sliding vertex's slip, so far from the answer,
      // where slips turn and reverse, its steps overshoot (line-search halvings, poor PCG warm
      // starts: in a hand's pinch most steps ran out of iterations). The loose steps use the
      // isotropic B/s·T of iteratively reweighted least squares instead, a majoriser whose full
      // steps descend; the accurate steps use Newton's once a slip's direction has settled.
      const bool settled =
          !loose && it > 0 && ws.last_slip[k].dot(w) > kSettledCos * sl * ws.last_slip[k].norm();
      ws.last_slip[k] = w;
      const Mat3 H = sl < eps  ? Mat3(f.max_impulse / eps * T)
                     : settled ? Mat3(f.max_impulse / sl * (T - w * w.transpose() / (sl * sl)))
                               : Mat3(f.max_impulse / sl * T);
      const Vec3 g = friction_gradient(w, f.max_impulse, eps);
      ws.blocks[static_cast<std::size_t>(
          model.pattern.diagonal[static_cast<std::size_t>(f.vertex)])] += H;
      ws.rhs.segment<3>(3 * f.vertex) += H * ws.dv_iterate.segment<3>(3 * f.vertex) - g;
    }
    eliminate_constraints(model, state, ws.solve_constraints, ws);
    ws.dv = ws.dv_iterate;  // warm start
    report = solve_system(model, ws.solve_constraints, ws, loose ? settings.newton_tolerance : 0.0);
    if (!report.ok) return report;
    ++outcome.iterations;
    if (!loose) ++accurate_solves;
    // Backtracking line search on the objective (convex: the full step almost always decreases
    // it).
    ws.dv_step = ws.dv - ws.dv_iterate;
    double alpha = 1.0, e_new = objective(ws.dv);
    for (int halving = 0; halving < 20 && e_new > e_current; ++halving) {
      alpha *= 0.5;
      ws.dv = ws.dv_iterate + alpha * ws.dv_step;
      e_new = objective(ws.dv);
    }
    const double moved = alpha * ws.dv_step.cwiseAbs().maxCoeff();
    if (e_new <= e_current) {
      ws.dv_iterate = ws.dv;
      e_current = e_new;
    }
    // Converged: a step from an accurately solved iterate changed no velocity by tolerance·ε.
    if (accurate_solves >= 2 && (moved < settings.tolerance * eps || e_new > e_current)) break;
    // Near the answer (or stalled), the steps solve accurately.
    if (moved < settings.accurate_below * eps || e_new > e_current) loose = false;
  }
  ws.dv = ws.dv_iterate;
  outcome.linear_solves = outcome.iterations;
  // The friction's share: the solves beyond the first.
  const int solves = std::max(1, outcome.linear_solves);
  outcome.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() *
      (solves - 1) / solves;
  return report;
}

}  // namespace dexcloth::cloth
