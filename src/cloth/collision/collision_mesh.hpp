#pragma once
/// The plain-array mesh every collision routine works on (cloth or obstacle, one step's motion).
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace dexcloth::collision {

/// CollisionMesh::frozen value of a vertex held in place by static friction (not a handle).
inline constexpr std::uint8_t kHeldByFriction = 2;

/// One triangle mesh taking part in collision handling for a step.
/// Velocities are implied: v = (x1 − x0)/h. Obstacles carry their prescribed motion x0 → x1.
struct CollisionMesh {
  Points x0;                         ///< |V|×3 positions at the start of the step [m]
  Points x1;                         ///< |V|×3 candidate positions at the end of the step [m]
                                     ///< (modified by responses)
  Triangles faces;                   ///< |F|×3 vertex indices
  Eigen::VectorXd mass;              ///< |V| vertex masses [kg] (ignored for obstacles)
  std::vector<std::uint8_t> frozen;  ///< |V| nonzero = position constrained: responses never
                                     ///< move it (1: handles), except that the impact zones let
                                     ///< go of a vertex held by static friction
                                     ///< (kHeldByFriction) when an obstacle runs into it;
                                     ///< empty = none frozen
  /// |V|×3 rest positions of a cloth [m], or empty (obstacles): two of its primitives closer
  /// than a fold's length at rest are never in contact with each other (see find_proximities).
  Points rest;
  bool obstacle{false};              ///< infinitely heavy, never moved, no self-collision
  /// An obstacle whose pairs with cloth the proximity search takes out to its obstacle reach,
  /// beyond the thickness (find_proximities): one the cloth never pushes.
  bool beyond_thickness{false};
  bool self_collision{true};         ///< a cloth's contacts with itself are handled (false: it
                                     ///< may pass through itself; other meshes still collide)
  double friction{0.5};              ///< Coulomb μ of this mesh's surface [-]
};

/// Checks the shapes of `mesh` (x0, x1, mass, frozen sizes, face indices in range, positive masses
/// of cloth vertices, rest rows 0 or |V|); always on, since a wrong shape is a programmer error in
/// the caller.
void demand_valid(const CollisionMesh& mesh);

/// True when the proximity search takes `mesh`'s pairs with cloth out to its obstacle reach.
inline bool searched_beyond_thickness(const CollisionMesh& mesh) {
  return mesh.obstacle && mesh.beyond_thickness;
}

/// True when responses must not move vertex `v`: obstacle meshes and frozen vertices.
inline bool is_fixed(const CollisionMesh& mesh, int v) {
  return mesh.obstacle || (!mesh.frozen.empty() && mesh.frozen[static_cast<std::size_t>(v)] != 0);
}

/// True when vertex `v` is held in place by static friction only (the impact zones may let it go).
inline bool held_by_friction(const CollisionMesh& mesh, int v) {
  return !mesh.obstacle && !mesh.frozen.empty() &&
         mesh.frozen[static_cast<std::size_t>(v)] == kHeldByFriction;
}

/// Inverse mass of vertex `v` [1/kg]; 0 for fixed vertices (infinite mass).
inline double inverse_mass(const CollisionMesh& mesh, int v) {
  return is_fixed(mesh, v) ? 0.0 : 1.0 / mesh.mass[v];
}

/// Normal of face `f` of (`x`, `faces`), twice the face's area long; on a closed obstacle, whose
/// faces run counter-clockwise seen from outside, it points out.
inline Vec3 face_normal(const Points& x, const Triangles& faces, Eigen::Index f) {
  const Vec3 a = x.row(faces(f, 0)).transpose();
  const Vec3 b = x.row(faces(f, 1)).transpose(), c = x.row(faces(f, 2)).transpose();
  return (b - a).cross(c - a);
}

/// Friction coefficient of a contact between two surfaces: √(μa·μb) [-].
inline double pair_friction(const CollisionMesh& a, const CollisionMesh& b) {
  return std::sqrt(a.friction * b.friction);
}

}  // namespace dexcloth::collision
