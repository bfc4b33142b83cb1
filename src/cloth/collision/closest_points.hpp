#pragma once
/// Closest points between the primitives of collision handling: point–triangle and
/// segment–segment (Ericson, Real-Time Collision Detection, §5.1.5 and §5.1.9).
#include "core/types.hpp"

namespace dexcloth::collision {

/// Barycentric weights (wa, wb, wc), summing to 1, of the point of triangle (a, b, c) closest to
/// `p`; degenerate triangles fall back to the closest point on their edges.
Vec3 closest_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Parameters (s, u) ∈ [0,1]² of the closest points p0 + s(p1 − p0) and q0 + u(q1 − q0) of two
/// segments; parallel and degenerate segments are handled (some closest pair is returned).
Vec2 closest_points_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

}  // namespace dexcloth::collision
