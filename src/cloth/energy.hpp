#pragma once
/// Whole-cloth energies and momenta, for tests and run summaries.
#include "cloth/model.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// Elastic energy [J] at positions `x` (|V|×3) [m]: stretching of every face plus bending of
/// every hinge.
double elastic_energy(const ClothModel& model, const Points& x);

/// Stretching part of elastic_energy [J].
double stretching_energy(const ClothModel& model, const Points& x);

/// Bending part of elastic_energy [J].
double total_bending_energy(const ClothModel& model, const Points& x);

/// Kinetic energy ½·Σ m_i·|v_i|² [J] of velocities `v` (|V|×3) [m/s] with the lumped masses.
double kinetic_energy(const ClothModel& model, const Points& v);

/// Linear momentum Σ m_i·v_i [kg·m/s].
Vec3 linear_momentum(const ClothModel& model, const Points& v);

/// Angular momentum Σ m_i·x_i × v_i about the world origin [kg·m²/s].
Vec3 angular_momentum(const ClothModel& model, const Points& x, const Points& v);

}  // namespace dexcloth::cloth
