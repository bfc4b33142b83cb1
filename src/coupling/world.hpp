#pragma once
/// The simulated world: every cloth, obstacle and (later) rigid skeleton, split into an immutable
/// WorldModel and a mutable WorldData (DESIGN.md, model/data split). `step` advances it.
#include <string>
#include <vector>

#include "cloth/dynamics.hpp"
#include "cloth/model.hpp"
#include "cloth/state.hpp"
#include "core/keyframes.hpp"
#include "core/warnings.hpp"

namespace dexcloth::coupling {

/// A pinned vertex set of a cloth, moved along a keyframe track.
struct Handle {
  std::vector<int> vertices;  ///< cloth vertex indices
  Points rest;                ///< |vertices|×3 rest world positions [m]
  KeyTrack motion;            ///< translation offset over time (empty: fixed)
};

/// One cloth: its immutable model and handles.
struct ClothBody {
  std::string name;
  cloth::ClothModel model;
  Points x_rest;  ///< |V|×3 rest world positions [m] (the initial state)
  std::vector<Handle> handles;
};

/// Everything that does not change during a run.
struct WorldModel {
  double dt{0.005};                     ///< time step [s]
  Vec3 gravity{0.0, 0.0, -9.81};        ///< [m/s²]
  std::vector<ClothBody> cloths;
};

/// Wall-clock seconds spent per part of the step (paper Table 1).
struct Timings {
  double cloth{};
  double rigid{};
  double interface{};
  double total{};
};

/// Everything a step changes.
struct WorldData {
  std::vector<cloth::ClothState> cloths;  ///< one per WorldModel::cloths
  double time{};                          ///< simulated time [s]
  long step{};                            ///< steps taken
  WarningLog warnings;
  Timings timings;
  double last_step_ms{};                  ///< wall time of the last step [ms]
  bool lost{};                            ///< state lost (NaN): the run cannot go on
  std::vector<cloth::VelocityConstraint> scratch_constraints;  ///< per-step scratch
};

/// Initial data of a model: cloths at rest, time zero.
WorldData make_data(const WorldModel& model);

/// True when every position and velocity is finite.
bool state_is_finite(const WorldData& data);

}  // namespace dexcloth::coupling
