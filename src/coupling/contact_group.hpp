#pragma once
/// Per-vertex contact groups handed from contact detection to the paper's interface.
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "cloth/collision/pair_friction.hpp"
#include "cloth/dynamics.hpp"
#include "core/types.hpp"
#include "coupling/friction_ncp.hpp"

namespace dexcloth::coupling {

/// One side of a cloth vertex's contact: all proximity records of the vertex against one mesh on
/// one side, merged (paper: one contact per touched surface, M ≤ 2 in practice).
struct ContactGroup {
  int cloth{};                       ///< cloth (mesh) index
  int vertex{};                      ///< cloth vertex
  int other_mesh{};                  ///< collision mesh on the other side
  Vec3 normal{Vec3::Zero()};         ///< unit normal toward the vertex
  Vec3 other_velocity{Vec3::Zero()}; ///< velocity of the touching surface [m/s]
  double repulsion_force{};          ///< repulsion impulse / h [N]
  double normal_force{};             ///< fN used for friction [N]
  int rigid_patch{-1};               ///< pool patch whose contact resultant is shared, or -1
  /// The other side's vertices and weights of the group's heaviest record, to read the surface's
  /// velocity again at the next step.
  std::array<int, 3> other_vertices{-1, -1, -1};
  Vec3 other_weights{Vec3::Zero()};
  double record_weight{};  ///< weight of that record
  /// Found ahead of a fast body (speculative_touches.hpp): the cloth's end-of-step position
  /// against the body's predicted pose, for the patches only (other_vertices index that pose).
  bool speculative{false};
};

/// End of the run of groups of the vertex whose first group is `first` (group_contacts keeps
/// the groups of one vertex consecutive).
inline std::size_t vertex_end(const std::vector<ContactGroup>& groups, std::size_t first) {
  std::size_t end = first;
  while (end < groups.size() && groups[end].cloth == groups[first].cloth &&
         groups[end].vertex == groups[first].vertex)
    ++end;
  return end;
}

/// One cloth vertex's friction NCP against the bodies and props it touches (paper §4.2), kept
/// through the sweeps that solve it together with the cloth–cloth pair friction.
struct BodyFriction {
  int cloth{};
  int vertex{};
  std::size_t first{}, end{};                                ///< the vertex's groups
  std::array<FrictionContact, kMaxVertexContacts> contacts;  ///< its body and prop contacts
  std::array<std::size_t, kMaxVertexContacts> source{};      ///< each contact's group
  std::size_t count{};
  bool coupled{};              ///< a corner of a cloth–cloth friction pair
  Vec3 applied{Vec3::Zero()};  ///< Δv applied so far [m/s]
  FrictionResult result;       ///< the last answer
};

/// Scratch of the interface, kept between steps so a step does not allocate.
struct InterfaceScratch {
  std::vector<ContactGroup> groups;
  std::vector<int> order;
  std::vector<double> weight;
  std::vector<std::vector<int>> patch_of;  ///< per cloth, per vertex: pool patch holding it, or −1
  std::vector<std::vector<double>> patch_force;  ///< per rigid mesh, per pool patch: Σ f_n [N]
  std::vector<std::vector<int>> patch_takers;    ///< per rigid mesh, per pool patch: vertices
  std::vector<double> squeeze;      ///< per pool patch: force through a stack of cloths [N]
  std::vector<int> squeeze_takers;  ///< per pool patch: middle-layer vertices sharing it
  std::vector<std::array<int, 2>> squeeze_bodies;  ///< per pool patch: its two pressing bodies
  std::vector<Vec2> pair_closing;  ///< per body × body: Σ squeeze·closing speed, Σ squeeze
  std::vector<double> closing_filtered;  ///< per body × body: low-passed closing speed [m/s]
  std::vector<long> closing_step;        ///< per body × body: step it was set
  // Friction of vertices already in contact, solved inside the next implicit step, per cloth.
  std::vector<std::vector<cloth::FrictionConstraint>> friction;
  std::vector<std::vector<std::pair<int, int>>>
      friction_groups;  ///< each one's groups [first, end)
  std::vector<cloth::FrictionOutcome> friction_outcome;
  std::vector<Points> reaction;  ///< per cloth: forces of stacked layers' friction [N], next step
  collision::PairFriction pairs;                       ///< the cloth–cloth friction of the step
  std::vector<std::vector<std::uint8_t>> pair_corner;  ///< per cloth, per vertex: in a pair
  std::vector<BodyFriction> body_friction;             ///< the step's vertex NCPs
  /// Per cloth, per vertex: 0 not in the implicit friction, 1 stuck, 2 sliding (last step).
  std::vector<std::vector<std::uint8_t>> friction_state;
  std::vector<std::vector<double>> force_filtered;  ///< per cloth, per vertex: filtered DART fN [N]
  std::vector<std::vector<long>> force_step;        ///< per cloth, per vertex: step it was set
};

}  // namespace dexcloth::coupling
