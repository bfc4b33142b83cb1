#pragma once
/// Paper §5 in the time step: rigid cloth patches rebuilt from the cloth under the hand.
#include "coupling/world.hpp"

namespace dexcloth::coupling {

/// Rebuilds data.patches from the cloth vertices touching actuated rigid bodies (the hand, the
/// gripper: a static prop needs no patch to know about the cloth) and places them in DART's patch
/// pool for the coming rigid step; every other pool patch is deactivated. Uses x1 of the cloth
/// meshes (the end-of-step positions) and (x1 − x0)/h as velocities. A patch is 2 × the
/// repulsion thickness thick (the cloth with its two repulsion layers); one whose cloth touches
/// bodies on both sides (a pinch) is centred between them and made thicker by DART's contact
/// allowance on each side, less 1 % of the thickness, so the bodies rest just inside the
/// repulsion layers. Returns the number of active patches.
int update_patches(const WorldModel& model, int cloth_meshes, WorldData& data);

/// Area-weighted unit vertex normals of a triangle mesh (|V|×3 into `normals`).
void vertex_normals(const Triangles& faces, const Points& x, Points& normals);

}  // namespace dexcloth::coupling
