#pragma once
/// One time step of the world (paper Algorithm 1; see DESIGN.md "One time step").
#include "coupling/world.hpp"

namespace dexcloth::coupling {

/// Advances `data` by model.dt. Numerical trouble is recorded in data.warnings; a NaN sets
/// data.lost and leaves the step's state as computed so it can be reported.
void step(const WorldModel& model, WorldData& data);

}  // namespace dexcloth::coupling
