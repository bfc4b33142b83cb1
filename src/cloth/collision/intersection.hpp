#pragma once
/// Exact triangle–triangle intersection (closed triangles, exact orientation predicates), and the
/// intersection count used to check that collision handling left no interpenetration.
#include <vector>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/collision_mesh.hpp"
#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::collision {

/// True when closed segment (p, q) and closed triangle (a, b, c) share a point; exact, including
/// a segment lying in the triangle's plane. A zero-area triangle intersects nothing.
bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                 const Vec3& c);

/// True when closed triangles (a0, a1, a2) and (b0, b1, b2) share a point [exact; touching at a
/// vertex or an edge counts; coplanar overlap counts]. Zero-area triangles never intersect.
bool triangles_intersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                         const Vec3& b1, const Vec3& b2);

/// Number of intersecting triangle pairs at x0 (`use_x1` false) or x1 (`use_x1` true): within
/// each cloth mesh with self-collision on (pairs sharing a vertex are skipped), between cloth
/// meshes, and between cloth and obstacle meshes; obstacle–obstacle pairs are ignored. Builds its
/// own BVHs (diagnostic use). With a `pool`, large searches run on its threads (same count).
int count_intersections(const std::vector<const CollisionMesh*>& meshes, bool use_x1,
                        WorkerPool* pool = nullptr);
/// The same with the meshes' BVHs kept in `trees` from one call to the next (a recording's
/// frames): a mesh's tree is refit to its positions, or built anew where its number of faces
/// changed. Any tree over a mesh's faces finds the same pairs, so the count is the same.
int count_intersections(const std::vector<const CollisionMesh*>& meshes, bool use_x1,
                        std::vector<Bvh>& trees, WorkerPool* pool = nullptr);

}  // namespace dexcloth::collision
