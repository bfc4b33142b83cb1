#pragma once
/// Small meshes for the collision tests: sheets, boxes, spheres.
#include "cloth/collision/collision_mesh.hpp"

namespace dexcloth::collision::testing {

/// Cloth sheet in the plane z = origin.z: nx × ny quads (two triangles each) over
/// size_x × size_y [m] starting at `origin`; x1 = x0; every vertex weighs `vertex_mass` [kg].
CollisionMesh make_sheet(int nx, int ny, double size_x, double size_y, const Vec3& origin,
                         double vertex_mass);

/// Static obstacle box [lo, hi] as 12 outward-facing triangles; x1 = x0.
CollisionMesh make_box(const Vec3& lo, const Vec3& hi);

/// One obstacle mesh made of `a` and then `b` (as a body with two shapes: two pieces, which may
/// overlap).
CollisionMesh join_obstacles(const CollisionMesh& a, const CollisionMesh& b);

/// Static obstacle UV sphere (`rings` latitude bands, `segments` longitudes); x1 = x0.
CollisionMesh make_sphere(const Vec3& centre, double radius, int rings, int segments);

}  // namespace dexcloth::collision::testing
