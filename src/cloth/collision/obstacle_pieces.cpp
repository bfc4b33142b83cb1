#include "cloth/collision/obstacle_pieces.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "cloth/collision/collision_mesh.hpp"

namespace dexcloth::collision {

namespace {

Vec3 corner(const Points& x, const Triangles& faces, Eigen::Index f, int k) {
  return x.row(faces(f, k)).transpose();
}

/// Signed solid angle of triangle f seen from p, times 2 (Van Oosterom & Strackee 1983).
double solid_angle(const Points& x, const Triangles& faces, Eigen::Index f, const Vec3& p) {
  const Vec3 a = corner(x, faces, f, 0) - p, b = corner(x, faces, f, 1) - p,
             c = corner(x, faces, f, 2) - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace

double winding_number(const Points& x, const Triangles& faces, const Vec3& p) {
  double total = 0.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) total += solid_angle(x, faces, f, p);
  return total / (4.0 * std::numbers::pi);
}

std::span<const int> ObstaclePieces::faces_of(int k) const {
  const auto first =
      static_cast<std::size_t>(m_topology->piece_face_start[static_cast<std::size_t>(k)]);
  const auto end =
      static_cast<std::size_t>(m_topology->piece_face_start[static_cast<std::size_t>(k) + 1]);
  return std::span<const int>(m_topology->piece_faces).subspan(first, end - first);
}

void ObstaclePieces::update(const Points& x, const Triangles& faces, const MeshTopology& topology) {
  m_x = &x;
  m_faces = &faces;
  m_topology = &topology;
  m_pieces.clear();
  if (!topology.closed) return;
  m_pieces.resize(static_cast<std::size_t>(topology.pieces()));
  const double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < size(); ++k) {
    Piece& piece = m_pieces[static_cast<std::size_t>(k)];
    piece.lo.setConstant(inf);
    piece.hi.setConstant(-inf);
    for (const int f : faces_of(k))
      for (int c = 0; c < 3; ++c) {
        piece.lo = piece.lo.cwiseMin(corner(x, faces, f, c));
        piece.hi = piece.hi.cwiseMax(corner(x, faces, f, c));
      }
    // Convex: at every edge the other face's far corner is on or behind this face's plane (to
    // rounding). On a closed surface that holds everywhere only when the surface is convex.
    const double tolerance = 1e-9 * (piece.hi - piece.lo).norm();
    for (const int f : faces_of(k)) {
      const Vec3 n = face_normal(x, faces, f);
      if (n.squaredNorm() == 0.0) continue;
      const Vec3 u = n.normalized(), a = corner(x, faces, f, 0);
      for (int e = 0; e < 3 && piece.convex; ++e) {
        const std::array<int, 2>& across = topology.edge_faces[static_cast<std::size_t>(
            topology.face_edges[static_cast<std::size_t>(f)][static_cast<std::size_t>(e)])];
        const int g = across[0] == f ? across[1] : across[0];
        for (int c = 0; c < 3; ++c)
          if (u.dot(corner(x, faces, g, c) - a) > tolerance) piece.convex = false;
      }
      if (!piece.convex) break;
    }
  }
}

bool ObstaclePieces::inside(int k, const Vec3& p, double margin) const {
  const Piece& piece = m_pieces[static_cast<std::size_t>(k)];
  if ((p.array() < piece.lo.array() + margin).any() ||
      (p.array() > piece.hi.array() - margin).any())
    return false;
  const Points& x = *m_x;
  const Triangles& faces = *m_faces;
  if (piece.convex) {
    for (const int f : faces_of(k)) {
      const Vec3 n = face_normal(x, faces, f);
      // On or in front of a face (less than `margin` behind it): outside. A degenerate face
      // has no front.
      if (n.dot(p - corner(x, faces, f, 0)) >= -margin * n.norm() && n.squaredNorm() > 0.0)
        return false;
    }
    return true;
  }
  double total = 0.0;
  for (const int f : faces_of(k)) total += solid_angle(x, faces, f, p);
  return total / (4.0 * std::numbers::pi) > 0.5;
}

bool ObstaclePieces::inside_other(int own, const Vec3& p, double margin) const {
  for (int k = 0; k < size(); ++k)
    if (k != own && inside(k, p, margin)) return true;
  return false;
}

}  // namespace dexcloth::collision
