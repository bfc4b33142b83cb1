#pragma once
/// Recovery of cloth vertices found inside a rigid body: a vertex that ends a step inside a
/// closed obstacle mesh (an impact zone that could not be resolved and stayed at its start while
/// the body moved on) is put back on the body's surface, so that the next step's repulsion and
/// collision detection see it from the outside instead of holding it in.
#include <vector>

#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/obstacle_pieces.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// True when every edge of `faces` is shared by exactly two faces that run along it in opposite
/// directions (a closed, consistently oriented surface, which has an inside).
bool closed_and_oriented(const Triangles& faces);

/// What push_out_of_obstacles did.
struct InsideReport {
  int vertices{};  ///< cloth vertices found inside an obstacle and moved out
  double depth{};  ///< the deepest of them below the surface [m]
};

/// Moves every movable cloth vertex of `meshes` whose x1 lies inside an obstacle's x1 to the
/// closest point of that obstacle's surface, `offset` [m] out along the closest face's outward
/// normal. An obstacle is looked into piece by piece (faces joined by shared vertices, one per
/// shape of a body): inside a convex piece is behind all its faces, inside another a winding
/// number above ½; a face buried in another piece is not surface. The move is not motion: x0 moves
/// too, so that the step's motion x1 − x0 (the velocity the step leaves) is what it was less any
/// part approaching the surface relative to it. Only closed obstacles (closed_and_oriented) with
/// outward-facing (counter-clockwise) triangles are looked into; frozen vertices (handles) stay
/// where they are.
InsideReport push_out_of_obstacles(const std::vector<CollisionMesh*>& meshes, double offset);

}  // namespace dexcloth::collision
