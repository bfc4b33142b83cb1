#pragma once
/// Speculative touches: cloth that a fast driven body will reach in the next step, for the rigid
/// cloth patches only.
///
/// Patches are fitted to the cloth within a repulsion thickness of a driven body at the step's
/// start. A body moving more than that in a step (a box dropped at 1 m/s moves 5 mm in a 5 ms
/// step) has none in its way when DART moves it; the next cloth step then sweeps its predicted
/// pose through cloth that cannot get out of the way (lying on a table, or held by another
/// finger) and the impact zones fail. So, for bodies that move more than half a thickness a
/// step (its velocity extrapolated by its last change), the cloth at the end of its step is also
/// searched against the body's predicted pose (x + h·v) out to 1.25 steps of the body's
/// approach speed; those vertices join the patches, whose boxes then reach out toward that
/// surface (patch_update.cpp, rigid_patch.hpp), so DART meets the body within its step and stops
/// it. They exert no repulsion or friction.
#include <vector>

#include "coupling/world.hpp"

namespace dexcloth::coupling {

/// Fills `data.speculative.groups` with one group per (cloth vertex, fast driven body) within
/// reach, sorted by cloth, vertex and body, flagged ContactGroup::speculative; surface points
/// and normals are at the body's predicted pose (`data.meshes`' x1 of the body), the cloth at its
/// end-of-step positions (x1). Empty when no driven body moves more than half a thickness a step.
void find_speculative_groups(const WorldModel& model, int cloth_meshes, WorldData& data);

/// `real` (the step's contact groups, each vertex's consecutive) with the groups of
/// `speculative` added whose body the vertex does not already touch, into `out`: each vertex's
/// groups stay consecutive, the vertices of `real` first in their order.
void merge_speculative_groups(const std::vector<ContactGroup>& real,
                              const std::vector<ContactGroup>& speculative,
                              std::vector<ContactGroup>& out);

}  // namespace dexcloth::coupling
