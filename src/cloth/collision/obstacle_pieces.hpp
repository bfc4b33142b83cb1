#pragma once
/// The inside of a closed obstacle mesh, piece by piece. A body's shapes are appended to its mesh
/// as separate pieces (faces joined by shared vertices); where two overlap (a finger's capsule and
/// the pad box on it), part of each one's surface lies inside the other and is no surface of the
/// body.
#include <span>
#include <vector>

#include "cloth/collision/mesh_topology.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Generalized winding number of the closed triangle mesh (`x`, `faces`, counter-clockwise seen
/// from outside) about point `p`: 1 inside, 0 outside (Jacobson et al. 2013; the sum of the
/// faces' signed solid angles over 4π).
double winding_number(const Points& x, const Triangles& faces, const Vec3& p);

/// The pieces of one closed obstacle mesh at one set of positions: their bounds, and whether each
/// is convex (every edge's two faces bend away from each other), so that a point is inside it
/// when behind all its faces; in another, when its winding number is above ½. Keeps pointers to
/// the positions, faces and topology given to `update`, which must outlive its queries.
class ObstaclePieces {
 public:
  /// The pieces of `faces` (with `topology` built from them) at positions `x`; none when the
  /// mesh is not closed (an open mesh, a cup, has no inside).
  void update(const Points& x, const Triangles& faces, const MeshTopology& topology);

  /// Number of pieces (0: not closed).
  int size() const { return static_cast<int>(m_pieces.size()); }

  /// Whether `p` is inside piece `k`: a convex piece's faces all have `p` more than `margin` [m]
  /// behind their planes; another piece has a winding number above ½ about `p`.
  bool inside(int k, const Vec3& p, double margin = 0.0) const;

  /// Whether `p` is inside any piece but `own` (−1: any piece).
  bool inside_other(int own, const Vec3& p, double margin = 0.0) const;

 private:
  struct Piece {
    Vec3 lo{Vec3::Zero()};
    Vec3 hi{Vec3::Zero()};
    bool convex{true};
  };
  std::span<const int> faces_of(int k) const;

  const Points* m_x{};
  const Triangles* m_faces{};
  const MeshTopology* m_topology{};
  std::vector<Piece> m_pieces;
};

}  // namespace dexcloth::collision
