#pragma once
/// Proximity detection: vertex–face and edge–edge pairs closer than the cloth thickness at the
/// start of the step (Bridson et al. 2002, §7.1), cloth–obstacle and cloth–cloth (self included).
#include <array>
#include <vector>

#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/collision_mesh.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// A primitive pair closer than the thickness at x0 (or, between cloth and an obstacle searched
/// beyond it, within the search's obstacle reach: a pair that may close to the thickness).
struct Proximity {
  bool edge_edge{};             ///< false: vertex–face, true: edge–edge
  std::array<int, 2> mesh{};    ///< mesh of the first primitive (vertex, edge p) and the second
                                ///< (face, edge q)
  std::array<int, 4> corner{};  ///< vertex indices (p, a, b, c) or (p0, p1, q0, q1); corner k
                                ///< lies in mesh[0] for k < 1 (VF) or k < 2 (EE), else mesh[1]
  int first{};                  ///< vertex (VF) or edge (EE) index of the first primitive
  int second{};                 ///< face (VF) or edge (EE) index of the second primitive
  Eigen::Vector4d w{
      Eigen::Vector4d::Zero()};  ///< signed corner weights of the closest points:
                                 ///< gap d = Σ w_k x0_k; VF (1, −b), EE (1−s, s, −(1−u), −u)
  Vec3 normal{Vec3::Zero()};  ///< unit normal from the second primitive toward the first
  double distance{};          ///< |d| at x0 [m]

  /// Mesh of corner k.
  int corner_mesh(int k) const { return mesh[(edge_edge ? k >= 2 : k >= 1) ? 1 : 0]; }
};

/// Replaces `out` with every vertex–face and edge–edge pair closer than `thickness` [m] at x0
/// among `meshes` (see `CollisionCandidates::update` for which mesh pairs take part).
/// `candidates` is the broad-phase scratch kept between steps; the search runs on its pool's
/// threads (the result does not depend on them), with `scratch` kept between calls.
void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      CollisionCandidates& candidates, std::vector<Proximity>& out,
                      std::vector<std::vector<Proximity>>& scratch);
/// The same, with the pairs of cloth and obstacles marked `beyond_thickness` closer than
/// `obstacle_reach` ≥ `thickness` [m]: those beyond the thickness let the repulsion stop a
/// vertex that would pass it in the step.
void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      double obstacle_reach, CollisionCandidates& candidates,
                      std::vector<Proximity>& out, std::vector<std::vector<Proximity>>& scratch);
/// The same with scratch of its own.
void find_proximities(const std::vector<const CollisionMesh*>& meshes, double thickness,
                      CollisionCandidates& candidates, std::vector<Proximity>& out);

}  // namespace dexcloth::collision
