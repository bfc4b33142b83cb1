#pragma once
/// ClothCollisionDetection of the paper's Algorithm 1: proximity within the repulsion thickness,
/// repulsion impulses on the candidate velocities, and the contact vertex sets Vr (touching
/// rigid bodies, i.e. obstacles) and Vc (touching cloth).
#include <vector>

#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/proximity.hpp"
#include "cloth/collision/repulsion.hpp"

namespace dexcloth::collision {

/// Mutable data of contact detection, kept between steps (broad-phase trees, scratch, results).
struct ClothContacts {
  CollisionCandidates candidates;      ///< broad phase (trees built once, refit per step)
  std::vector<Proximity> proximities;  ///< pairs closer than the thickness at x0
  std::vector<std::vector<Proximity>> proximity_scratch;  ///< per chunk of the parallel search
  std::vector<VertexContact> contacts;  ///< per-vertex records of the last detection
  std::vector<double> impulses;         ///< per proximity: its repulsion impulse λ [N·s]
};

/// Vertices of one mesh in contact, sorted and unique.
struct ContactVertexSets {
  std::vector<int> obstacle;  ///< Vr: vertices touching an obstacle (rigid body)
  std::vector<int> cloth;     ///< Vc: vertices touching cloth (another mesh or the same one)
};

/// Finds proximities at x0 within `options.thickness` and applies repulsion (and friction, per
/// `options.friction`) to x1 of `meshes`; fills `data.proximities`, `data.contacts` and
/// `data.impulses`.
void detect_cloth_contacts(const std::vector<CollisionMesh*>& meshes,
                           const RepulsionOptions& options, ClothContacts& data);

/// Vr and Vc of mesh `mesh` from `contacts`.
ContactVertexSets contact_vertex_sets(const std::vector<VertexContact>& contacts, int mesh);

}  // namespace dexcloth::collision
