// Friction in the implicit step through the Schur complement of the friction vertices.
//
// The step minimises f(Δv) = ½ΔvᵀAΔv − bᵀΔv + Σ_k B_k φ(‖w_k‖), whose friction terms touch only
// the slip coordinates y of the friction vertices F: in each one's frame R (its contact plane's
// tangents, then its normal; all three axes when its planes disagree) the coordinates split
// into y and the rest. With the frames' rotation applied to A and b and the y ordered last in a
// Cholesky factorisation A = LLᵀ, they satisfy S·y = c + λ with S = L₂₂L₂₂ᵀ the Schur complement
// of every other unknown and c = L₂₂z₂ (z the forward-substituted b), λ the friction impulses.
// So the whole friction problem is the small dense one min ½yᵀSy − cᵀy + Σ B_k φ(‖w_k(y)‖), and
// one back substitution gives every other velocity: the friction costs a dense problem of about
// 2|F| unknowns instead of a linear solve of the cloth per Newton iteration. F changes seldom
// (vertices that lose their friction stay in it a while): the order, and its analysis, depend
// on F alone, and the y of vertices without friction now are condensed out of the dense problem
// once, before its Newton iterations.
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

/// Each friction vertex's frame and number of slip coordinates (ws.schur_frame, ws.schur_count):
/// its contact plane's tangents first when its active constraints agree on the plane, else all
/// three axes. A vertex keeps three once it needed them, and two without friction now (in any
/// frame), so that the order of the unknowns, and its analysis, change only with F.
void slip_frames(std::span<const FrictionConstraint> friction, DynamicsWorkspace& ws) {
  const std::vector<int>& F = ws.schur_vertices;
  const std::vector<int>& slot = ws.schur_slot;
  std::vector<Mat3>& frame = ws.schur_frame;
  std::vector<char>& planes = ws.schur_planes;  // per friction vertex: 0, 1, or 2 and more
  frame.assign(F.size(), Mat3::Identity());
  planes.assign(F.size(), 0);
  for (std::size_t k = 0; k < friction.size(); ++k) {
    if (!ws.active[k]) continue;
    const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(friction[k].vertex)]);
    const Vec3& n = friction[k].normal;
    if (planes[a] == 0) {
      planes[a] = 1;
      frame[a].col(2) = n;
    } else if (planes[a] == 1 && std::abs(frame[a].col(2).dot(n)) < 1.0 - 1e-12) {
      planes[a] = 2;
    }
  }
  for (std::size_t a = 0; a < F.size(); ++a) {
    char& count = ws.schur_count[static_cast<std::size_t>(F[a])];
    count = std::max<char>(count, planes[a] == 2 ? 3 : 2);
    if (planes[a] == 1 && count == 2) {
      const Vec3 n = frame[a].col(2);
      const Vec3 t1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
      frame[a].col(0) = t1;
      frame[a].col(1) = n.cross(t1);
    } else {
      frame[a].setIdentity();
    }
  }
}

/// The elimination order of the unknowns: the other vertices' in the pattern's order, then the
/// friction vertices' coordinates beyond their slip ones, then the slip coordinates (y).
void schur_order(const SystemPattern& p, const DynamicsWorkspace& ws, std::vector<int>& dofs) {
  const std::vector<int>& F = ws.schur_vertices;
  dofs.clear();
  for (int v : p.fill_order)
    if (ws.schur_slot[static_cast<std::size_t>(v)] < 0)
      for (int c = 0; c < 3; ++c) dofs.push_back(3 * v + c);
  for (int v : F)
    for (int c = ws.schur_count[static_cast<std::size_t>(v)]; c < 3; ++c) dofs.push_back(3 * v + c);
  for (int v : F)
    for (int c = 0; c < ws.schur_count[static_cast<std::size_t>(v)]; ++c) dofs.push_back(3 * v + c);
}

/// Rotates the system's rows and columns of the friction vertices into their frames
/// (A ← BᵀAB, b ← Bᵀb for the block-diagonal B of the frames), keeping the blocks and right-hand
/// sides it changes in ws.schur_saved_blocks / ws.schur_saved_rhs for restore_system.
void rotate_system(const SystemPattern& p, DynamicsWorkspace& ws) {
  const std::vector<int>& F = ws.schur_vertices;
  ws.schur_saved_blocks.clear();
  ws.schur_saved_rhs.clear();
  for (int v : F) {
    for (int b = p.col_start[static_cast<std::size_t>(v)];
         b < p.col_start[static_cast<std::size_t>(v) + 1]; ++b) {
      for (const int k : {b, p.transpose[static_cast<std::size_t>(b)]})
        ws.schur_saved_blocks.emplace_back(k, ws.blocks[static_cast<std::size_t>(k)]);
    }
    ws.schur_saved_rhs.emplace_back(v, ws.rhs.segment<3>(3 * v));
  }
  for (std::size_t a = 0; a < F.size(); ++a) {
    const int v = F[a];
    const Mat3& R = ws.schur_frame[a];
    for (int b = p.col_start[static_cast<std::size_t>(v)];
         b < p.col_start[static_cast<std::size_t>(v) + 1]; ++b) {
      Mat3& column = ws.blocks[static_cast<std::size_t>(b)];  // A(i, v)
      column = (column * R).eval();
      Mat3& row = ws.blocks[static_cast<std::size_t>(p.transpose[static_cast<std::size_t>(b)])];
      row = (R.transpose() * row).eval();  // A(v, i)
    }
    ws.rhs.segment<3>(3 * v) = R.transpose() * ws.rhs.segment<3>(3 * v);
  }
}

/// Rotates the friction vertices' rows of ws.correction (a residual) into their frames.
void rotate_residual(DynamicsWorkspace& ws) {
  for (std::size_t a = 0; a < ws.schur_vertices.size(); ++a) {
    const int v = ws.schur_vertices[a];
    ws.correction.segment<3>(3 * v) =
        ws.schur_frame[a].transpose() * ws.correction.segment<3>(3 * v);
  }
}

/// Undoes rotate_system exactly.
void restore_system(DynamicsWorkspace& ws) {
  for (const auto& [k, block] : ws.schur_saved_blocks)
    ws.blocks[static_cast<std::size_t>(k)] = block;
  for (const auto& [v, b] : ws.schur_saved_rhs) ws.rhs.segment<3>(3 * v) = b;
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
  const auto n = static_cast<Eigen::Index>(3 * model.num_vertices());
  const double eps = settings.stick_velocity;

  // Frames and the order with the slip coordinates last; the analysis is redone only when the
  // order changed.
  ws.schur_count.resize(static_cast<std::size_t>(model.num_vertices()), 0);
  slip_frames(friction, ws);
  schur_order(model.pattern, ws, ws.schur_order);
  if (ws.schur_order != ws.schur.dof ||
      ws.schur.cholesky.precision() != model.solver.factor_precision)
    analyse_unknowns(model.pattern, ws.schur_order, model.solver.threads, ws.schur,
                     model.solver.factor_precision);
  const std::vector<Mat3>& frame = ws.schur_frame;
  // Per tail vertex: its slip coordinates' offset in the tail's p (`yoff`) and, when it has
  // friction now, in the q of the Newton problem (`qoff`, else −1).
  std::vector<int>& yoff = ws.schur_yoff;
  std::vector<int>& qoff = ws.schur_qoff;
  yoff.assign(F.size() + 1, 0);
  qoff.assign(F.size(), -1);
  ws.schur_fidx.clear();
  ws.schur_ridx.clear();
  for (std::size_t a = 0; a < F.size(); ++a) {
    const int count = ws.schur_count[static_cast<std::size_t>(F[a])];
    yoff[a + 1] = yoff[a] + count;
    if (ws.schur_planes[a] > 0) qoff[a] = static_cast<int>(ws.schur_fidx.size());
    for (int c = 0; c < count; ++c)
      (ws.schur_planes[a] > 0 ? ws.schur_fidx : ws.schur_ridx).push_back(yoff[a] + c);
  }
  const auto dofs = [&](std::size_t a) { return yoff[a + 1] - yoff[a]; };
  const auto axes = [&](std::size_t a) { return frame[a].leftCols(dofs(a)); };
  const auto p = static_cast<Eigen::Index>(yoff.back());
  const auto q = static_cast<Eigen::Index>(ws.schur_fidx.size());
  seconds += since(start);

  // Factorisation of the rotated system (the assembled one, in ws.blocks and ws.rhs): the
  // cloth's own solve.
  eliminate_constraints(model, state, ws.solve_constraints, ws);
  rotate_system(model.pattern, ws);
  DynamicsReport report = factorise(ws.blocks, ws.schur, solver_pool(model.solver.threads, ws));
  const DirectSystem& d = ws.schur;
  for (Eigen::Index k = 0; k < n; ++k) ws.work[k] = ws.rhs[d.dof[static_cast<std::size_t>(k)]];
  restore_system(ws);
  if (!report.ok) return report;

  // The friction problem on the Schur complement: min ½yᵀSy − cᵀy + Σ B_k φ(‖w_k‖), with
  // S = L₂₂L₂₂ᵀ and c = L₂₂z₂.
  start = Clock::now();
  d.cholesky.trailing_factor(static_cast<int>(p), ws.schur_L);
  lower_times_transpose(ws.schur_L, ws.schur_S);
  // The coordinates r of the tail vertices without friction now (kept in F, unchanged order)
  // enter it quadratically: condensed once, the Newton iterations see only the q slip
  // coordinates x of the vertices with friction. With S_rr = L_r·L_rᵀ, W = L_r⁻¹·S_rx and
  // z_r = L_r⁻¹·c_r: S_xx − WᵀW and c_x − Wᵀz_r.
  const std::vector<int>& fidx = ws.schur_fidx;
  const std::vector<int>& ridx = ws.schur_ridx;
  ws.schur_Sxx = ws.schur_S(fidx, fidx);
  if (!ridx.empty()) {
    ws.schur_Lr = ws.schur_S(ridx, ridx);
    if (!cholesky_lower(ws.schur_Lr)) {  // not expected: S is SPD
      report.ok = false;
      report.message = "friction solve: the Schur complement is not positive definite";
      return report;
    }
    ws.schur_W = ws.schur_S(ridx, fidx);
    solve_lower(ws.schur_Lr, ws.schur_W);
    subtract_gram(ws.schur_W, ws.schur_Sxx);
  }
  seconds += since(start);

  // One solve of the problem for the right-hand side in ws.work (permuted and rotated), into
  // `out` (3|V|), its Newton iterations starting from the last step's Δv (ws.dv_iterate). With
  // `base` (3|V|, not `out`) given, the problem of a correction δ of Δv = base whose right-hand
  // side is the whole residual, from δ = 0: the friction vertices slip at v + base + δ, and
  // their friction's gradient at base is taken out (it is in the residual), so that every term
  // shrinks with the residual.
  const auto solve_once = [&](const Eigen::VectorXd* base, Eigen::VectorXd& out) {
    d.cholesky.forward_in_place(std::span<double>(ws.work.data(), static_cast<std::size_t>(n)));
    const auto round_start = Clock::now();
    ws.schur_c.noalias() = ws.schur_L.triangularView<Eigen::Lower>() * ws.work.tail(p);
    ws.schur_cx = ws.schur_c(fidx);
    if (!ridx.empty()) {
      ws.schur_zr = ws.schur_c(ridx);
      solve_lower(ws.schur_Lr, ws.schur_zr);
      ws.schur_cx.noalias() -= ws.schur_W.transpose() * ws.schur_zr;
    }
    ws.schur_x.setZero(q);
    if (base == nullptr)
      for (std::size_t a = 0; a < F.size(); ++a)
        if (qoff[a] >= 0)
          ws.schur_x.segment(qoff[a], dofs(a)) =
              axes(a).transpose() * ws.dv_iterate.segment<3>(3 * F[a]);
    // Slip of friction constraint k at the slip coordinates x.
    const auto slip = [&](std::size_t k, const Eigen::VectorXd& x) {
      const FrictionConstraint& f = friction[k];
      const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(f.vertex)]);
      const Vec3 w = base == nullptr
                         ? Vec3(state.v.row(f.vertex).transpose() - f.surface_velocity +
                                axes(a) * x.segment(qoff[a], dofs(a)))
                         : Vec3(state.v.row(f.vertex).transpose() + base->segment<3>(3 * f.vertex) -
                                f.surface_velocity + axes(a) * x.segment(qoff[a], dofs(a)));
      return Vec3(w - f.normal.dot(w) * f.normal);
    };
    // A correction's friction gradients at its start x = 0, in the Newton problem's coordinates.
    ws.schur_g0.setZero(q);
    if (base != nullptr) {
      for (std::size_t k = 0; k < friction.size(); ++k) {
        if (!active[k]) continue;
        const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(friction[k].vertex)]);
        ws.schur_g0.segment(qoff[a], dofs(a)) +=
            axes(a).transpose() *
            friction_gradient(slip(k, ws.schur_x), friction[k].max_impulse, eps);
      }
    }
    const auto objective = [&](const Eigen::VectorXd& x) {
      double e = 0.5 * x.dot(ws.schur_Sxx * x) - ws.schur_cx.dot(x);
      if (base != nullptr) e -= ws.schur_g0.dot(x);
      for (std::size_t k = 0; k < friction.size(); ++k) {
        if (!active[k]) continue;
        const double s = slip(k, x).norm();
        e += friction[k].max_impulse * (s < eps ? 0.5 * s * s / eps + 0.5 * eps : s);
      }
      return e;
    };
    std::vector<Vec3>& last_slip = ws.last_slip;
    last_slip.assign(friction.size(), Vec3::Zero());
    double e_current = objective(ws.schur_x);
    const int max_iterations = 20 * settings.max_iterations;
    for (int newton = 0; newton < max_iterations; ++newton) {
      ws.schur_K = ws.schur_Sxx;
      ws.schur_r.noalias() = ws.schur_cx - ws.schur_Sxx * ws.schur_x;
      if (base != nullptr) ws.schur_r += ws.schur_g0;
      for (std::size_t k = 0; k < friction.size(); ++k) {
        if (!active[k]) continue;
        const FrictionConstraint& f = friction[k];
        const Vec3 w = slip(k, ws.schur_x);
        const double s = w.norm();
        const Mat3 T = Mat3::Identity() - f.normal * f.normal.transpose();
        const bool settled =
            newton > 0 && last_slip[k].dot(w) > kSettledCos * s * last_slip[k].norm();
        last_slip[k] = w;
        const Mat3 H = s < eps   ? Mat3(f.max_impulse / eps * T)
                       : settled ? Mat3(f.max_impulse / s * (T - w * w.transpose() / (s * s)))
                                 : Mat3(f.max_impulse / s * T);
        const auto a = static_cast<std::size_t>(slot[static_cast<std::size_t>(f.vertex)]);
        const int o = qoff[a], nd = dofs(a);
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
    // The tail: x, and r = S_rr⁻¹·(c_r − S_rx·x) = L_r⁻ᵀ·(z_r − W·x); back substitution for
    // every other unknown; the friction vertices' velocities back from their frames.
    ws.schur_tail.resize(p);
    ws.schur_tail(fidx) = ws.schur_x;
    if (!ridx.empty()) {
      ws.schur_zr.noalias() -= ws.schur_W * ws.schur_x;
      solve_lower_transposed(ws.schur_Lr, ws.schur_zr);
      ws.schur_tail(ridx) = ws.schur_zr;
    }
    ws.work.tail(p) = ws.schur_tail;
    seconds += since(round_start);
    d.cholesky.backward_in_place(std::span<double>(ws.work.data(), static_cast<std::size_t>(n)),
                                 static_cast<int>(p));
    for (Eigen::Index k = 0; k < n; ++k) out[d.dof[static_cast<std::size_t>(k)]] = ws.work[k];
    for (std::size_t a = 0; a < F.size(); ++a)
      out.segment<3>(3 * F[a]) = frame[a] * out.segment<3>(3 * F[a]);
  };
  // Every row of the system balances, the friction vertices' with their impulses: the relative
  // residual of Δv (its product on the solver's pool, as direct_residual), A·Δv − b + ∇Φ left in
  // ws.work.
  const double b_norm = ws.rhs.norm();
  const auto residual = [&] {
    block_multiply(model.pattern, ws.blocks, ws.dv, ws.work, solver_pool(model.solver.threads, ws));
    ws.work -= ws.rhs;
    for (std::size_t k = 0; k < friction.size(); ++k) {
      if (!active[k]) continue;
      const FrictionConstraint& f = friction[k];
      ws.work.segment<3>(3 * f.vertex) +=
          friction_gradient(tangential_slip(f, state, ws.dv), f.max_impulse, eps);
    }
    return ws.work.norm() / (b_norm > 0.0 ? b_norm : 1.0);
  };

  solve_once(nullptr, ws.dv);
  report.residual = residual();
  // A single-precision factor: refined in double, each round the problem of the correction δ
  // of Δv for the residual, until it is below refine_tolerance or stops shrinking.
  if (model.solver.factor_precision == Precision::single_precision) {
    ws.schur_delta.resize(n);
    for (int round = 0;
         report.residual > model.solver.refine_tolerance && round < model.solver.max_refinements;
         ++round) {
      ws.correction = -ws.work;
      rotate_residual(ws);
      for (Eigen::Index k = 0; k < n; ++k)
        ws.work[k] = ws.correction[d.dof[static_cast<std::size_t>(k)]];
      solve_once(&ws.dv, ws.schur_delta);
      ws.dv += ws.schur_delta;
      ++outcome.linear_solves;
      const double last = report.residual;
      report.residual = residual();
      if (report.residual > last) {  // rounding reached: keep the better one
        ws.dv -= ws.schur_delta;
        report.residual = last;
      }
      if (report.residual > last / kRefinementGain) break;
    }
  }
  if (!ws.dv.allFinite() || !(report.residual <= std::max(model.solver.tolerance, 1e-6))) {
    report.ok = false;
    report.message = "friction solve through the Schur complement left a relative residual " +
                     std::to_string(report.residual);
  }
  return report;
}

}  // namespace dexcloth::cloth
