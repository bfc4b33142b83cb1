#pragma once
/// Cloth dynamics without collisions: linearised implicit Euler, one Newton step per time step
/// (Baraff & Witkin 1998; ARCSim), with hard velocity constraints (handles).
#include <span>
#include <string>
#include <vector>

#include "cloth/model.hpp"
#include "cloth/state.hpp"
#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::cloth {

/// A vertex whose velocity over the step is prescribed (its unknowns are eliminated): in all
/// three directions; with a nonzero `free_direction`, in the plane orthogonal to it; with a
/// nonzero `fixed_direction`, along that direction only.
struct VelocityConstraint {
  int vertex{};                        ///< vertex index in [0, |V|)
  Vec3 velocity{Vec3::Zero()};         ///< prescribed velocity [m/s]
  Vec3 free_direction{Vec3::Zero()};   ///< unit direction left to the dynamics, or zero (none)
  Vec3 fixed_direction{Vec3::Zero()};  ///< the only prescribed unit direction, or zero
};

/// Coulomb friction of a vertex against a surface, solved inside the implicit step. The vertex
/// sticks (tangential velocity that of the surface) while that takes a tangential impulse of at
/// most `max_impulse`; otherwise it slides and friction applies `max_impulse` against its
/// sliding velocity. Its normal velocity is left to the dynamics, unless it is squeezed between
/// two surfaces: then it moves with them along the normal too (their contact forces, outside the
/// solve, would stop any normal motion relative to them); its other constraints, if any, must
/// share that plane.
struct FrictionConstraint {
  int vertex{};                         ///< vertex index in [0, |V|)
  Vec3 normal{Vec3::UnitZ()};           ///< unit contact normal (sign irrelevant)
  Vec3 surface_velocity{Vec3::Zero()};  ///< velocity of the touching surface [m/s]
  double max_impulse{};                 ///< μ·Σ fN·h, the friction impulse bound [N·s], ≥ 0
  bool squeezed{false};                 ///< normal velocity prescribed: the surface's
};

/// How the friction of a solve is solved.
struct FrictionSettings {
  double stick_velocity{1e-4};  ///< ε: slip speeds below it count as sticking [m/s], > 0
  /// Newton iterations (each one linear solve), ≥ 1; one more, accurate, when all were loose.
  int max_iterations{12};
  double tolerance{1.0};  ///< stop when no velocity changes by more than tolerance·ε
  /// Relative residual of the linear solves of Newton steps far from the answer [-].
  double newton_tolerance{1e-3};
  /// Once a step changes no velocity by more than accurate_below·ε (or the line search stalls),
  /// the solves are to the model's tolerance, and convergence needs two of them.
  double accurate_below{100.0};
  /// Up to this many friction vertices, the friction is solved on their Schur complement in a
  /// direct factorisation of the step (one factorisation, a dense problem of three unknowns per
  /// vertex); with more, by the Newton iterations above, each a linear solve of the cloth.
  int max_schur_vertices{200};
};

/// Outcome of the friction constraints of a solve, in their order.
struct FrictionOutcome {
  std::vector<char> sticking;  ///< 1 = moves with its surface, 0 = sliding (or held elsewhere)
  std::vector<Vec3> impulse;   ///< friction impulse applied [N·s], zero when held elsewhere
  int iterations{};            ///< Newton iterations taken
  int linear_solves{};         ///< linear solves of the cloth's system taken
  /// Time spent on the friction beyond one linear solve of the step [s]: the Newton iterations'
  /// further solves, or the Schur complement's ordering and dense problem.
  double seconds{};
};

/// Outcome of a dynamics solve. A failed solve never aborts: ok = false and `message` says why.
struct DynamicsReport {
  bool ok{true};      ///< false if the linear solve failed or produced a non-finite velocity
  int iterations{};   ///< linear-solver iterations (1 for the direct solver)
  double residual{};  ///< relative residual ‖AΔv − b‖/‖b‖ of the linear solve [-]
  /// What went wrong when !ok; when ok, empty or a note (PCG fell back to Cholesky for this step).
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

/// solve_velocities with Coulomb friction in the implicit step (paper §4.2's conditions, for
/// vertices whose contact persists; the coupling uses it): Δv minimises the convex
/// ½ΔvᵀAΔv − bᵀΔv + Σ_k B_k‖w_k‖, w_k the tangential slip of friction vertex k at v + Δv and
/// B_k its bound — the implicit Euler step whose friction impulses lie in their discs and
/// oppose the slip (Coulomb) — with ‖w‖ smoothed below ε = settings.stick_velocity, by Newton's
/// method with a backtracking line search (reweighted least-squares steps while the solves are
/// loose or a slip still turns), started from the last step's Δv. Vertices that
/// end below ε stick: they take their surface's tangential velocity exactly; squeezed ones take
/// its normal velocity too, as an eliminated constraint, sticking or not. Vertices also in
/// `constraints` keep those, without friction. Writes v̄ into state.v, the friction impulses into
/// state.constraint_impulse, and `outcome`; on failure state.v is left unchanged.
DynamicsReport solve_velocities(const ClothModel& model, ClothState& state, double h,
                                const Vec3& gravity,
                                std::span<const VelocityConstraint> constraints,
                                std::span<const FrictionConstraint> friction,
                                FrictionOutcome& outcome, const FrictionSettings& settings = {});

/// The assembly of solve_velocities' system ahead of the solve, in pieces that may run beside
/// other work (the coupling runs them beside the rigid step). begin_assembly keeps bitwise
/// copies of state.x, state.v, state.f_ext, `h` and `gravity` and returns the number of pieces;
/// assemble_piece(model, state, k) assembles piece k from those copies, each k once, on any
/// threads in any order (none at the same time as another call on `state`). The next
/// solve_velocities on `state` uses that system when every piece is done and its inputs are
/// bitwise the kept ones, and assembles afresh otherwise: either way the system is bitwise the
/// same.
int begin_assembly(const ClothModel& model, ClothState& state, double h, const Vec3& gravity);
void assemble_piece(const ClothModel& model, ClothState& state, int k);

/// Lends `pool` (with model.solver.threads threads; null: none) to the solves on `state` until
/// lent another: they run on it instead of the solver's own threads. The coupling lends the
/// pool of its own steps when nothing else runs on it during the solve, so that its workers,
/// busy just before, need no wake-up from sleep. Results do not depend on the pool.
void lend_solver_pool(ClothState& state, WorkerPool* pool);

/// Moves the positions with the current velocities: x += h·v (`h` [s]).
void advance_positions(ClothState& state, double h);

/// solve_velocities, then advance_positions when the solve succeeded (on failure x and v are
/// left unchanged).
DynamicsReport step_dynamics(const ClothModel& model, ClothState& state, double h,
                             const Vec3& gravity, std::span<const VelocityConstraint> constraints);

}  // namespace dexcloth::cloth
