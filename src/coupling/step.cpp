#include "coupling/step.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "cloth/collision/inside_obstacles.hpp"
#include "cloth/collision/strain_limit.hpp"
#include "coupling/contact_forces.hpp"
#include "coupling/patch_update.hpp"

namespace dexcloth::coupling {
namespace {

/// Contact planes of one vertex closer than this are one plane in the friction NCP [deg]. DART
/// reports a patch contact's normal along either the body's face or the patch's fitted face, so
/// the two jaws of a pinch give normals a fraction of a degree apart; exact parallelism would
/// send every pinched vertex to the Gauss–Seidel fallback, which never yields static friction.
constexpr double kCoplanarDeg = 2.0;

/// The pairs of cloth and static or keyframed obstacles are searched this many repulsion
/// thicknesses out, so that a vertex resting just beyond the thickness keeps its pair: the
/// repulsion stops it at the thickness when the solve moves it further in. Searched to the
/// thickness only, the vertex over a sphere's pole under a draped sheet's tension had no pair
/// at times, was pulled 5–9 mm into the sphere by the solve and stopped 0.2 mm above its surface
/// by the impact zones, every 0.1–0.2 s. Further out (two thicknesses) more of the impacts the
/// impact zones had stopped without friction took friction: dress_sleeve's sleeve slid 10.3
/// instead of 14.5 cm up the arm, and a pinch_move start dropped its sheet. Not the bodies the
/// cloth pushes (their patches meet them in DART; with their pairs searched as far, a gripper's
/// strip crept 4.1 mm in a second at 1.1 times the Coulomb threshold, 52 mm at two
/// thicknesses), nor in the kinematic baseline (ARCSim's search).
constexpr double kObstacleReachThicknesses = 1.25;

/// The proximity search's placement (search_ahead): the weight of a step's cost in its moving
/// average, and how often the costlier placement is tried again [steps].
constexpr double kPlacementWeight = 0.1;
constexpr int kPlacementTrial = 16;

/// Wall-clock laps for the Table-1 breakdown.
class Stopwatch {
 public:
  /// Seconds since the last lap (or construction).
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - m_last).count();
    m_last = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point m_last{std::chrono::steady_clock::now()};
};

/// Hard velocity constraints that carry every handle vertex to its keyframed place at t + h; a
/// sliding handle's vertices only across its direction (they keep to their rod).
void handle_constraints(const ClothBody& body, const cloth::ClothState& state, double t_next,
                        double h, std::vector<cloth::VelocityConstraint>& out) {
  out.clear();
  for (const Handle& handle : body.handles) {
    if (t_next > handle.release + 1e-12) continue;
    const Vec3 offset = handle.motion.empty()
                            ? Vec3::Zero()
                            : Vec3(rigid::sample_pose(handle.motion, t_next).X_WF.translation());
    for (std::size_t k = 0; k < handle.vertices.size(); ++k) {
      const int i = handle.vertices[k];
      const Vec3 target = handle.rest.row(static_cast<Eigen::Index>(k)).transpose() + offset;
      out.push_back({i, (target - state.x.row(i).transpose()) / h, handle.slide});
    }
  }
}

/// Cloth c's external forces over the next step: the last step's friction reactions of stacked
/// cloths on it.
void next_external_forces(const WorldModel& model, WorldData& data, std::size_t c) {
  const std::vector<Points>& reaction = data.interface.reaction;
  if (model.mode == CouplingMode::bai_liu && c < reaction.size())
    data.cloths[c].f_ext = reaction[c];
  else
    data.cloths[c].f_ext.setZero();
}

/// ClothDynamics (Algorithm 1): candidate velocities v̄ of every cloth, handles as constraints.
/// In the bai-liu coupling, vertices that touched rigid bodies at the last step carry their
/// Coulomb friction (the paper's §4.2 conditions, same fN and μ) into the implicit solve: a
/// pinch then holds the load the whole cloth puts on it. The paper's per-vertex NCP after the
/// solve sees only one vertex's share of a cloth that falls freely in the solve, so a strip
/// slid out of a gripper at 1.5 N*; it still handles each contact's first step. The friction
/// constraints are friction_constraints' (made before). Returns the seconds the friction took
/// beyond one solve of the cloth (interface time in Table 1).
double cloth_dynamics(const WorldModel& model, WorldData& data) {
  double friction_seconds = 0.0;
  const bool bai_liu = model.mode == CouplingMode::bai_liu;
  InterfaceScratch& s = data.interface;
  s.friction_state.resize(model.cloths.size());
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    const ClothBody& body = model.cloths[c];
    cloth::ClothState& state = data.cloths[c];
    handle_constraints(body, state, data.time + model.dt, model.dt, data.scratch_constraints);
    next_external_forces(model, data, c);
    std::vector<std::uint8_t>& solved = s.friction_state[c];
    solved.assign(static_cast<std::size_t>(state.x.rows()), 0);
    cloth::DynamicsReport report;
    if (bai_liu && !s.friction[c].empty()) {
      s.friction_outcome[c].impulse.clear();  // filled only by a successful solve
      report =
          cloth::solve_velocities(body.model, state, model.dt, model.gravity,
                                  data.scratch_constraints, s.friction[c], s.friction_outcome[c]);
      friction_seconds += s.friction_outcome[c].seconds;
      if (report.ok)
        for (std::size_t k = 0; k < s.friction[c].size(); ++k)
          solved[static_cast<std::size_t>(s.friction[c][k].vertex)] =
              s.friction_outcome[c].sticking[k] ? 1 : 2;
    } else {
      report = cloth::solve_velocities(body.model, state, model.dt, model.gravity,
                                       data.scratch_constraints);
    }
    if (!report.ok) data.warnings.add(data.step, body.name + ": " + report.message);
  }
  if (bai_liu) stack_reactions(static_cast<int>(model.cloths.size()), model.dt, data);
  return friction_seconds;
}

/// The step's motion of every collision mesh known before the cloth's dynamics: the cloths' start
/// x0 = x, and the rigid bodies' whole motion, from the pose the cloth was last resolved against
/// to x + h·v of the last rigid step.
void load_collision_meshes(const WorldModel& model, WorldData& data) {
  const double h = model.dt;
  for (std::size_t c = 0; c < model.cloths.size(); ++c) data.meshes[c].x0 = data.cloths[c].x;
  for (std::size_t m = 0; m < data.rigid.meshes.size(); ++m) {
    collision::CollisionMesh& mesh = data.meshes[model.cloths.size() + m];
    const rigid::ObstacleMesh& body = data.rigid.meshes[m];
    // A body starts the step where the cloth was last made free of it (its x1 of the last
    // step), not where DART put it: contact impulses make DART's step differ from the
    // prediction x + h·v, and a cloth closer than that difference to a finger pressing on a
    // patch began the step inside the finger, which no collision response can undo (a hand's
    // pinch kept 2–14 intersecting pairs for a fifth of its steps). The difference is swept
    // through during this step instead.
    if (data.step == 0 || mesh.x1.rows() != body.x.rows()) mesh.x1 = body.x;
    mesh.x0 = mesh.x1;
    mesh.x1 = body.x + h * body.v;
    mesh.beyond_thickness = model.mode == CouplingMode::bai_liu && data.rigid.mesh_coupled[m] == 0;
  }
}

/// Pointers to the collision meshes, as the collision routines take them.
std::vector<collision::CollisionMesh*>& mesh_list(WorldData& data) {
  data.mesh_pointers.clear();
  for (collision::CollisionMesh& m : data.meshes) data.mesh_pointers.push_back(&m);
  return data.mesh_pointers;
}

/// The cloths' end of the step: x1 = x + h·v̄, with handle vertices frozen.
void load_cloth_motion(const WorldModel& model, WorldData& data) {
  const double h = model.dt;
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    collision::CollisionMesh& mesh = data.meshes[c];
    mesh.x1 = data.cloths[c].x + h * data.cloths[c].v;
    std::fill(mesh.frozen.begin(), mesh.frozen.end(), std::uint8_t{0});
    for (const Handle& handle : model.cloths[c].handles)
      if (data.time + h <= handle.release + 1e-12)
        for (int i : handle.vertices) mesh.frozen[static_cast<std::size_t>(i)] = 1;
  }
}

/// The proximity search of ClothCollisionDetection among `meshes` (at their x0), into
/// `proximities`: on the candidates' pool, or with `one_thread` on the calling thread alone
/// (beside other work on the pool's other threads).
void search_proximities(const WorldModel& model,
                        const std::vector<const collision::CollisionMesh*>& meshes,
                        collision::ClothContacts& contacts,
                        std::vector<collision::Proximity>& proximities, bool one_thread) {
  WorkerPool* pool = contacts.candidates.pool();
  if (one_thread) contacts.candidates.set_pool(nullptr);
  collision::find_proximities(meshes, model.thickness, kObstacleReachThicknesses * model.thickness,
                              contacts.candidates, proximities, contacts.proximity_scratch);
  contacts.candidates.set_pool(pool);
}

template <class Matrix>
bool same(const Matrix& a, const Matrix& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::equal(a.data(), a.data() + a.size(), b.data());
}

/// Whether meshes `a` and `b` are the same to the proximity search: start positions, faces,
/// rest shape and flags, bitwise.
bool same_search(const collision::CollisionMesh& a, const collision::CollisionMesh& b) {
  return same(a.x0, b.x0) && same(a.faces, b.faces) && same(a.rest, b.rest) &&
         a.obstacle == b.obstacle && a.beyond_thickness == b.beyond_thickness &&
         a.self_collision == b.self_collision;
}

/// The collision meshes as load_collision_meshes will start the next step, as far as the
/// proximity search reads them: the cloths at their end of this step, the bodies at their x1
/// of this step (where the cloth was made free of them). Read beside the rigid step, which
/// changes neither.
void load_lookahead_meshes(const WorldModel& model, const WorldData& data,
                           std::vector<collision::CollisionMesh>& out) {
  out.resize(data.meshes.size());
  for (std::size_t m = 0; m < data.meshes.size(); ++m) {
    const collision::CollisionMesh& mesh = data.meshes[m];
    collision::CollisionMesh& next = out[m];
    next.x0 = m < model.cloths.size() ? data.cloths[m].x : mesh.x1;
    next.faces = mesh.faces;
    next.rest = mesh.rest;
    next.obstacle = mesh.obstacle;
    next.beyond_thickness = mesh.beyond_thickness;
    next.self_collision = mesh.self_collision;
  }
}

/// cloth_dynamics and the proximity search of ClothCollisionDetection, which reads only the
/// meshes' start positions (x0), not v̄. When the search ran at the end of the last step, beside
/// the rigid step (lookahead_proximities), its proximities are taken if this step starts with
/// the meshes it searched, which is checked. Otherwise, on several threads the search runs
/// beside the dynamics, on one thread while the calling thread solves the cloths (the solver
/// has threads of its own); on one thread, after them. Wherever it runs it finds the same pairs
/// in the same order. Returns cloth_dynamics' friction seconds.
double dynamics_and_proximities(const WorldModel& model, WorldData& data, WorkerPool* pool) {
  Stopwatch clock;
  ProximityLookahead& lookahead = data.lookahead;
  bool looked_ahead = lookahead.ready && lookahead.thickness == model.thickness &&
                      lookahead.meshes.size() == data.meshes.size();
  for (std::size_t m = 0; looked_ahead && m < data.meshes.size(); ++m)
    looked_ahead = same_search(lookahead.meshes[m], data.meshes[m]);
  lookahead.ready = false;
  collision::ClothContacts& contacts = data.contacts;
  double friction_seconds = 0.0;
  if (looked_ahead) {
    // Nothing else runs now: the solves take this step's pool, whose workers are awake.
    contacts.proximities.swap(lookahead.proximities);
    for (cloth::ClothState& state : data.cloths) cloth::lend_solver_pool(state, pool);
    friction_seconds = cloth_dynamics(model, data);
    for (cloth::ClothState& state : data.cloths) cloth::lend_solver_pool(state, nullptr);
  } else {
    const std::vector<collision::CollisionMesh*>& meshes = mesh_list(data);
    const std::vector<const collision::CollisionMesh*> view(meshes.begin(), meshes.end());
    auto task = [&](int t) {
      if (t == 0) friction_seconds = cloth_dynamics(model, data);
      if (t == 1 || pool == nullptr)
        search_proximities(model, view, contacts, contacts.proximities, true);
    };
    if (pool != nullptr) {
      pool->run(task);
    } else {
      task(0);
    }
  }
  // The cost of the placement taken at the end of the last step.
  if (lookahead.rigid_phase > 0.0) {
    double& cost = lookahead.cost[lookahead.ahead ? 0 : 1];
    const double sample = lookahead.rigid_phase + clock.lap();
    cost = cost < 0.0 ? sample : cost + kPlacementWeight * (sample - cost);
  }
  return friction_seconds;
}

/// Whether the next step's proximity search runs ahead (beside the rigid step) rather than
/// beside the next solve: always on one thread (the same work either way), else the placement
/// of lower cost, the other one every kPlacementTrial-th step (each first once).
bool search_ahead(ProximityLookahead& lookahead, WorkerPool* pool) {
  if (pool == nullptr) return true;
  const double* cost = lookahead.cost;
  if (cost[0] < 0.0 || cost[1] < 0.0) return cost[0] < 0.0;
  const bool cheaper = cost[0] <= cost[1];
  lookahead.trial = (lookahead.trial + 1) % kPlacementTrial;
  return lookahead.trial == 0 ? !cheaper : cheaper;
}

/// The next step's proximity search (dynamics_and_proximities), at the meshes' next start:
/// run at the end of a step, beside the rigid step, on one thread.
void lookahead_proximities(const WorldModel& model, WorldData& data) {
  ProximityLookahead& lookahead = data.lookahead;
  load_lookahead_meshes(model, data, lookahead.meshes);
  std::vector<const collision::CollisionMesh*> view;
  for (const collision::CollisionMesh& m : lookahead.meshes) view.push_back(&m);
  search_proximities(model, view, data.contacts, lookahead.proximities, true);
  lookahead.thickness = model.thickness;
  lookahead.ready = true;
}

/// StrainLimit (Algorithm 1): per cloth with limits, frozen vertices fixed.
void strain_limit(const WorldModel& model, WorldData& data) {
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    const ClothBody& body = model.cloths[c];
    if (!body.strain_limits) continue;
    collision::StrainLimitOptions options;
    options.min_stretch = (*body.strain_limits)[0];
    options.max_stretch = (*body.strain_limits)[1];
    collision::CollisionMesh& mesh = data.meshes[c];
    const collision::StrainLimitReport report = collision::limit_strain(
        mesh.x1, mesh.faces, body.model.Dm_inv, mesh.mass, mesh.frozen, options);
    if (!report.converged)
      data.warnings.add(data.step, body.name + ": strain limiting left a stretch " +
                                       std::to_string(report.violation) + " outside its bounds");
  }
}

/// InelasticProjection (Algorithm 1): no collision is left on x0 → x1.
void inelastic_projection(const WorldModel& model, WorldData& data) {
  collision::ImpactZoneOptions options;
  options.offset = 0.03 * model.thickness;
  const collision::ImpactZoneReport report = data.impact_zones.resolve(mesh_list(data), options);
  for (const std::string& w : report.warnings) data.warnings.add(data.step, w);
  // Vertices the projection could not keep out of a body (a zone kept at its start while the
  // body moved on) go back onto its surface, or the two sides' repulsions hold them inside.
  // Not in the kinematic baseline (ARCSim's handling): its bodies go where they are driven,
  // and a jaw that swallows a whole region of a pile (323 vertices at once in grab_pile) is
  // left with a tangle when each vertex leaves by its own closest face.
  if (model.mode != CouplingMode::bai_liu) return;
  const collision::InsideReport inside =
      collision::push_out_of_obstacles(mesh_list(data), options.offset);
  if (inside.vertices > 0) {
    char text[96];
    std::snprintf(text, sizeof text,
                  "%d cloth vertices found inside bodies moved to their surface (deepest %.2f mm)",
                  inside.vertices, 1e3 * inside.depth);
    data.warnings.add(data.step, text);
  }
}

/// The cloth's new state from the refined end-of-step positions.
void finish_cloth(const WorldModel& model, WorldData& data) {
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    const collision::CollisionMesh& mesh = data.meshes[c];
    data.cloths[c].v = (mesh.x1 - mesh.x0) / model.dt;
    data.cloths[c].x = mesh.x1;
  }
}

/// ControlForce and RigidSimulation (Algorithm 1): controllers, the DART step, and the bodies'
/// collision meshes for the next cloth step.
void rigid_step(WorldData& data) {
  RigidSide& rigid = data.rigid;
  for (control::BuiltBody& body : rigid.bodies)
    body.controllers.apply(*rigid.world, rigid.world->time());
  rigid.world->step();
  rigid.world->export_obstacle_meshes(rigid.meshes);
}

/// rigid_step beside the assembly of the next step's cloth systems, which depends on the cloths
/// alone (positions, velocities and the stacked layers' reactions, final by now), and, where
/// search_ahead places it, the next step's proximity search (lookahead_proximities), which
/// depends on the cloths and on where the bodies were last resolved against: the calling thread
/// steps the bodies, a second the search, then each joins the others on the assembly's pieces. The
/// next cloth_dynamics finds each system assembled, bitwise as it would assemble it. Returns the
/// rigid step's seconds.
double rigid_step_beside_assembly(const WorldModel& model, WorldData& data, WorkerPool* pool) {
  data.assembly_pieces.clear();
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    cloth::ClothState& state = data.cloths[c];
    next_external_forces(model, data, c);
    const int pieces = cloth::begin_assembly(model.cloths[c].model, state, model.dt, model.gravity);
    for (int k = 0; k < pieces; ++k) data.assembly_pieces.push_back({static_cast<int>(c), k});
  }
  double rigid_seconds = 0.0;
  const auto rigid = [&] {
    Stopwatch clock;
    rigid_step(data);
    rigid_seconds = clock.lap();
  };
  Stopwatch clock;
  const bool ahead = data.lookahead.ahead = search_ahead(data.lookahead, pool);
  const auto first = [&](int t) {
    if (t == 0) rigid();
    if (ahead && (t == 1 || pool == nullptr)) lookahead_proximities(model, data);
  };
  for_each_index_after(pool, first, data.assembly_pieces.size(), [&](std::size_t k) {
    const auto [c, piece] = data.assembly_pieces[k];
    cloth::assemble_piece(model.cloths[static_cast<std::size_t>(c)].model,
                          data.cloths[static_cast<std::size_t>(c)], piece);
  });
  data.lookahead.rigid_phase = clock.lap();
  return rigid_seconds;
}

}  // namespace

void step(const WorldModel& model, WorldData& data) {
  const auto start = std::chrono::steady_clock::now();
  // The threads of the collision searches (the cloth's linear solves have their own).
  if (model.threads > 1 && (!data.pool || data.pool->threads() != model.threads))
    data.pool = std::make_unique<WorkerPool>(model.threads);
  WorkerPool* pool = model.threads > 1 ? data.pool.get() : nullptr;
  data.contacts.candidates.set_pool(pool);
  data.impact_zones.set_pool(pool);
  // The impact zones fit the step's end, where the next proximity search starts (never at the
  // same time: the search runs beside the cloth's solve, the impact zones after it).
  data.impact_zones.share_fits(data.contacts.candidates);
  Stopwatch clock;
  const int cloths = static_cast<int>(model.cloths.size());
  const bool bai_liu = model.mode == CouplingMode::bai_liu;
  const double h = model.dt;

  // v̄ = ClothDynamics(x, v), with the friction of persisting contacts (paper §4.2); beside it
  // the proximities of Vr, Vc = ClothCollisionDetection(x, v̄, q, q̇), found at x and q.
  if (bai_liu) friction_constraints(cloths, h, kCoplanarDeg, data);
  load_collision_meshes(model, data);
  const double friction_seconds = dynamics_and_proximities(model, data, pool);
  // The repulsion on v̄; in the kinematic baseline it also applies ARCSim's capped friction.
  load_cloth_motion(model, data);
  collision::RepulsionOptions repulsion;
  repulsion.thickness = model.thickness;
  repulsion.dt = h;
  repulsion.friction = !bai_liu;
  const std::vector<collision::CollisionMesh*>& meshes = mesh_list(data);
  collision::apply_repulsion(meshes, data.contacts.proximities, repulsion, data.contacts.contacts,
                             data.contacts.impulses);
  data.timings.cloth += clock.lap() - friction_seconds;
  data.timings.interface += friction_seconds;

  // Paper §4: contact groups, normal forces (§4.1), friction NCP and position constraints (§4.2).
  group_contacts(cloths, h, data);
  data.stats.sticking = 0;
  if (bai_liu) {
    assign_normal_forces(cloths, model.clusters.distance, h, data);
    data.stats.sticking = apply_friction(h, kCoplanarDeg, meshes, data);
  }
  data.timings.interface += clock.lap();

  // x̂ = StrainLimit(x̃, c); x̌ = InelasticProjection(x̂, c): constrained vertices do not move.
  strain_limit(model, data);
  inelastic_projection(model, data);
  finish_cloth(model, data);
  data.timings.cloth += clock.lap();

  // q̄ = UpdateRigidClothPatches(x, v, Vr) (paper §5).
  data.stats.patches = bai_liu ? update_patches(model, cloths, data) : 0;
  data.timings.interface += clock.lap();

  // τ = ControlForce(q̄); q, q̇, f_c = RigidSimulation(q̄, τ), beside the next cloth assembly.
  const double rigid_seconds = rigid_step_beside_assembly(model, data, pool);
  data.timings.rigid += rigid_seconds;
  data.timings.cloth += clock.lap() - rigid_seconds;

  // Bookkeeping: statistics, time, lost state.
  data.stats.contacts = static_cast<int>(data.contacts.contacts.size());
  data.stats.vr = data.stats.vc = 0;
  for (int c = 0; c < cloths; ++c) {
    const collision::ContactVertexSets sets =
        collision::contact_vertex_sets(data.contacts.contacts, c);
    data.stats.vr += static_cast<int>(sets.obstacle.size());
    data.stats.vc += static_cast<int>(sets.cloth.size());
  }
  data.time += h;
  ++data.step;
  if (!state_is_finite(data)) {
    data.lost = true;
    data.warnings.add(data.step, "state lost: NaN or infinite cloth position/velocity");
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  data.timings.total += elapsed;
  data.last_step_ms = 1e3 * elapsed;
}

}  // namespace dexcloth::coupling
