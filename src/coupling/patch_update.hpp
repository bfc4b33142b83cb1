#pragma once
/// Paper §5 in the time step: rigid cloth patches rebuilt from the cloth under the hand.
#include <span>

#include "cloth/collision/mesh_topology.hpp"
#include "coupling/world.hpp"

namespace dexcloth::coupling {

/// Rebuilds data.patches from the cloth vertices touching actuated rigid bodies (the hand, the
/// gripper: a static prop needs no patch to know about the cloth) and places them in DART's patch
/// pool for the coming rigid step; every other pool patch is deactivated. Uses x1 of the cloth
/// meshes (the end-of-step positions) and (x1 − x0)/h as velocities; the boxes start the rigid
/// step without turning (the rotation fitted to the cloth is its deformation more than a turn).
/// A patch is 2 × the repulsion thickness thick (the cloth with its two repulsion layers); one
/// whose cloth touches bodies on both sides (a pinch) is centred between them and made thicker
/// by DART's contact allowance on each side, less 1 % of the thickness, so the bodies rest just
/// inside the repulsion layers. The vertices of all cloths are clustered together, so cloths
/// stacked between two fingers make one patch, as thick as n + 1 repulsion thicknesses for its n
/// cloth layers (those it holds and those they touch, the middle layers that touch no finger);
/// its vertices carry their cloth (RigidPatch::cloths). Returns the number of active patches.
int update_patches(const WorldModel& model, int cloth_meshes, WorldData& data);

/// The normal a cloth vertex is clustered by (δn, δd of eqs. 10–11): the mean of the normals of
/// the rigid surfaces it touches (its contact groups with meshes ≥ `cloth_meshes`), each turned
/// to the side of its cloth normal `n`; `n` itself when it touches no rigid surface. Cloth
/// pressed by a finger lies along the finger whatever its mesh normals say: where the cloth
/// under a finger pad wrinkled at the scale of the pad, its vertex normals spread past δn and a
/// hand's pinch fell apart into 20–30 small patches, few of them reaching both fingers.
Vec3 clustering_normal(const Vec3& n, std::span<const ContactGroup> groups, int cloth_meshes);

/// A body's own unit normal where it touches a cloth vertex through `group`, at the body's
/// vertex positions `x` (its faces `faces`, with `topology` built for them): the normal of the
/// body's face the vertex touches, or, where a vertex or an edge of the body touches the cloth,
/// the normal of the face around that corner or the edge's ends that faces the group's normal
/// most; the group's normal where there is none (or `topology` is not the mesh's).
/// Turned to the group's side (toward the vertex). The group's own normal is its records' mean,
/// and a body's corner touching a cloth face records the cloth's normal: in a pinch whose cloth
/// lay 16° off the pads the patch was turned to the cloth, the pads met its faces askew and
/// squeezed it aside (DART's force on it 0.001–0.01 N), closed to 8.6 mm, 1.6 mm inside the
/// cloth's repulsion layers, and the sheet crept out. (A corner's mean vertex normal is no
/// better: the hand's cylinders have every vertex on a rim, halfway between side and cap.)
Vec3 body_normal(const ContactGroup& group, const Points& x, const Triangles& faces,
                 const collision::MeshTopology& topology);

/// Area-weighted unit vertex normals of a triangle mesh (|V|×3 into `normals`).
void vertex_normals(const Triangles& faces, const Points& x, Points& normals);

}  // namespace dexcloth::coupling
