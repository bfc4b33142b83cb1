#include "cloth/collision/ccd.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/collision/closest_points.hpp"
#include "cloth/collision/polynomial_roots.hpp"

namespace dexcloth::collision {

namespace {

enum class Kind { VertexFace, EdgeEdge };

// Smallest |n·ĝ0| (cosine between the geometric normal and the start gap) for which the
// geometric normal is reported; below it the start gap's direction is [-].
constexpr double kMinNormalAlignment = 0.2;

Corners at_time(const Corners& x0, const Corners& x1, double t) {
  Corners x;
  for (std::size_t k = 0; k < 4; ++k) x[k] = t == 1.0 ? x1[k] : x0[k] + t * (x1[k] - x0[k]);
  return x;
}

// Signed corner weights of the closest points, and the gap vector they give.
Eigen::Vector4d closest_weights(Kind kind, const Corners& x) {
  if (kind == Kind::VertexFace) {
    const Vec3 b = closest_point_triangle(x[0], x[1], x[2], x[3]);
    return {1.0, -b[0], -b[1], -b[2]};
  }
  const Vec2 su = closest_points_segments(x[0], x[1], x[2], x[3]);
  return {1.0 - su[0], su[0], -(1.0 - su[1]), -su[1]};
}

Vec3 gap(const Eigen::Vector4d& w, const Corners& x) {
  return w[0] * x[0] + w[1] * x[1] + w[2] * x[2] + w[3] * x[3];
}

// Geometric normal of the configuration: face normal, or the edges' common perpendicular.
Vec3 geometric_normal(Kind kind, const Corners& x) {
  return kind == Kind::VertexFace ? Vec3((x[2] - x[1]).cross(x[3] - x[1]))
                                  : Vec3((x[1] - x[0]).cross(x[3] - x[2]));
}

// Any unit vector perpendicular to `e` (or +z for a zero `e`).
Vec3 perpendicular(const Vec3& e) {
  if (e.squaredNorm() == 0.0) return Vec3::UnitZ();
  Vec3 axis = Vec3::Zero();
  int k = 0;
  e.cwiseAbs().minCoeff(&k);
  axis[k] = 1.0;
  return e.cross(axis).normalized();
}

// Unit normal of the plane the pair stays in when its cubic vanishes identically.
Vec3 degenerate_plane_normal(Kind kind, const Corners& x0, const Corners& x1) {
  for (const Corners* x : {&x0, &x1}) {
    const Vec3 n = geometric_normal(kind, *x);
    if (n.squaredNorm() > 0.0) return n.normalized();
  }
  // Parallel edges or collinear face: the plane through the first edge and a corner off it.
  const Corners& x = x0;
  const Vec3 e = kind == Kind::VertexFace ? Vec3(x[2] - x[1]) : Vec3(x[1] - x[0]);
  const Vec3 base = kind == Kind::VertexFace ? x[1] : x[0];
  for (std::size_t k = 0; k < 4; ++k) {
    const Vec3 n = e.cross(x[k] - base);
    if (n.squaredNorm() > 1e-24 * e.squaredNorm() * (x[k] - base).squaredNorm()) return n.normalized();
  }
  return perpendicular(e);
}

// Coefficients of det(x1 − x0, x2 − x0, x3 − x0)(t) for the linear motion (VF uses a as origin
// via the corner order, see callers).
std::array<double, 4> coplanarity_cubic(const Vec3& e10, const Vec3& e20, const Vec3& e30,
                                        const Vec3& d1, const Vec3& d2, const Vec3& d3) {
  auto det = [](const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); };
  return {det(e10, e20, e30), det(d1, e20, e30) + det(e10, d2, e30) + det(e10, e20, d3),
          det(e10, d2, d3) + det(d1, e20, d3) + det(d1, d2, e30), det(d1, d2, d3)};
}

// Appends the candidate times where point P crosses the line of edge (A, B) inside plane n:
// ((B − A) × (P − A))·n = 0, a quadratic in t.
void crossing_candidates(const Corners& x0, const Corners& x1, std::size_t ia, std::size_t ib,
                         std::size_t ip, const Vec3& n, double near_zero,
                         std::array<double, 64>& times, int& count) {
  const Vec3 u0 = x0[ib] - x0[ia], du = (x1[ib] - x1[ia]) - u0;
  const Vec3 w0 = x0[ip] - x0[ia], dw = (x1[ip] - x1[ia]) - w0;
  const std::array<double, 4> c{u0.cross(w0).dot(n), (u0.cross(dw) + du.cross(w0)).dot(n),
                                du.cross(dw).dot(n), 0.0};
  CubicCandidates roots{};
  int nr = cubic_candidates(c, near_zero, roots);
  for (int i = 0; i < nr && count < 64; ++i) times[static_cast<std::size_t>(count++)] = roots[static_cast<std::size_t>(i)];
  // P stays on the edge's line (collinear motion): contact starts when P passes A or B.
  if (std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])}) > near_zero) return;
  if (u0.squaredNorm() == 0.0) return;
  for (const std::size_t ie : {ia, ib}) {
    const Vec3 r0 = x0[ip] - x0[ie], dr = (x1[ip] - x1[ie]) - r0;
    nr = cubic_candidates({r0.dot(u0), dr.dot(u0), 0.0, 0.0}, 0.0, roots);
    for (int i = 0; i < nr && count < 64; ++i) times[static_cast<std::size_t>(count++)] = roots[static_cast<std::size_t>(i)];
  }
}

std::optional<CcdHit> ccd(Kind kind, const Corners& x0, const Corners& x1, double tolerance) {
  // Conservative early out: the distance can shrink no faster than the largest relative
  // displacement M of a corner of one primitive against a corner of the other, so pairs farther
  // apart than M + tolerance at the start cannot touch (the common case: a sheet moving
  // almost rigidly past its own neighbouring primitives).
  const std::size_t split = kind == Kind::VertexFace ? 1 : 2;
  double reach = 0.0;
  for (std::size_t i = 0; i < split; ++i)
    for (std::size_t j = split; j < 4; ++j)
      reach = std::max(reach, ((x1[i] - x0[i]) - (x1[j] - x0[j])).squaredNorm());
  reach = std::sqrt(reach) + tolerance;
  if (gap(closest_weights(kind, x0), x0).squaredNorm() > reach * reach) return std::nullopt;

  // Origin corner and the three relative vectors whose determinant is the coplanarity cubic.
  const std::size_t o = kind == Kind::VertexFace ? 1 : 0;
  const std::array<std::size_t, 3> rel = kind == Kind::VertexFace
                                             ? std::array<std::size_t, 3>{2, 3, 0}
                                             : std::array<std::size_t, 3>{1, 2, 3};
  Vec3 e[3], d[3];
  double scale = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    e[i] = x0[rel[i]] - x0[o];
    d[i] = (x1[rel[i]] - x1[o]) - e[i];
    scale = std::max({scale, e[i].norm(), (e[i] + d[i]).norm()});
  }
  if (scale == 0.0) scale = 1.0;
  const std::array<double, 4> cubic = coplanarity_cubic(e[0], e[1], e[2], d[0], d[1], d[2]);

  // Candidate times: the cubic's roots and near-roots (t = 0 and t = 1 among them when the pair
  // is within the tolerance there: |cubic| ≤ 2·area·distance ≤ scale²·tolerance).
  std::array<double, 64> times{};
  int count = 0;
  const double near_zero = scale * scale * tolerance;
  const double cubic_size =
      std::max({std::abs(cubic[0]), std::abs(cubic[1]), std::abs(cubic[2]), std::abs(cubic[3])});
  CubicCandidates roots{};
  const int nr = cubic_candidates(cubic, near_zero, roots);
  for (int i = 0; i < nr; ++i) times[static_cast<std::size_t>(count++)] = roots[static_cast<std::size_t>(i)];
  // (Nearly) coplanar for the whole step: a cubic bounded by near_zero on [0,1] has coefficients
  // below 48·near_zero (Chebyshev). Contact then starts when a corner crosses an edge in the plane.
  Vec3 plane_normal = Vec3::Zero();
  if (cubic_size <= 64.0 * near_zero || cubic_size <= 1e-12 * scale * scale * scale) {
    plane_normal = degenerate_plane_normal(kind, x0, x1);
    const double nz = scale * tolerance;
    if (kind == Kind::VertexFace) {
      for (std::size_t k = 0; k < 3; ++k)
        crossing_candidates(x0, x1, 1 + k, 1 + (k + 1) % 3, 0, plane_normal, nz, times, count);
    } else {
      crossing_candidates(x0, x1, 2, 3, 0, plane_normal, nz, times, count);
      crossing_candidates(x0, x1, 2, 3, 1, plane_normal, nz, times, count);
      crossing_candidates(x0, x1, 0, 1, 2, plane_normal, nz, times, count);
      crossing_candidates(x0, x1, 0, 1, 3, plane_normal, nz, times, count);
    }
  }
  std::sort(times.begin(), times.begin() + count);

  // Earliest candidate at which the primitives are within the tolerance.
  for (int i = 0; i < count; ++i) {
    const double t = times[static_cast<std::size_t>(i)];
    const Corners x = at_time(x0, x1, t);
    const Eigen::Vector4d w = closest_weights(kind, x);
    const Vec3 g = gap(w, x);
    const double dist = g.norm();
    if (dist > tolerance) continue;

    CcdHit hit;
    hit.t = t;
    hit.w = w;
    hit.distance = dist;
    // Normal: geometric normal at t; for degenerate configurations the gap or the plane.
    Vec3 n = geometric_normal(kind, x);
    const Vec3 g0 = gap(w, x0), g1 = gap(w, x1);
    if (n.squaredNorm() <= 1e-24 * std::pow(scale, 4)) {
      const Vec3 edge = kind == Kind::VertexFace ? Vec3(x[2] - x[1]) : Vec3(x[1] - x[0]);
      const Vec3 side = g0 - g0.dot(edge) / std::max(edge.squaredNorm(), 1e-300) * edge;
      if (side.squaredNorm() > 1e-24 * scale * scale) n = side;
      else if (plane_normal.squaredNorm() > 0.0) n = plane_normal.cross(edge);
      else n = perpendicular(edge);
      if (n.squaredNorm() == 0.0) n = perpendicular(edge);
    }
    n.normalize();
    // Orientation: the side the pair started on; when it starts on the plane, the side it ends.
    const double s0 = n.dot(g0);
    const double s = std::abs(s0) > 1e-14 * scale ? s0 : n.dot(g1);
    hit.normal = s < 0.0 ? Vec3(-n) : n;
    // A geometric normal nearly perpendicular to the start gap does not say which side the pair
    // came from: the primitives approached within its plane (a vertex meeting an edge, edges
    // meeting end-on in a common plane, in-plane motion). Its sign is then round-off, and two
    // such constraints on one vertex can demand opposite moves. The start gap's direction is
    // the separating direction of such lower-dimensional contacts; every constraint then holds
    // at x0 with a clear margin. (A pair starting within the tolerance has no such direction.)
    const double g0_norm = g0.norm();
    if (g0_norm > 2.0 * tolerance && std::abs(s0) < kMinNormalAlignment * g0_norm)
      hit.normal = g0 / g0_norm;
    return hit;
  }
  return std::nullopt;
}

}  // namespace

std::optional<CcdHit> vertex_face_ccd(const Corners& x0, const Corners& x1, double tolerance) {
  return ccd(Kind::VertexFace, x0, x1, tolerance);
}

std::optional<CcdHit> edge_edge_ccd(const Corners& x0, const Corners& x1, double tolerance) {
  return ccd(Kind::EdgeEdge, x0, x1, tolerance);
}

}  // namespace dexcloth::collision
