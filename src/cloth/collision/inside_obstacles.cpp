#include "cloth/collision/inside_obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cloth/collision/closest_points.hpp"

namespace dexcloth::collision {

namespace {

struct SurfacePoint {
  Vec3 point{Vec3::Zero()};
  Vec3 normal{Vec3::UnitZ()};  // outward normal of the closest face
  Vec3 motion{Vec3::Zero()};   // the surface point's motion over the step, x0 → x1 [m]
  double distance{std::numeric_limits<double>::infinity()};
};

/// The closest point to `p` of the obstacle's surface at x1, with its motion from x0; with
/// `outer`, only points that `offset` out along their face's normal are inside no piece (a face
/// of one piece buried in another is not the body's surface).
SurfacePoint closest_surface_point(const CollisionMesh& obstacle, const Vec3& p,
                                   const ObstaclePieces* outer = nullptr, double offset = 0.0) {
  const Points& x = obstacle.x1;
  const Triangles& faces = obstacle.faces;
  SurfacePoint best;
  Eigen::Index closest = -1;
  Vec3 weights = Vec3::Zero();
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = x.row(faces(f, 0)).transpose(), b = x.row(faces(f, 1)).transpose(),
               c = x.row(faces(f, 2)).transpose();
    const Vec3 n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0.0) continue;  // degenerate: no side to push out to
    const Vec3 w = closest_point_triangle(p, a, b, c);
    const Vec3 q = w[0] * a + w[1] * b + w[2] * c;
    const double d = (p - q).norm();
    if (d < best.distance && outer && outer->inside_other(-1, q + offset * n.normalized()))
      continue;
    if (d < best.distance) {
      best = {q, n.normalized(), Vec3::Zero(), d};
      closest = f;
      weights = w;
    }
  }
  if (closest >= 0)
    for (int k = 0; k < 3; ++k) {
      const int c = faces(closest, k);
      best.motion += weights[k] * (obstacle.x1.row(c) - obstacle.x0.row(c)).transpose();
    }
  return best;
}

}  // namespace

bool closed_and_oriented(const Triangles& faces) {
  return faces.rows() > 0 && build_topology(faces, faces.maxCoeff() + 1).closed;
}

InsideReport push_out_of_obstacles(const std::vector<CollisionMesh*>& meshes, double offset) {
  InsideReport report;
  for (const CollisionMesh* obstacle : meshes) {
    if (!obstacle->obstacle) continue;
    const Points& ox = obstacle->x1;
    const Vec3 lo = ox.colwise().minCoeff().transpose(), hi = ox.colwise().maxCoeff().transpose();
    // Looked at when a cloth vertex is first within the bounds: only a closed body has an inside
    // (an open mesh, a cup, would claim its hollow), then its pieces.
    bool looked = false;
    MeshTopology topology;
    ObstaclePieces pieces;
    for (CollisionMesh* cloth : meshes) {
      if (cloth->obstacle) continue;
      for (Eigen::Index v = 0; v < cloth->x1.rows(); ++v) {
        if (is_fixed(*cloth, static_cast<int>(v)) && !held_by_friction(*cloth, static_cast<int>(v)))
          continue;
        const Vec3 p = cloth->x1.row(v).transpose();
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
        if (!looked) {
          looked = true;
          topology = build_topology(obstacle->faces, static_cast<int>(ox.rows()));
          pieces.update(ox, obstacle->faces, topology);
        }
        if (pieces.size() == 0) break;  // not closed
        if (!pieces.inside_other(-1, p)) continue;
        SurfacePoint s = closest_surface_point(*obstacle, p);
        if (pieces.size() > 1 && pieces.inside_other(-1, s.point + offset * s.normal))
          s = closest_surface_point(*obstacle, p, &pieces, offset);
        if (!std::isfinite(s.distance)) continue;
        // Moved, not accelerated: the step's motion keeps its tangential part and loses what
        // approached the surface (inelastically), so x0 moves with x1 and x1 − x0 stays a
        // velocity the vertex had, not the jump out.
        Vec3 motion = (cloth->x1.row(v) - cloth->x0.row(v)).transpose();
        const double approach = (motion - s.motion).dot(s.normal);
        if (approach < 0.0) motion -= approach * s.normal;
        cloth->x1.row(v) = (s.point + offset * s.normal).transpose();
        cloth->x0.row(v) = cloth->x1.row(v) - motion.transpose();
        ++report.vertices;
        report.depth = std::max(report.depth, s.distance);
      }
    }
  }
  return report;
}

}  // namespace dexcloth::collision
