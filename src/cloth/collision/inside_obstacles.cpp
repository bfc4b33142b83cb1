#include "cloth/collision/inside_obstacles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "cloth/collision/closest_points.hpp"

namespace dexcloth::collision {

double winding_number(const Points& x, const Triangles& faces, const Vec3& p) {
  // Signed solid angle of each triangle seen from p (Van Oosterom & Strackee 1983).
  double total = 0.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = x.row(faces(f, 0)).transpose() - p;
    const Vec3 b = x.row(faces(f, 1)).transpose() - p;
    const Vec3 c = x.row(faces(f, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * std::numbers::pi);
}

namespace {

/// A closed piece of an obstacle mesh (a body's shapes are appended as separate pieces): its
/// faces, bounds, and whether it is convex (then a point is inside iff behind every face).
struct Piece {
  Triangles faces;  ///< its faces, as rows of the obstacle's
  Vec3 lo{Vec3::Constant(std::numeric_limits<double>::infinity())};
  Vec3 hi{Vec3::Constant(-std::numeric_limits<double>::infinity())};
  bool convex{true};
};

Vec3 corner(const Points& x, const Triangles& faces, Eigen::Index f, int k) {
  return x.row(faces(f, k)).transpose();
}

/// The obstacle's pieces at x1: faces joined by shared vertices.
std::vector<Piece> pieces_of(const CollisionMesh& obstacle) {
  const auto nv = static_cast<std::size_t>(obstacle.x1.rows());
  std::vector<int> parent(nv);
  for (std::size_t v = 0; v < nv; ++v) parent[v] = static_cast<int>(v);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  for (Eigen::Index f = 0; f < obstacle.faces.rows(); ++f)
    for (int k = 1; k < 3; ++k)
      parent[static_cast<std::size_t>(root(obstacle.faces(f, k)))] = root(obstacle.faces(f, 0));
  // Each face's piece, then each piece's faces in the obstacle's order.
  std::vector<int> piece_of_root(nv, -1), piece_of_face;
  std::vector<Eigen::Index> count;
  for (Eigen::Index f = 0; f < obstacle.faces.rows(); ++f) {
    int& index = piece_of_root[static_cast<std::size_t>(root(obstacle.faces(f, 0)))];
    if (index < 0) {
      index = static_cast<int>(count.size());
      count.push_back(0);
    }
    piece_of_face.push_back(index);
    ++count[static_cast<std::size_t>(index)];
  }
  std::vector<Piece> pieces(count.size());
  for (std::size_t k = 0; k < count.size(); ++k) pieces[k].faces.resize(count[k], 3);
  std::fill(count.begin(), count.end(), 0);
  for (Eigen::Index f = 0; f < obstacle.faces.rows(); ++f) {
    const auto k = static_cast<std::size_t>(piece_of_face[static_cast<std::size_t>(f)]);
    Piece& piece = pieces[k];
    piece.faces.row(count[k]++) = obstacle.faces.row(f);
    for (int c = 0; c < 3; ++c) {
      piece.lo = piece.lo.cwiseMin(corner(obstacle.x1, obstacle.faces, f, c));
      piece.hi = piece.hi.cwiseMax(corner(obstacle.x1, obstacle.faces, f, c));
    }
  }
  // Convex: every corner of the piece on or behind every face's plane (to rounding).
  const Points& x = obstacle.x1;
  for (Piece& piece : pieces) {
    const double tolerance = 1e-9 * (piece.hi - piece.lo).norm();
    for (Eigen::Index f = 0; f < piece.faces.rows() && piece.convex; ++f) {
      const Vec3 a = corner(x, piece.faces, f, 0);
      const Vec3 n = (corner(x, piece.faces, f, 1) - a).cross(corner(x, piece.faces, f, 2) - a);
      if (n.squaredNorm() == 0.0) continue;
      const Vec3 u = n.normalized();
      for (Eigen::Index g = 0; g < piece.faces.rows() && piece.convex; ++g)
        for (int k = 0; k < 3; ++k)
          if (u.dot(corner(x, piece.faces, g, k) - a) > tolerance) piece.convex = false;
    }
  }
  return pieces;
}

/// Whether `p` is inside `piece` of `obstacle` (strictly behind every face of a convex piece,
/// else a winding number above ½).
bool inside_piece(const CollisionMesh& obstacle, const Piece& piece, const Vec3& p) {
  if ((p.array() < piece.lo.array()).any() || (p.array() > piece.hi.array()).any()) return false;
  const Points& x = obstacle.x1;
  if (piece.convex) {
    for (Eigen::Index f = 0; f < piece.faces.rows(); ++f) {
      const Vec3 a = corner(x, piece.faces, f, 0);
      const Vec3 n = (corner(x, piece.faces, f, 1) - a).cross(corner(x, piece.faces, f, 2) - a);
      // In front of a face: outside (a degenerate face has no front).
      if (n.dot(p - a) >= 0.0 && n.squaredNorm() > 0.0) return false;
    }
    return true;
  }
  return winding_number(x, piece.faces, p) > 0.5;
}

bool inside_any(const CollisionMesh& obstacle, const std::vector<Piece>& pieces, const Vec3& p) {
  return std::any_of(pieces.begin(), pieces.end(),
                     [&](const Piece& piece) { return inside_piece(obstacle, piece, p); });
}

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
                                   const std::vector<Piece>* outer = nullptr, double offset = 0.0) {
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
    if (d < best.distance && outer && inside_any(obstacle, *outer, q + offset * n.normalized()))
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
  // Each directed edge once, and its reverse present: every edge shared by two faces that
  // traverse it in opposite directions.
  std::vector<std::uint64_t> edges;
  edges.reserve(static_cast<std::size_t>(3 * faces.rows()));
  const auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
  };
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges.push_back(key(faces(f, k), faces(f, (k + 1) % 3)));
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  for (const std::uint64_t e : edges) {
    const auto a = static_cast<int>(e >> 32), b = static_cast<int>(e & 0xffffffffu);
    if (!std::binary_search(edges.begin(), edges.end(), key(b, a))) return false;
  }
  return !edges.empty();
}

InsideReport push_out_of_obstacles(const std::vector<CollisionMesh*>& meshes, double offset) {
  InsideReport report;
  for (const CollisionMesh* obstacle : meshes) {
    if (!obstacle->obstacle) continue;
    const Points& ox = obstacle->x1;
    const Vec3 lo = ox.colwise().minCoeff().transpose(), hi = ox.colwise().maxCoeff().transpose();
    // Looked at when a cloth vertex is first within the bounds: only a closed body has an inside
    // (an open mesh, a cup, would claim its hollow), then its pieces.
    bool looked = false, closed = false;
    std::vector<Piece> pieces;
    for (CollisionMesh* cloth : meshes) {
      if (cloth->obstacle) continue;
      for (Eigen::Index v = 0; v < cloth->x1.rows(); ++v) {
        if (is_fixed(*cloth, static_cast<int>(v)) && !held_by_friction(*cloth, static_cast<int>(v)))
          continue;
        const Vec3 p = cloth->x1.row(v).transpose();
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
        if (!looked) {
          looked = true;
          closed = closed_and_oriented(obstacle->faces);
          if (closed) pieces = pieces_of(*obstacle);
        }
        if (!closed) break;
        if (!inside_any(*obstacle, pieces, p)) continue;
        SurfacePoint s = closest_surface_point(*obstacle, p);
        if (pieces.size() > 1 && inside_any(*obstacle, pieces, s.point + offset * s.normal))
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
