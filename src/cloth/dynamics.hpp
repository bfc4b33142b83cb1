#pragma once
/// Cloth dynamics without collisions: linearised implicit Euler, one Newton step per time step
/// (Baraff & Witkin 1998; ARCSim), with hard velocity constraints (handles).
#include <span>
#include <string>

#include "cloth/model.hpp"
#include "cloth/state.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// A vertex whose velocity over the step is prescribed exactly (its unknowns are eliminated).
struct VelocityConstraint {
  int vertex{};                 ///< vertex index in [0, |V|)
  Vec3 velocity{Vec3::Zero()};  ///< prescribed velocity [m/s]
};

/// Outcome of a dynamics solve. A failed solve never aborts: ok = false and `message` says why.
struct DynamicsReport {
  bool ok{true};      ///< false if the linear solve failed or produced a non-finite velocity
  int iterations{};   ///< linear-solver iterations (1 for the direct solver)
  double residual{};  ///< relative residual ‖AΔv − b‖/‖b‖ of the linear solve [-]
  /// What went wrong when !ok; when ok, empty or a note (PCG fell back to LDLT for this step).
  std::string message;
};

/// Candidate next velocities v̄ (DESIGN.md, one time step): solves
///   (M + (h² + h·β)·K)·Δv = h·(f(x) + f_ext + M·g − (h + β)·K·v),   v̄ = v + Δv,
/// with M the lumped masses, K the sum of the PSD element Hessians (stretching, bending) at x,
/// f = −∇E the elastic forces, β = material.damping [s] (stiffness-proportional damping
/// −β·K·v), `h` [s] the time step and `gravity` [m/s²]. Constrained vertices get exactly their
/// prescribed velocity (a later constraint on the same vertex wins). Writes v̄ into state.v and
/// leaves state.x untouched; on failure (ok = false) state.v is left unchanged too.
/// Allocates only on the first call for a given state.
DynamicsReport solve_velocities(const ClothModel& model, ClothState& state, double h,
                                const Vec3& gravity,
                                std::span<const VelocityConstraint> constraints);

/// Moves the positions with the current velocities: x += h·v (`h` [s]).
void advance_positions(ClothState& state, double h);

/// solve_velocities, then advance_positions when the solve succeeded (on failure x and v are
/// left unchanged).
DynamicsReport step_dynamics(const ClothModel& model, ClothState& state, double h,
                             const Vec3& gravity, std::span<const VelocityConstraint> constraints);

}  // namespace dexcloth::cloth
