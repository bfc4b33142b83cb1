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

/// Paper §4.1: a vertex touching a DART body takes the normal force of the nearest contact point
/// between that body and a rigid cloth patch, shared among all vertices that took the same point;
/// other groups keep the cloth simulator's repulsion force. Contacts farther than `reach` [m]
/// from the vertex are not taken. A vertex of a patch pressed on that body takes the patch
/// contact's resultant (the sum over DART's manifold points, whose split among the points is
/// not determined by the LCP), shared among the patch's vertices touching the body. The group
/// normal becomes DART's contact normal, the direction of fN. Each vertex's DART force is
/// low-passed (time constant 50 ms; step `h` [s]) while the vertex stays in contact.
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
/// contacts with cloth give no friction in that step (the grip dominates). `surface` reads a
/// body group's surface.
std::optional<cloth::FrictionConstraint> grip_constraint(
    std::span<const ContactGroup> groups, int cloth_meshes, double coplanar_sin, double h,
    const std::function<GripSurface(const ContactGroup&)>& surface);

/// Friction of the vertices held by hands and grippers, for the next implicit step: the
/// grip_constraint of each vertex of the last step's groups, with coplanar_deg in degrees.
/// Fills data.interface.friction per cloth. The first step of a contact, and vertices touching
/// props (tables, obstacles) or only cloth, go through apply_friction: the friction of a resting
/// or sliding cloth needs no load transfer through the solve, and each friction vertex costs
/// Newton iterations of the whole cloth's system.
void friction_constraints(int cloth_meshes, double h, double coplanar_deg, WorldData& data);

/// Paper §4.2 and §3: solves each vertex's friction NCP on the candidate velocity (x1 − x0)/h,
/// moves x1 by h·Δv, and freezes (position-constrains) vertices in static friction. Returns the
/// number of frozen vertices. Vertices whose friction the implicit step solved
/// (data.interface.friction_state) are not solved again; those that stuck are frozen. Contact
/// planes of one vertex within `coplanar_deg` of each other are one plane, as the vertices of one
/// rigid cloth patch are (paper §5, δn).
int apply_friction(double h, double coplanar_deg, WorldData& data);

}  // namespace dexcloth::coupling
