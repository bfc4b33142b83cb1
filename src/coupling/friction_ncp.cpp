#include "coupling/friction_ncp.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/assert.hpp"

namespace dexcloth::coupling {
namespace {

/// Problem data shared by the candidates: a = m/h, capacities c_i = μ_i fN_i, and the relative
/// tangential velocities u_i (projected on the common plane).
struct Problem {
  int count{};
  double a{};
  std::array<double, kMaxVertexContacts> c{};
  std::array<Vec3, kMaxVertexContacts> u{};
  Mat3 P{Mat3::Identity()};
  double speed_eps{};  ///< speeds below this are zero [m/s]
};

Mat3 tangent_projector(const Vec3& n) {
  const Vec3 nn = n.normalized();
  return Mat3::Identity() - nn * nn.transpose();
}

/// The common plane of the contacts, when every normal is within asin(max_sin) of ±n_0 (sandwich
/// or same side): the sign-aligned mean normal. False otherwise (or with no contacts).
bool common_normal(std::span<const FrictionContact> contacts, double max_sin, Vec3& n) {
  // A contact without friction capacity exerts no force whatever its plane: it does not count.
  const auto carries = [](const FrictionContact& c) { return c.mu * c.normal_force > 0.0; };
  const auto first = std::find_if(contacts.begin(), contacts.end(), carries);
  if (first == contacts.end()) return false;
  const Vec3 n0 = first->normal.normalized();
  n = Vec3::Zero();
  for (const FrictionContact& c : contacts) {
    if (!carries(c)) continue;
    const Vec3 ni = c.normal.normalized();
    if (ni.cross(n0).norm() > max_sin) return false;
    n += ni.dot(n0) >= 0.0 ? ni : Vec3(-ni);
  }
  n.normalize();
  return true;
}

/// Tolerance of the checks, as a force [N].
double force_scale(const Problem& p) {
  double s = 0.0;
  for (int i = 0; i < p.count; ++i) s = std::max({s, p.c[i], p.a * p.u[i].norm()});
  return s + 1e-300;
}

/// Candidate "static at k": the vertex moves with contact k, Δv = −u_k. Contacts moving with k
/// share the remaining force in proportion to their capacity; the others slide against it.
bool try_static_at(const Problem& p, int k, FrictionResult& r) {
  const Vec3 dv = -p.u[k];
  Vec3 remainder = p.a * dv;
  double static_capacity = 0.0;
  for (int i = 0; i < p.count; ++i) {
    const Vec3 w = p.u[i] + dv;
    const double speed = w.norm();
    r.sticking[i] = speed <= p.speed_eps;
    if (r.sticking[i]) {
      static_capacity += p.c[i];
    } else {
      r.force[i] = -p.c[i] * w / speed;
      remainder -= r.force[i];
    }
  }
  // The sticking contacts must be able to supply the remainder inside their cones.
  const double need = remainder.norm();
  if (need > static_capacity * (1.0 + 1e-12) + 1e-14 * force_scale(p)) return false;
  for (int i = 0; i < p.count; ++i)
    if (r.sticking[i])
      r.force[i] =
          static_capacity > 0.0 ? Vec3(remainder * (p.c[i] / static_capacity)) : Vec3::Zero();
  r.delta_v = dv;
  r.which = FrictionCase::static_at;
  r.anchor = k;
  return true;
}

/// General contact planes: block Gauss–Seidel, each block solved exactly (stick if the cone can
/// stop it, else slide at the cone boundary).
/// `common`, when given, is the tangent projector shared by all contacts (parallel planes).
void solve_general(std::span<const FrictionContact> contacts, double a, const Mat3* common,
                   FrictionResult& r) {
  const int m = static_cast<int>(contacts.size());
  std::array<Mat3, kMaxVertexContacts> P;
  for (int i = 0; i < m; ++i) P[i] = common ? *common : tangent_projector(contacts[i].normal);
  Vec3 total = Vec3::Zero();
  for (int iter = 0; iter < 2000; ++iter) {
    double change = 0.0, scale = 1e-300;
    for (int i = 0; i < m; ++i) {
      const double c = contacts[i].mu * contacts[i].normal_force;
      const Vec3 others = total - r.force[i];
      const Vec3 u = P[i] * (contacts[i].relative_velocity + others / a);
      const Vec3 f = a * u.norm() <= c ? Vec3(-a * u) : Vec3(-c * u.normalized());
      change = std::max(change, (f - r.force[i]).norm());
      scale = std::max({scale, c, a * u.norm()});
      total = others + f;
      r.force[i] = f;
    }
    if (change <= 1e-15 * scale) break;
  }
  r.delta_v = total / a;
  for (int i = 0; i < m; ++i)
    r.sticking[i] = (P[i] * (contacts[i].relative_velocity + r.delta_v)).norm() <=
                    1e-12 * (1.0 + contacts[i].relative_velocity.norm());
  r.which = FrictionCase::general;
}

/// Refines a dual answer (r.force) by accelerated projected gradient on the dual, FISTA with
/// adaptive restart: maximise −‖Σf‖²/(2a) − Σ f_i·u_i over f_i in the disk of radius c_i in
/// plane i, whose gradient is −w_i, the next slip. Block Gauss–Seidel crawls where the planes are
/// a few degrees apart and the cones far from full (a pinch between pads that are not parallel:
/// large squeezing forces nearly cancel), and the 3-D Newton stalls at the kinks nearby; this
/// converges there. Stops once `good` accepts the answer (checked every 32 iterations).
template <class Accept>
void refine_dual(std::span<const FrictionContact> contacts, double a, const Mat3* P,
                 const double* c, Accept good, FrictionResult& r) {
  const int m = static_cast<int>(contacts.size());
  std::array<Vec3, kMaxVertexContacts> f{}, previous{}, y{};
  const auto project = [&](int i, const Vec3& g) {
    const Vec3 t = P[i] * g;
    const double norm = t.norm();
    return norm > c[i] ? Vec3(t * (c[i] / norm)) : t;
  };
  for (int i = 0; i < m; ++i) y[i] = f[i] = project(i, r.force[static_cast<std::size_t>(i)]);
  const double step = a / m;  // 1/L: the dual's Hessian is (1/a)·11ᵀ on the planes
  double t = 1.0;
  for (int iter = 1; iter <= 20000; ++iter) {
    Vec3 total = Vec3::Zero();
    for (int i = 0; i < m; ++i) total += y[i];
    const Vec3 dv = total / a;
    previous = f;
    for (int i = 0; i < m; ++i) {
      const Vec3 slip = P[i] * (contacts[static_cast<std::size_t>(i)].relative_velocity + dv);
      f[i] = c[i] > 0.0 ? project(i, y[i] - step * slip) : Vec3::Zero();
    }
    // Restart when the momentum points uphill (O'Donoghue & Candès' gradient test).
    double uphill = 0.0;
    for (int i = 0; i < m; ++i) uphill += (y[i] - f[i]).dot(f[i] - previous[i]);
    const double t_next = uphill > 0.0 ? 1.0 : 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    for (int i = 0; i < m; ++i)
      y[i] = uphill > 0.0 ? f[i] : Vec3(f[i] + ((t - 1.0) / t_next) * (f[i] - previous[i]));
    t = t_next;
    if (iter % 32 != 0 && iter != 20000) continue;
    total = Vec3::Zero();
    for (int i = 0; i < m; ++i) {
      r.force[static_cast<std::size_t>(i)] = f[i];
      total += f[i];
    }
    r.delta_v = total / a;
    if (good(r)) break;
  }
}

/// Non-parallel planes, candidate "static at k": Δv on the line P_k(u_k + Δv) = 0, i.e.
/// Δv = −P_k·u_k + t·n_k, with t minimising the convex ½a‖Δv‖² + Σ_{j≠k} c_j‖P_j(u_j + Δv)‖
/// (its derivative is increasing: bisection). Contacts that end stuck with k share the rest of
/// aΔv, the others slide.
bool try_general_static_at(std::span<const FrictionContact> contacts, double a, const double* c,
                           const Mat3* P, double speed_eps, int k, FrictionResult& r) {
  const int m = static_cast<int>(contacts.size());
  const Vec3 n = contacts[static_cast<std::size_t>(k)].normal.normalized();
  const Vec3 base = -(P[k] * contacts[static_cast<std::size_t>(k)].relative_velocity);
  const auto slope = [&](double t) {
    const Vec3 dv = base + t * n;
    double d = a * t;
    for (int j = 0; j < m; ++j) {
      if (j == k) continue;
      const Vec3 w = P[j] * (contacts[static_cast<std::size_t>(j)].relative_velocity + dv);
      const double s = w.norm();
      if (s > 0.0) d += c[j] * (P[j] * n).dot(w) / s;
    }
    return d;
  };
  double bound = 0.0;
  for (int j = 0; j < m; ++j) bound += j == k ? 0.0 : c[j];
  double lo = -bound / a - 1e-300, hi = bound / a + 1e-300;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (hi - lo + std::abs(lo) + std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0.0 ? hi : lo) = mid;
  }
  const Vec3 dv = base + 0.5 * (lo + hi) * n;
  // The contacts that end stuck with k (moving with it) share what sliding leaves of aΔv:
  // f_j = c_j·P_j·λ with Σ c_j·P_j·λ = rest (in proportion to capacity, each in its plane).
  Vec3 rest = a * dv;
  Mat3 shared = Mat3::Zero();
  double stuck_capacity = 0.0;
  for (int j = 0; j < m; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    const Vec3 w = P[j] * (contacts[uj].relative_velocity + dv);
    const double s = w.norm();
    r.sticking[uj] = j == k || (c[j] > 0.0 && s <= speed_eps);
    r.force[uj] = Vec3::Zero();
    if (r.sticking[uj]) {
      shared += c[j] * P[j];
      stuck_capacity += c[j];
    } else if (s > 0.0) {
      r.force[uj] = -c[j] * w / s;
      rest -= r.force[uj];
    }
  }
  // Stuck planes all parallel to k's: the rest lies in that plane (optimality in t).
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(shared, Eigen::EigenvaluesOnly);
  const bool spans = eig.eigenvalues()[0] > 1e-9 * stuck_capacity;
  const Vec3 lambda = spans ? Vec3(shared.ldlt().solve(rest)) : Vec3(P[k] * rest / stuck_capacity);
  for (int j = 0; j < m; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    if (!r.sticking[uj]) continue;
    r.force[uj] = c[j] * (spans ? Vec3(P[j] * lambda) : lambda);
    if (r.force[uj].norm() > c[j] * (1.0 + 1e-12)) return false;
  }
  r.delta_v = dv;
  r.anchor = k;
  return true;
}

/// Non-parallel planes, candidate "all dynamic": Newton in 3-D on ½a‖Δv‖² + Σ c_i‖P_i(u_i + Δv)‖
/// from `start`, valid when no contact ends stuck.
bool try_general_dynamic(std::span<const FrictionContact> contacts, double a, const double* c,
                         const Mat3* P, double speed_eps, const Vec3& start, FrictionResult& r) {
  const int m = static_cast<int>(contacts.size());
  const auto slip = [&](int i, const Vec3& dv) {
    return Vec3(P[i] * (contacts[static_cast<std::size_t>(i)].relative_velocity + dv));
  };
  const auto objective = [&](const Vec3& dv) {
    double f = 0.5 * a * dv.squaredNorm();
    for (int i = 0; i < m; ++i) f += c[i] * slip(i, dv).norm();
    return f;
  };
  // Gradient (and Hessian); false at a kink.
  const auto gradient = [&](const Vec3& dv, Vec3& g, Mat3* H) {
    g = a * dv;
    if (H) *H = a * Mat3::Identity();
    for (int i = 0; i < m; ++i) {
      if (c[i] <= 0.0) continue;
      const Vec3 w = slip(i, dv);
      const double s = w.norm();
      if (s <= speed_eps) return false;
      g += c[i] * w / s;
      if (H) *H += (c[i] / s) * (P[i] - w * w.transpose() / (s * s));
    }
    return true;
  };
  Vec3 dv = start, g;
  Mat3 H;
  double scale = 1e-300;  // the problem's force scale
  for (int i = 0; i < m; ++i) scale = std::max({scale, c[i], a * slip(i, Vec3::Zero()).norm()});
  // A start on a kink (a contact stuck, as Gauss–Seidel often leaves one) is moved off it in a
  // generic direction: the kinks are lines along the normals.
  if (!gradient(dv, g, nullptr))
    dv += 1e-6 * (1.0 + dv.norm()) * Vec3(1.0, std::sqrt(2.0), std::sqrt(3.0)).normalized();
  for (int iter = 0; iter < 50; ++iter) {
    if (!gradient(dv, g, &H)) return false;
    if (g.norm() <= 1e-15 * scale) break;
    const Vec3 step = -H.ldlt().solve(g);
    const double f0 = objective(dv), g0 = g.norm();
    double t = 1.0;
    for (; t > 1e-12; t *= 0.5) {
      Vec3 g_new;
      const Vec3 trial = dv + t * step;
      if (!gradient(trial, g_new, nullptr)) continue;
      const double f = objective(trial);
      const bool resolvable = std::abs(f - f0) > 1e-13 * std::abs(f0);
      if (resolvable ? f <= f0 + 1e-4 * t * g.dot(step) : g_new.norm() < (1.0 - 1e-4 * t) * g0)
        break;
    }
    if (t <= 1e-12) break;
    dv += t * step;
  }
  if (!gradient(dv, g, nullptr)) return false;
  for (int i = 0; i < m; ++i) {
    const Vec3 w = slip(i, dv);
    const double s = w.norm();
    r.force[static_cast<std::size_t>(i)] = s > 0.0 ? Vec3(-c[i] * w / s) : Vec3::Zero();
    r.sticking[static_cast<std::size_t>(i)] = false;
  }
  r.delta_v = dv;
  return true;
}

/// Parallel planes, candidate "all dynamic": the 3-D Newton above with the common plane for
/// every contact. Newton alone can stall near a kink it does not end at, so it starts from the
/// block Gauss–Seidel answer and only polishes it.
bool try_all_dynamic(const Problem& p, std::span<const FrictionContact> contacts,
                     FrictionResult& r) {
  FrictionResult start;
  solve_general(contacts, p.a, &p.P, start);
  std::array<Mat3, kMaxVertexContacts> P;
  P.fill(p.P);
  if (!try_general_dynamic(contacts, p.a, p.c.data(), P.data(), p.speed_eps, start.delta_v, r))
    return false;
  r.which = FrictionCase::all_dynamic;
  return true;
}

}  // namespace

FrictionResult solve_friction(std::span<const FrictionContact> contacts, double mass, double h,
                              double coplanar_sin) {
  DEXCLOTH_DEMAND(contacts.size() <= static_cast<std::size_t>(kMaxVertexContacts));
  DEXCLOTH_DEMAND(mass > 0.0 && h > 0.0);
  FrictionResult r;
  Problem p;
  p.count = static_cast<int>(contacts.size());
  p.a = mass / h;
  double capacity = 0.0;
  Vec3 n0 = Vec3::UnitZ();
  const bool parallel = common_normal(contacts, std::max(coplanar_sin, kParallelSin), n0);
  p.P = tangent_projector(n0);
  double max_speed = 0.0;
  for (int i = 0; i < p.count; ++i) {
    p.c[i] = contacts[i].mu * contacts[i].normal_force;
    capacity += p.c[i];
    p.u[i] = p.P * contacts[i].relative_velocity;
    max_speed = std::max(max_speed, p.u[i].norm());
  }
  p.speed_eps = 1e-14 + 1e-12 * max_speed;
  if (capacity <= 0.0) return r;  // no friction: fT = 0

  // Each contact's plane (the common one for parallel planes), and the static candidates in the
  // order of the paper's heuristic μ‖fN‖ − m‖v_r‖/h (eq. 7), largest margin first.
  std::array<Mat3, kMaxVertexContacts> P;
  std::array<int, kMaxVertexContacts> order{};
  std::array<double, kMaxVertexContacts> margin{};
  for (int i = 0; i < p.count; ++i) {
    P[i] = parallel ? p.P : tangent_projector(contacts[i].normal);
    margin[i] = p.c[i] - p.a * (P[i] * contacts[i].relative_velocity).norm();
    int j = i;  // insertion sort (M is tiny)
    for (; j > 0 && margin[order[j - 1]] < margin[i]; --j) order[j] = order[j - 1];
    order[j] = i;
  }
  const double scale = force_scale(p);
  // Every checked candidate is measured; when none passes, the least violating one is the
  // answer. Near a double kink (two contacts all but stuck, their lines of sticking a hair
  // apart, as at a fold's symmetric crease) a static candidate can miss the tolerance by
  // rounding alone, while the dual refinement, flat along the forces that cancel, ends far off.
  FrictionResult best;
  double best_violation = std::numeric_limits<double>::infinity();
  const auto passes = [&](const FrictionResult& candidate) {
    const double v = friction_violation(contacts, mass, h, candidate, coplanar_sin);
    if (v < best_violation) {
      best = candidate;
      best_violation = v;
    }
    return v <= 1e-9 * scale;
  };
  bool found = false;
  if (!parallel) {
    // Candidates in 3-D, as for parallel planes: the block Gauss–Seidel answer, static at k,
    // then all dynamic from that answer, each checked.
    solve_general(contacts, p.a, nullptr, r);
    found = passes(r);
    for (int k = 0; k < p.count && !found; ++k) {
      if (p.c[order[k]] <= 0.0) continue;
      FrictionResult candidate;
      if (try_general_static_at(contacts, p.a, p.c.data(), P.data(), p.speed_eps, order[k],
                                candidate) &&
          passes(candidate)) {
        r = candidate;
        found = true;
      }
    }
    FrictionResult candidate;
    if (!found &&
        try_general_dynamic(contacts, p.a, p.c.data(), P.data(), p.speed_eps, r.delta_v,
                            candidate) &&
        passes(candidate)) {
      r = candidate;
      found = true;
    }
    r.which = FrictionCase::general;
  } else {
    // Static candidates (exact by construction), then all dynamic, checked.
    for (int k = 0; k < p.count && !found; ++k) {
      FrictionResult candidate;
      if (try_static_at(p, order[k], candidate)) {
        r = candidate;
        found = true;
      }
    }
    FrictionResult candidate;
    if (!found && try_all_dynamic(p, contacts, candidate) && passes(candidate)) {
      r = candidate;
      found = true;
    }
    if (!found) {
      solve_general(contacts, p.a, &p.P, r);
      passes(r);
    }
  }
  if (!found) {
    // No candidate passed: refine the dual answer and let the 3-D Newton polish its Δv. The
    // least violating answer of all stays. The contacts left not sliding (to the check's
    // tolerance) stick.
    refine_dual(contacts, p.a, P.data(), p.c.data(), passes, r);
    passes(r);
    FrictionResult polished;
    if (try_general_dynamic(contacts, p.a, p.c.data(), P.data(), p.speed_eps, r.delta_v,
                            polished))
      passes(polished);
    r = best;
    r.which = parallel ? FrictionCase::all_dynamic : FrictionCase::general;
    r.anchor = -1;
    double held = 0.0;
    for (int i = 0; i < p.count; ++i) {
      const double slip = (P[i] * (contacts[i].relative_velocity + r.delta_v)).norm();
      r.sticking[i] = p.c[i] > 0.0 && p.a * slip <= 1e-9 * scale;
      // With parallel planes the vertex moving with a contact is "static at" it.
      if (parallel && r.sticking[i] && p.c[i] > held) {
        held = p.c[i];
        r.which = FrictionCase::static_at;
        r.anchor = i;
      }
    }
  }
  r.violation = friction_violation(contacts, mass, h, r, coplanar_sin) / scale;
  r.ok = r.violation <= 1e-9;
  return r;
}

double friction_violation(std::span<const FrictionContact> contacts, double mass, double h,
                          const FrictionResult& r, double coplanar_sin) {
  const double a = mass / h;
  Vec3 common = Vec3::Zero();
  const bool coplanar = common_normal(contacts, std::max(coplanar_sin, kParallelSin), common);
  Vec3 sum = Vec3::Zero();
  double worst = 0.0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const double c = contacts[i].mu * contacts[i].normal_force;
    const Vec3& f = r.force[i];
    sum += f;
    const Vec3 normal = coplanar ? common : Vec3(contacts[i].normal.normalized());
    const Vec3 w = tangent_projector(normal) * (contacts[i].relative_velocity + r.delta_v);
    const double fn = f.norm();
    // Cone, complementarity (as a force), and a sliding force opposing the sliding.
    worst = std::max(worst, fn - c);
    worst = std::max(worst, std::abs(c - fn) * std::min(1.0, a * w.norm() / (c + 1e-300)));
    if (a * w.norm() > 1e-9 * (c + 1e-300))
      worst = std::max(worst, (f + c * w.normalized()).norm());
    worst = std::max(worst, std::abs(f.dot(normal)));
  }
  return std::max(worst, (a * r.delta_v - sum).norm());
}

}  // namespace dexcloth::coupling
