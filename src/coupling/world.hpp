#pragma once
/// The simulated world: every cloth, the rigid world (DART skeletons and scene props) and the
/// coupling's state, split into an immutable WorldModel and a mutable WorldData (DESIGN.md,
/// model/data split). `step` (coupling/step.hpp) advances it by one time step.
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cloth/collision/cloth_contacts.hpp"
#include "cloth/collision/impact_zones.hpp"
#include "cloth/dynamics.hpp"
#include "cloth/model.hpp"
#include "cloth/state.hpp"
#include "control/body_spec.hpp"
#include "core/warnings.hpp"
#include "coupling/contact_group.hpp"
#include "coupling/rigid_patch.hpp"
#include "rigid/keyframes.hpp"
#include "rigid/obstacle_mesh.hpp"
#include "rigid/world.hpp"

namespace dexcloth::coupling {

/// How cloth and rigid bodies exchange information (DESIGN.md, coupling modes).
enum class CouplingMode {
  bai_liu,    ///< the paper: DART normal forces, friction NCP, position constraints, patches
  kinematic,  ///< ARCSim baseline: rigid bodies are kinematic obstacles, repulsion friction
};

/// A pinned vertex set of a cloth, moved along keyframes (translation offsets from rest).
struct Handle {
  std::vector<int> vertices;                 ///< cloth vertex indices
  Points rest;                               ///< |vertices|×3 rest world positions [m]
  std::vector<rigid::PoseKeyframe> motion;   ///< offset X_WF(t) (translation only); empty: fixed
  double release{std::numeric_limits<double>::infinity()};  ///< time the handle lets go [s]
  Vec3 slide{Vec3::Zero()};  ///< unit direction the vertices move freely along (a rod), or zero
};

/// One cloth: its immutable model, rest shape and handles.
struct ClothBody {
  std::string name;
  cloth::ClothModel model;
  Points x_rest;                                   ///< |V|×3 rest world positions [m]
  std::vector<Handle> handles;
  std::optional<std::array<double, 2>> strain_limits;  ///< [min, max] singular values
};

/// Everything that does not change during a run.
struct WorldModel {
  double dt{0.005};                     ///< time step [s]
  Vec3 gravity{0.0, 0.0, -9.81};        ///< [m/s²]
  CouplingMode mode{CouplingMode::bai_liu};
  double thickness{5e-3};               ///< repulsion thickness [m] (paper: 5 mm)
  bool self_collision{true};
  ClusterParams clusters;               ///< patch clustering thresholds (paper §5)
  std::vector<ClothBody> cloths;
  int threads{1};  ///< threads of the step's parallel parts (set_threads); results do not depend on it
};

/// Runs the step's parallel parts (each cloth's linear solve, the collision searches) on
/// `threads` ≥ 1 threads, where they are big enough to gain from it (a cloth of fewer than 2000
/// vertices is solved on one).
void set_threads(WorldModel& model, int threads);

/// Wall-clock seconds spent per part of the step (paper Table 1).
struct Timings {
  double cloth{};      ///< dynamics, collision handling, strain limiting
  double rigid{};      ///< controllers and the DART step
  double interface{};  ///< normal forces, friction NCP, position constraints, patches
  double total{};
};

/// Counts of the last step, for summaries.
struct StepStats {
  int contacts{};       ///< cloth vertex contact records
  int vr{};             ///< vertices touching rigid bodies
  int vc{};             ///< vertices touching cloth
  int sticking{};       ///< static-friction vertices (position constrained)
  int patches{};        ///< active rigid cloth patches
};

/// The rigid side: DART world, skeletons with their controllers, and which DART body each
/// obstacle mesh stands for.
struct RigidSide {
  std::unique_ptr<rigid::RigidWorld> world;
  std::vector<control::BuiltBody> bodies;
  std::vector<rigid::ObstacleMesh> meshes;        ///< body collision meshes, refreshed per step
  std::vector<rigid::BodyId> mesh_body;           ///< DART body of each mesh
  /// 1: a skeleton the cloth pushes back on through patches: a hand or gripper from `bodies`,
  /// or a dynamic obstacle (mass > 0); 0: a static or keyframed obstacle.
  std::vector<std::uint8_t> mesh_coupled;
};

/// Scratch of the speculative touches (speculative_touches.hpp), kept between steps.
struct SpeculativeScratch {
  std::vector<std::uint8_t> fast;     ///< per body mesh: 1 when searched this step
  std::vector<Points> last_velocity;  ///< per body mesh: its vertex velocities a step ago [m/s]
  std::vector<Points> velocity;       ///< per body mesh: those expected in the next step [m/s]
  std::vector<collision::CollisionCandidates> candidates;  ///< per cloth: it and those bodies
  std::vector<collision::CollisionMesh> meshes;  ///< a cloth, then each body (empty if slow)
  std::vector<collision::Proximity> found;
  std::vector<ContactGroup> groups;  ///< the last search's, sorted by cloth, vertex, body
  std::vector<ContactGroup> merged;  ///< the step's groups with them (merge_speculative_groups)
};

/// The next step's proximity search, run at the end of a step beside the rigid step (step.cpp):
/// the collision meshes as the next step will start (x0 and what the search reads) and the
/// proximities found among them, used when the next step starts with exactly those meshes.
struct ProximityLookahead {
  std::vector<collision::CollisionMesh> meshes;  ///< cloths first, then rigid bodies (no x1)
  std::vector<collision::Proximity> proximities;
  double thickness{};  ///< the search's thickness [m]
  bool ready{};        ///< found at the end of the last step
  // On several threads, where the search runs: ahead (beside the rigid step) or beside the
  // cloth's solve. Each placement's cost is the wall time of the rigid step's phase and of the
  // next solve's, a moving average; the cheaper is taken, the other tried every few steps.
  double cost[2]{-1.0, -1.0};  ///< [ahead, beside] [s]; negative: not measured yet
  bool ahead{};                ///< the placement of the coming step's search
  int trial{};                 ///< steps counted toward the next trial of the costlier one
  double rigid_phase{};        ///< the last rigid step's phase [s] (0: none yet)
};

/// Everything a step changes.
struct WorldData {
  std::vector<cloth::ClothState> cloths;  ///< one per WorldModel::cloths
  RigidSide rigid;
  double time{};                          ///< simulated time [s]
  long step{};                            ///< steps taken
  WarningLog warnings;
  Timings timings;
  StepStats stats;
  double last_step_ms{};                  ///< wall time of the last step [ms]
  bool lost{};                            ///< state lost (NaN): the run cannot go on
  // Scratch, kept between steps so the step does not allocate.
  std::vector<cloth::VelocityConstraint> scratch_constraints;
  std::vector<collision::CollisionMesh> meshes;  ///< cloths first, then rigid bodies
  std::vector<collision::CollisionMesh*> mesh_pointers;  ///< the same, as the routines take them
  std::vector<std::pair<int, int>> assembly_pieces;      ///< (cloth, piece) assembled ahead
  collision::ClothContacts contacts;
  collision::ImpactZoneSolver impact_zones;
  InterfaceScratch interface;
  std::vector<RigidPatch> patches;
  std::vector<PatchVertex> patch_vertices;
  std::vector<std::pair<int, int>> patch_vertex_ids;     ///< (cloth, vertex) of each patch vertex
  std::vector<std::pair<int, int>> patch_vertex_groups;  ///< its contact groups [first, end)
  std::vector<std::vector<SurfaceTouch>> cluster_touches;  ///< rigid surfaces touching each
                                                          ///< cluster's cloth
  SpeculativeScratch speculative;
  Points normals;                       ///< vertex normals scratch
  std::unique_ptr<WorkerPool> pool;     ///< the step's threads when WorldModel::threads > 1
  ProximityLookahead lookahead;
};

/// Initial data: cloths at rest, time zero, the rigid world as built by the caller.
WorldData make_data(const WorldModel& model, RigidSide rigid);

/// True when every cloth position and velocity is finite.
bool state_is_finite(const WorldData& data);

}  // namespace dexcloth::coupling
