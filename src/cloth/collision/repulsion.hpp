#pragma once
/// Proximity response on the candidate velocities (Bridson et al. 2002, §7.2): inelastic and
/// spring repulsion impulses, Coulomb friction capped per step (the `kinematic` baseline), and the
/// per-vertex contact records the cloth–rigid coupling consumes.
#include <array>
#include <vector>

#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/proximity.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Settings of the repulsion pass.
struct RepulsionOptions {
  double thickness{5e-3};  ///< repulsion thickness [m] (paper: 5 mm)
  double dt{5e-3};         ///< step size h [s]; velocities are (x1 − x0)/h
  double stiffness{1e3};   ///< Bridson's repulsion spring stiffness k [N/m]
  int iterations{8};       ///< Gauss–Seidel sweeps of the normal impulses over all pairs
  bool friction{true};     ///< apply friction impulses; off when the coupling computes friction
};

/// How a contact record's vertex takes part in its proximity pair.
enum class ContactKind {
  VertexFace,  ///< the vertex against a face of `other_mesh`
  FaceVertex,  ///< the vertex is a corner of a face touched by vertex `face_or_edge` of `other_mesh`
  EdgeEdge,    ///< the vertex ends an edge touching edge `face_or_edge` of `other_mesh`
};

/// One cloth vertex's share of one proximity pair (paper Algorithm 1, ClothCollisionDetection).
struct VertexContact {
  int mesh{};                  ///< mesh of the cloth vertex
  int vertex{};                ///< the cloth vertex
  int other_mesh{};            ///< mesh on the other side
  bool with_obstacle{};        ///< the other side is an obstacle (rigid body): vertex ∈ Vr
  ContactKind kind{ContactKind::VertexFace};  ///< role of the vertex in the pair
  Vec3 normal{Vec3::Zero()};   ///< unit normal pointing from the other side toward the vertex
  double distance{};           ///< gap of the pair at x0 [m]
  Vec3 other_velocity{Vec3::Zero()};  ///< velocity of the touching point on the other side after
                                      ///< the pass [m/s]
  double normal_impulse{};     ///< this vertex's share of the pair's repulsion impulse [N·s]
  double friction_impulse{};   ///< this vertex's share of the pair's friction impulse [N·s]
                               ///< (the kinematic baseline's; 0 when the coupling computes it)
  int face_or_edge{};          ///< other side's face (VertexFace), vertex (FaceVertex) or edge
                               ///< (EdgeEdge, index into its MeshTopology::edges)
  Vec3 weights{Vec3::Zero()};  ///< barycentric weights of the touching point on the other side:
                               ///< face (VertexFace), (1,0,0) (FaceVertex), (1−u, u, 0) (EdgeEdge)
  std::array<int, 3> other_vertices{-1, -1, -1};  ///< the other side's vertices those weigh (−1:
                                                  ///< unused)
};

/// Applies repulsion (and, with `options.friction`, friction) impulses for every pair in
/// `proximities` to x1 of the meshes' movable vertices (fixed vertices and obstacles have
/// infinite mass). Per pair with overlap d = thickness − distance and relative normal velocity
/// v_N, the target is v_N ≥ max(v_N⁰, min(max(v_N⁰, 0) + h·k·d·K, 0.1·d/h)) with K the pair's
/// inverse effective mass (Bridson eq. in §7.2); a pair beyond the thickness (d < 0) may close
/// to it and no further, v_N ≥ max(v_N⁰, d/h). Targets are reached by Gauss–Seidel on
/// accumulated impulses λ ≥ 0. Friction (apply_pair_friction in one pass):
/// v_T ← max(1 − μ·Δv_N/|v_T|, 0)·v_T, so the friction impulse is ≤ μ·λ and never reverses the
/// relative tangential velocity. Replaces `contacts` with one record per cloth vertex of each
/// pair with a nonzero weight (of pairs beyond the thickness, only those with λ > 0), and
/// `impulses` with each pair's λ [N·s].
void apply_repulsion(const std::vector<CollisionMesh*>& meshes,
                     const std::vector<Proximity>& proximities, const RepulsionOptions& options,
                     std::vector<VertexContact>& contacts, std::vector<double>& impulses);

}  // namespace dexcloth::collision
