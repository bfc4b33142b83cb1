// Friction in the implicit step through the Schur complement of the friction vertices.
//
// The step minimises f(Δv) = ½ΔvᵀAΔv − bᵀΔv + Σ_k B_k φ(‖w_k‖), whose friction terms touch only
// the friction vertices F. Ordered last in a Cholesky factorisation A = LLᵀ, their unknowns x
// satisfy S·x = c + λ with S = L₂₂L₂₂ᵀ the Schur complement of the other unknowns and
// c = L₂₂z₂ (z the forward-substituted b), λ the friction impulses. So the whole friction problem
// is the small dense one min ½xᵀSx − cᵀx + Σ B_k φ(‖w_k(x)‖), condensed further on the slip
// coordinates (two per vertex), and one back substitution gives every other velocity: the friction
// costs a dense problem of about 2|F| unknowns instead of a linear solve of the cloth per Newton
// iteration.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cloth/block_pcg.hpp"
#include "cloth/dense_blas.hpp"
#include "cloth/dynamics_workspace.hpp"

namespace dexcloth::cloth {
namespace {

/// The elimination order with the friction vertices last (the rest in the pattern's order).
void schur_order(const SystemPattern& p, const std::vector<int>& last, const std::vector<int>& slot,
                 std::vector<int>& order) {
  order.clear();
  for (int v : p.fill_order)
    if (slot[static_cast<std::size_t>(v)] < 0) order.push_back(v);
  order.insert(order.end(), last.begin(), last.end());
}

}  // namespace

DynamicsReport solve_friction_schur(const ClothModel& model, const ClothState& state,
                                    std::span<const FrictionConstraint> friction,
                                    const FrictionSettings& settings, DynamicsWorkspace& ws,
                                    FrictionOutcome& outcome) {
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  auto start = Clock::now();
  double& seconds = outcome.seconds;
  int& iterations = outcome.iterations;
  seconds = 0.0;
  iterations = 0;
  outcome.linear_solves = 1;
  const std::span<const char> active = ws.active;
  const std::vector<int>& F = ws.schur_vertices;
  const std::vector<int>& slot = ws.schur_slot;
  const auto m = static_cast<Eigen::Index>(3 * F.size());
  const auto n = static_cast<Eigen::Index>(3 * model.num_vertices());
  const double eps = settings.stick_velocity;

  // The order with F last; the analysis is redone only when F changed.
  schur_order(model.pattern, F, slot, ws.schur_order);
  if (ws.schur_order != ws.schur.order)
    analyse(model.pattern, ws.schur_order, model.solver.threads, ws.schur);
  seconds += since(start);

  // Factorisation and forward substitution: the cloth's own solve.
  ws.blocks = ws.base_blocks;
  ws.rhs = ws.base_rhs;
  eliminate_constraints(model, state, ws.solve_constraints, ws);
  DynamicsReport report = factorise(ws.blocks, ws.schur);
  if (!report.ok) return report;
  const DirectSystem& d = ws.schur;
  for (Eigen::Index k = 0; k < n; ++k) ws.work[k] = ws.rhs[d.dof[static_cast<std::size_t>(k)]];
  d.cholesky.forward_in_place(std::span<double>(ws.work.data(), static_cast<std::size_t>(n)));

  // The friction problem on the Schur complement: min ½xᵀSx − cᵀx + Σ B_k φ(‖w_k‖).
  start = Clock::now();
  d.cholesky.trailing_factor(static_cast<int>(m), ws.schur_L);
  // S = L₂₂L₂₂ᵀ; c = L₂₂z₂.
  lower_times_transpose(ws.schur_L, ws.schur_S);
  ws.schur_c.noalias() = ws.schur_L.triangularView<Eigen::Lower>() * ws.work.tail(m);
  // Only the slip directions are nonlinear: in each tail vertex's frame R (tangents first when
  // its contact planes agree, else all three axes; none without friction) the unknowns split
  // into slip coordinates y and the rest r, and r is eliminated exactly once. Newton's method
  // then works on the p slip coordinates alone.
  std::vector<int>& fidx = ws.schur_fidx;
  std::vector<int>& ridx = ws.schur_ridx;
  std::vector<Mat3>& frame = ws.schur_frame;
  std::vector<int>& slip_dofs = ws.schur_slip_dofs;  // per tail vertex: 0, 2 or 3
  frame.assign(F.size(), Mat3::Identity());
  slip_dofs.assign(F.size(), 0);
  for (std::size_t k = 0; k < friction.size(); ++k) {
    if (!active[k]) continue;
    const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(friction[k].vertex)]);
    const Vec3& n = friction[k].normal;
    if (slip_dofs[a] == 0) {
      slip_dofs[a] = 2;
      frame[a].col(2) = n;  // the plane; its tangents below
    } else if (slip_dofs[a] == 2 && std::abs(frame[a].col(2).dot(n)) < 1.0 - 1e-12) {
      slip_dofs[a] = 3;
      frame[a].setIdentity();
    }
  }
  fidx.clear();
  ridx.clear();
  for (std::size_t a = 0; a < F.size(); ++a) {
    if (slip_dofs[a] == 2) {
      const Vec3 n = frame[a].col(2);
      const Vec3 t1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
      frame[a].col(0) = t1;
      frame[a].col(1) = n.cross(t1);
    }
    for (int c = 0; c < 3; ++c)
      (c < slip_dofs[a] ? fidx : ridx).push_back(3 * static_cast<int>(a) + c);
  }
  // S and c in the frames (block-diagonal rotation B: BᵀSB, Bᵀc).
  for (std::size_t b = 0; b < F.size(); ++b) {
    const auto col = static_cast<Eigen::Index>(3 * b);
    ws.schur_S.middleCols(col, 3) = (ws.schur_S.middleCols(col, 3) * frame[b]).eval();
  }
  for (std::size_t a = 0; a < F.size(); ++a) {
    const auto row = static_cast<Eigen::Index>(3 * a);
    ws.schur_S.middleRows(row, 3) = (frame[a].transpose() * ws.schur_S.middleRows(row, 3)).eval();
    ws.schur_c.segment<3>(row) = frame[a].transpose() * ws.schur_c.segment<3>(row);
  }
  const auto p = static_cast<Eigen::Index>(fidx.size());
  const auto q = static_cast<Eigen::Index>(ridx.size());
  // Condensed: Sc = S_yy − S_yr·S_rr⁻¹·S_ry, cc = c_y − S_yr·S_rr⁻¹·c_r. With S_rr = L_r·L_rᵀ,
  // W = L_r⁻¹·S_ry and z_r = L_r⁻¹·c_r: Sc = S_yy − WᵀW, cc = c_y − Wᵀz_r.
  ws.schur_Syy = ws.schur_S(fidx, fidx);
  ws.schur_cy = ws.schur_c(fidx);
  if (q > 0) {
    ws.schur_Lr = ws.schur_S(ridx, ridx);
    if (!cholesky_lower(ws.schur_Lr)) {  // not expected: S is SPD
      report.ok = false;
      report.message = "friction solve: the Schur complement is not positive definite";
      return report;
    }
    ws.schur_W = ws.schur_S(ridx, fidx);
    solve_lower(ws.schur_Lr, ws.schur_W);
    ws.schur_zr = ws.schur_c(ridx);
    solve_lower(ws.schur_Lr, ws.schur_zr);
    subtract_gram(ws.schur_W, ws.schur_Syy);
    ws.schur_cy.noalias() -= ws.schur_W.transpose() * ws.schur_zr;
  }
  // Per constraint: offset of its vertex's slip coordinates in y and their axes.
  std::vector<int>& yoff = ws.schur_yoff;  // per tail vertex
  yoff.assign(F.size(), 0);
  for (std::size_t a = 0, o = 0; a < F.size(); o += static_cast<std::size_t>(slip_dofs[a]), ++a)
    yoff[a] = static_cast<int>(o);
  const auto axes = [&](std::size_t a) { return frame[a].leftCols(slip_dofs[a]); };
  // Warm start: the last step's Δv in the frames.
  ws.schur_x.resize(p);
  for (std::size_t a = 0; a < F.size(); ++a)
    ws.schur_x.segment(yoff[a], slip_dofs[a]) =
        axes(a).transpose() * ws.dv_iterate.segment<3>(3 * F[a]);
  // Slip of friction constraint k at the slip coordinates y.
  const auto slip = [&](std::size_t k, const Eigen::VectorXd& y) {
    const FrictionConstraint& f = friction[k];
    const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(f.vertex)]);
    const Vec3 w = state.v.row(f.vertex).transpose() - f.surface_velocity +
                   axes(a) * y.segment(yoff[a], slip_dofs[a]);
    return Vec3(w - f.normal.dot(w) * f.normal);
  };
  const auto objective = [&](const Eigen::VectorXd& y) {
    double e = 0.5 * y.dot(ws.schur_Syy * y) - ws.schur_cy.dot(y);
    for (std::size_t k = 0; k < friction.size(); ++k) {
      if (!active[k]) continue;
      const double s = slip(k, y).norm();
      e += friction[k].max_impulse * (s < eps ? 0.5 * s * s / eps + 0.5 * eps : s);
    }
    return e;
  };
  std::vector<Vec3>& last_slip = ws.last_slip;
  last_slip.assign(friction.size(), Vec3::Zero());
  double e_current = objective(ws.schur_x);
  const int max_iterations = 20 * settings.max_iterations;
  for (; iterations < max_iterations;) {
    ws.schur_K = ws.schur_Syy;
    ws.schur_r.noalias() = ws.schur_cy - ws.schur_Syy * ws.schur_x;
    for (std::size_t k = 0; k < friction.size(); ++k) {
      if (!active[k]) continue;
      const FrictionConstraint& f = friction[k];
      const Vec3 w = slip(k, ws.schur_x);
      const double s = w.norm();
      const Mat3 T = Mat3::Identity() - f.normal * f.normal.transpose();
      const bool settled =
          iterations > 0 && last_slip[k].dot(w) > kSettledCos * s * last_slip[k].norm();
      last_slip[k] = w;
      const Mat3 H = s < eps   ? Mat3(f.max_impulse / eps * T)
                     : settled ? Mat3(f.max_impulse / s * (T - w * w.transpose() / (s * s)))
                               : Mat3(f.max_impulse / s * T);
      const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(f.vertex)]);
      const int o = yoff[a], nd = slip_dofs[a];
      ws.schur_K.block(o, o, nd, nd) += axes(a).transpose() * H * axes(a);
      ws.schur_r.segment(o, nd) -= axes(a).transpose() * friction_gradient(w, f.max_impulse, eps);
    }
    if (!cholesky_lower(ws.schur_K)) break;  // not expected: Sc is SPD, the H are PSD
    ws.schur_step = ws.schur_r;
    cholesky_solve(ws.schur_K, ws.schur_step);
    ++iterations;
    double alpha = 1.0;
    ws.schur_trial = ws.schur_x + ws.schur_step;
    double e_new = objective(ws.schur_trial);
    for (int halving = 0; halving < 30 && e_new > e_current; ++halving) {
      alpha *= 0.5;
      ws.schur_trial = ws.schur_x + alpha * ws.schur_step;
      e_new = objective(ws.schur_trial);
    }
    if (!(e_new < e_current)) break;  // no descent left: the minimum to rounding
    ws.schur_x = ws.schur_trial;
    e_current = e_new;
    // To rounding: the iterations here are cheap, and near a stuck vertex's stiff smoothing a
    // step far below ε still leaves a large impulse residual.
    if (alpha * ws.schur_step.cwiseAbs().maxCoeff() < 1e-8 * eps) break;
  }
  // The tail: y, the rest r = S_rr⁻¹·(c_r − S_ry·y) = L_r⁻ᵀ·(z_r − W·y), back from the frames.
  ws.schur_tail.resize(m);
  ws.schur_tail(fidx) = ws.schur_x;
  if (q > 0) {
    ws.schur_zr.noalias() -= ws.schur_W * ws.schur_x;
    solve_lower_transposed(ws.schur_Lr, ws.schur_zr);
    ws.schur_tail(ridx) = ws.schur_zr;
  }
  for (std::size_t a = 0; a < F.size(); ++a) {
    const auto row = static_cast<Eigen::Index>(3 * a);
    ws.work.segment<3>(n - m + row) = frame[a] * ws.schur_tail.segment<3>(row);
  }
  seconds += since(start);

  // Back substitution: every other velocity from the friction vertices'.
  d.cholesky.backward_in_place(std::span<double>(ws.work.data(), static_cast<std::size_t>(n)),
                               static_cast<int>(m));
  for (Eigen::Index k = 0; k < n; ++k) ws.dv[d.dof[static_cast<std::size_t>(k)]] = ws.work[k];

  // Check: every row of the system balances, the friction vertices' with their impulses (one
  // thread, as direct_residual).
  block_multiply(model.pattern, ws.blocks, ws.dv, ws.work, 1);
  ws.work -= ws.rhs;
  for (std::size_t k = 0; k < friction.size(); ++k) {
    if (!active[k]) continue;
    const FrictionConstraint& f = friction[k];
    ws.work.segment<3>(3 * f.vertex) +=
        friction_gradient(tangential_slip(f, state, ws.dv), f.max_impulse, eps);
  }
  const double b_norm = ws.rhs.norm();
  report.residual = ws.work.norm() / (b_norm > 0.0 ? b_norm : 1.0);
  if (!ws.dv.allFinite() || !(report.residual <= std::max(model.solver.tolerance, 1e-6))) {
    report.ok = false;
    report.message = "friction solve through the Schur complement left a relative residual " +
                     std::to_string(report.residual);
  }
  return report;
}

}  // namespace dexcloth::cloth
