#include "cloth/collision/closest_points.hpp"

#include <algorithm>

namespace dexcloth::collision {

Vec3 closest_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then the edges, then the interior (Ericson §5.1.5).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double sum = va + vb + vc;
  if (sum > 0.0) {
    const double v = vb / sum, w = vc / sum;
    return {1.0 - v - w, v, w};
  }
  // Degenerate (zero-area) triangle: best of its three edges.
  Vec3 best{1.0, 0.0, 0.0};
  double best_d = (p - a).squaredNorm();
  const Vec3 corners[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const Vec3& e0 = corners[k];
    const Vec3& e1 = corners[(k + 1) % 3];
    const Vec3 e = e1 - e0;
    const double len2 = e.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - e0).dot(e) / len2, 0.0, 1.0) : 0.0;
    const double d = (p - (e0 + s * e)).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best.setZero();
      best[k] = 1.0 - s;
      best[(k + 1) % 3] = s;
    }
  }
  return best;
}

Vec2 closest_points_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // Ericson §5.1.9, with the degenerate and parallel branches.
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double tiny = 1e-30;
  double s = 0.0, u = 0.0;
  if (a <= tiny && e <= tiny) return {0.0, 0.0};
  if (a <= tiny) {
    u = std::clamp(f / e, 0.0, 1.0);
    return {0.0, u};
  }
  const double c = d1.dot(r);
  if (e <= tiny) {
    s = std::clamp(-c / a, 0.0, 1.0);
    return {s, 0.0};
  }
  const double b = d1.dot(d2);
  const double denom = a * e - b * b;
  // Parallel segments: denom is (relatively) zero; any s works, take 0 then fix up.
  s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  u = (b * s + f) / e;
  if (u < 0.0) {
    u = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (u > 1.0) {
    u = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return {s, u};
}

}  // namespace dexcloth::collision
