#include "cloth/collision/polynomial_roots.hpp"

#include <algorithm>
#include <cmath>

namespace dexcloth::collision {

int quadratic_roots(double c0, double c1, double c2, std::array<double, 2>& roots) {
  if (c2 == 0.0) {
    if (c1 == 0.0) return 0;
    roots[0] = -c0 / c1;
    return 1;
  }
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc < 0.0) return 0;
  // q = −(c1 + sign(c1)·√disc)/2 avoids cancellation; roots q/c2 and c0/q.
  const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
  if (q == 0.0) {  // c1 = 0 and c0 = 0: double root at 0
    roots[0] = 0.0;
    return 1;
  }
  double r0 = q / c2, r1 = c0 / q;
  if (r0 > r1) std::swap(r0, r1);
  roots[0] = r0;
  roots[1] = r1;
  return r0 == r1 ? 1 : 2;
}

namespace {

double eval(const std::array<double, 4>& c, double t) {
  return ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
}

double eval_derivative(const std::array<double, 4>& c, double t) {
  return (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1];
}

// Root of a monotone p on [lo, hi] with p(lo)·p(hi) < 0: Newton steps kept inside the bracket,
// bisection otherwise, until the bracket cannot shrink.
double refine_root(const std::array<double, 4>& c, double lo, double hi, double plo) {
  double t = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double pt = eval(c, t);
    if (pt == 0.0) return t;
    if ((pt < 0.0) == (plo < 0.0)) {
      lo = t;
      plo = pt;
    } else {
      hi = t;
    }
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;  // bracket is two adjacent doubles
    const double dp = eval_derivative(c, t);
    double next = dp != 0.0 ? t - pt / dp : mid;
    if (!(next > lo && next < hi)) next = mid;
    // Newton stalled inside the bracket: bisect instead.
    if (std::abs(next - t) < 1e-3 * (hi - lo) && it % 4 == 3) next = mid;
    t = next;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

int cubic_candidates(const std::array<double, 4>& c, double near_zero, CubicCandidates& out) {
  // Split [0,1] at the derivative's roots: p′ = c1 + 2c2·t + 3c3·t².
  std::array<double, 4> split{};
  int ns = 0;
  split[static_cast<std::size_t>(ns++)] = 0.0;
  std::array<double, 2> crit{};
  const int nc = quadratic_roots(c[1], 2.0 * c[2], 3.0 * c[3], crit);
  for (int i = 0; i < nc; ++i)
    if (crit[static_cast<std::size_t>(i)] > 0.0 && crit[static_cast<std::size_t>(i)] < 1.0)
      split[static_cast<std::size_t>(ns++)] = crit[static_cast<std::size_t>(i)];
  split[static_cast<std::size_t>(ns++)] = 1.0;

  int n = 0;
  auto push = [&](double t) {
    if (n > 0 && out[static_cast<std::size_t>(n - 1)] == t) return;
    out[static_cast<std::size_t>(n++)] = t;
  };
  double plo = eval(c, 0.0);
  for (int i = 0; i + 1 < ns; ++i) {
    const double lo = split[static_cast<std::size_t>(i)];
    const double hi = split[static_cast<std::size_t>(i + 1)];
    const double phi = eval(c, hi);
    // Split points touching zero (roots at the ends, tangential touches).
    if (std::abs(plo) <= near_zero || plo == 0.0) push(lo);
    if ((plo < 0.0 && phi > 0.0) || (plo > 0.0 && phi < 0.0)) push(refine_root(c, lo, hi, plo));
    plo = phi;
  }
  if (std::abs(plo) <= near_zero || plo == 0.0) push(1.0);
  return n;
}

}  // namespace dexcloth::collision
