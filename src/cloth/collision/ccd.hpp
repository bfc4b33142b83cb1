#pragma once
/// Continuous collision detection between primitives moving linearly over a step, t ∈ [0,1]:
/// vertex–face and edge–edge (Provot 1997, Bridson et al. 2002): roots of the coplanarity cubic,
/// then a closest-distance test at each candidate time.
#include <array>
#include <optional>

#include "core/types.hpp"

namespace dexcloth::collision {

/// Four corner positions of a primitive pair [m]: vertex–face (p, a, b, c) or edge–edge
/// (p0, p1, q0, q1).
using Corners = std::array<Vec3, 4>;

/// Earliest contact found by a continuous test.
struct CcdHit {
  double t{};              ///< contact time as a fraction of the step, in [0,1] [-]
  Eigen::Vector4d w{Eigen::Vector4d::Zero()};  ///< signed corner weights: the gap vector is
                           ///< d(t) = Σ w_k x_k(t); vertex–face (1, −b_a, −b_b, −b_c) with
                           ///< barycentric b; edge–edge (1−s, s, −(1−u), −u)
  Vec3 normal{Vec3::Zero()};  ///< unit contact normal, pointing from the second primitive (face,
                              ///< edge q) toward the first (vertex, edge p) on the side the pair
                              ///< started on (the side it ends on when it starts in contact)
  double distance{};       ///< |d(t)| at the contact time [m]
};

/// Vertex p against triangle (a, b, c), positions `x0` at t = 0 and `x1` at t = 1 (order p, a,
/// b, c). Returns the earliest t at which p is within `tolerance` [m] of the triangle and
/// coplanar with it (or t = 0 when it starts within `tolerance`); empty on a miss. Coplanar
/// motion (identically vanishing cubic) is solved in the plane as vertex–edge crossings.
std::optional<CcdHit> vertex_face_ccd(const Corners& x0, const Corners& x1, double tolerance);

/// Edge (p0, p1) against edge (q0, q1), positions `x0` at t = 0 and `x1` at t = 1 (order p0, p1,
/// q0, q1). Same contract as `vertex_face_ccd`; parallel edges (coplanar at all times) are
/// solved as vertex–edge crossings.
std::optional<CcdHit> edge_edge_ccd(const Corners& x0, const Corners& x1, double tolerance);

}  // namespace dexcloth::collision
