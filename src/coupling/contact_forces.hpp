#pragma once
/// The interface of the paper between contact detection and the refinement steps: per-vertex
/// contact groups, normal forces (§4.1), friction (§4.2) and position constraints (§3, §7.2).
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "coupling/contact_group.hpp"
#include "coupling/world.hpp"

namespace dexcloth::coupling {

/// Merges data.contacts.contacts into groups, one per (vertex, other mesh, side), sorted by
/// (cloth, vertex). `cloth_meshes` = number of cloth meshes at the front of data.meshes.
/// Fills data.interface.groups.
void group_contacts(int cloth_meshes, double h, WorldData& data);

/// Paper §4.1: a vertex touching a DART body takes the normal force that body exerts on a rigid
/// cloth patch — its own patch when the body presses it, else the patch of the body's nearest
/// contact point (within `reach` [m]) — and each body's resultant on a patch (the sum over
/// DART's manifold points, whose split among the points the LCP does not determine) is shared
/// among all vertices that took it: the paper's per-contact rule summed per patch, so the shares
/// add up to the body's force. Other groups keep the cloth simulator's repulsion force, except
/// the middle layers of cloths stacked between two bodies, which take the squeeze through the
/// stack. The group normal becomes DART's contact normal, the direction of fN. Each vertex's
/// DART force is low-passed (time constant 50 ms; step `h` [s]) while the vertex stays in
/// contact.
void assign_normal_forces(int cloth_meshes, double reach, double h, WorldData& data);

/// A body surface a cloth vertex touches, as the implicit friction sees it.
struct GripSurface {
  bool actuated{};                  ///< part of a skeleton of `bodies` (a hand or gripper)
  Vec3 velocity{Vec3::Zero()};      ///< surface velocity at the contact now [m/s]
  double mu{};                      ///< friction coefficient of the pair [-]
};

/// The implicit friction constraint of one vertex from its contact groups (all of one vertex,
/// `cloth_meshes` cloth meshes first), or none. A vertex whose contacts with bodies are all with
/// actuated ones, have a surface record, and are coplanar (|n_i × n_0| ≤ coplanar_sin) gets its
/// first body contact's normal, the fN-weighted surface velocity, and the bound Σ μ·fN·h; its
/// contacts with cloth give no friction in that step (the grip dominates). The contacts of a
/// middle layer of a squeezed stack with the cloths around it (cloth groups with a rigid_patch,
/// see assign_normal_forces) grip as bodies do. `surface` reads a gripping group's surface.
std::optional<cloth::FrictionConstraint> grip_constraint(
    std::span<const ContactGroup> groups, int cloth_meshes, double coplanar_sin, double h,
    const std::function<GripSurface(const ContactGroup&)>& surface);

/// Friction of the vertices held by hands and grippers, for the next implicit step: the
/// grip_constraint of each vertex of the last step's groups, with coplanar_deg in degrees.
/// The reactions of the implicit friction of middle layers of stacks on the cloths around them
/// (Newton's third law): each constraint's impulse, split among its gripping surfaces by their
/// normal forces, acts with opposite sign on the touched cloth's vertices (the record's
/// barycentric weights) as a force over the next step, into data.interface.reaction. Without
/// it the outer layers would not carry the middle ones, and a stack between two fingers would
/// hold at a third of its weight too little.
void stack_reactions(int cloth_meshes, double h, WorldData& data);

/// Fills data.interface.friction per cloth. The first step of a contact, and vertices touching
/// props (tables, obstacles) or only cloth, go through apply_friction: the friction of a resting
/// or sliding cloth needs no load transfer through the solve, and each friction vertex costs
/// Newton iterations of the whole cloth's system.
void friction_constraints(int cloth_meshes, double h, double coplanar_deg, WorldData& data);

/// Paper §4.2 and §3 on the candidate velocities (x1 − x0)/h of `meshes` (data.meshes).
/// Cloth–cloth friction acts per proximity pair, its repulsion impulse the normal force, equal
/// and opposite on its two sides (collision::PairFriction), so friction within and between
/// cloths keeps their momentum. Each other vertex in contact solves its friction NCP against the
/// bodies and props it touches, x1 moved by h·Δv, in block Gauss–Seidel with the pairs. Vertices
/// whose friction the implicit step solved (data.interface.friction_state) are not solved again
/// and weigh as the hand in the pairs; those that stuck, and those in static friction with a
/// body, are frozen (position-constrained) unless still closing on a surface. Returns the
/// number of frozen vertices. Contact planes of one vertex within `coplanar_deg` of each other
/// are one plane, as the vertices of one rigid cloth patch are (paper §5, δn).
int apply_friction(double h, double coplanar_deg,
                   const std::vector<collision::CollisionMesh*>& meshes, WorldData& data);

}  // namespace dexcloth::coupling
