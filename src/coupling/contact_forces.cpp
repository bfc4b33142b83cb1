#include "coupling/contact_forces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cloth/collision/pair_friction.hpp"
#include "coupling/friction_ncp.hpp"

namespace dexcloth::coupling {

void group_contacts(int cloth_meshes, double h, WorldData& data) {
  std::vector<ContactGroup>& groups = data.interface.groups;
  groups.clear();
  const auto& records = data.contacts.contacts;
  // Visit records in (mesh, vertex) order without copying them.
  std::vector<int>& order = data.interface.order;
  order.resize(records.size());
  for (std::size_t k = 0; k < records.size(); ++k) order[k] = static_cast<int>(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::pair(records[a].mesh, records[a].vertex) < std::pair(records[b].mesh, records[b].vertex);
  });
  std::vector<double>& weight = data.interface.weight;  // accumulated weight of each group
  weight.clear();
  std::size_t first_of_vertex = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const collision::VertexContact& r = records[order[k]];
    if (r.mesh >= cloth_meshes) continue;
    if (k == 0 || r.mesh != records[order[k - 1]].mesh || r.vertex != records[order[k - 1]].vertex)
      first_of_vertex = groups.size();
    // Same mesh, same side: merge; else a new group.
    const double w = r.normal_impulse + 1e-12;
    auto it = std::find_if(groups.begin() + static_cast<std::ptrdiff_t>(first_of_vertex),
                           groups.end(), [&](const ContactGroup& g) {
                             return g.other_mesh == r.other_mesh && g.normal.dot(r.normal) >= 0.0;
                           });
    if (it == groups.end()) {
      ContactGroup g;
      g.cloth = r.mesh;
      g.vertex = r.vertex;
      g.other_mesh = r.other_mesh;
      groups.push_back(g);
      weight.resize(groups.size(), 0.0);
      it = groups.end() - 1;
    }
    const std::size_t gi = static_cast<std::size_t>(it - groups.begin());
    weight.resize(groups.size(), 0.0);
    if (w > it->record_weight) {
      it->record_weight = w;
      it->other_vertices = r.other_vertices;
      it->other_weights = r.weights;
    }
    it->normal += w * r.normal;
    it->other_velocity += w * r.other_velocity;
    it->repulsion_force += r.normal_impulse / h;
    weight[gi] += w;
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    groups[g].normal.normalize();
    groups[g].other_velocity /= weight[g];
    groups[g].normal_force = groups[g].repulsion_force;
  }
}

namespace {

/// Whether the group took a DART contact force (§4.1) rather than the repulsion force.
bool takes_dart_force(const ContactGroup& g) { return g.rigid_patch >= 0; }

/// Whether the group is a middle layer's contact with a cloth beside it in a squeezed stack.
bool squeezed_layer(const ContactGroup& g, int cloth_meshes) {
  return g.other_mesh < cloth_meshes && g.rigid_patch >= 0;
}

/// Whether the group's surface grips the vertex: a body, or a cloth squeezed against it.
bool grips(const ContactGroup& g, int cloth_meshes) {
  return g.other_mesh >= cloth_meshes || squeezed_layer(g, cloth_meshes);
}

/// Whether a vertex with contact groups `run` is squeezed: it grips a patch that two bodies
/// pressed at the last rigid step (`squeeze` per pool patch, from squeeze_middle_layers).
bool squeezed(std::span<const ContactGroup> run, int cloth_meshes, const std::vector<double>& squeeze) {
  return std::any_of(run.begin(), run.end(), [&](const ContactGroup& g) {
    return grips(g, cloth_meshes) && g.rigid_patch >= 0 &&
           static_cast<std::size_t>(g.rigid_patch) < squeeze.size() &&
           squeeze[static_cast<std::size_t>(g.rigid_patch)] > 0.0;
  });
}

/// Whether velocity `v` still closes on any of the surfaces of groups [first, end).
bool closing(const std::vector<ContactGroup>& groups, std::size_t first, std::size_t end, const Vec3& v) {
  for (std::size_t k = first; k < end; ++k)
    if ((v - groups[k].other_velocity).dot(groups[k].normal) < 0.0) return true;
  return false;
}

/// Friction NCP answers further than this from the conditions (relative to the vertex's force
/// scale) are warned about. The solver aims at 1e-9; at a vertex in a fold's crease (two contacts
/// all but stuck, their lines of sticking a hair apart) rounding alone leaves up to ~1e-7.
constexpr double kFrictionWarnViolation = 1e-6;
/// Nor those whose unsolved part (the violation as a force) could not move the vertex this far in
/// a step [m]: a vertex barely touching two cloth layers (normal forces of 4e-13 N, slips of
/// 1e-14 m/s, at the rounding of (x1 − x0)/h) was warned about at its whole force scale.
constexpr double kFrictionWarnMotion = 1e-12;

/// Gauss–Seidel sweeps of the cloth–cloth pair friction (with the NCPs of the vertices it moves)
/// at most, and the change of a relative velocity [m/s] below which they stop. A crumpled heap's
/// thousands of pairs converge slowly: its sweeps still changed a pair by 46 mm/s (median step)
/// after 8 sweeps, 0.7 mm/s after 64. Stopped after 8, the heap on a table drifted further
/// (median 17 mm against 10.5 over 2.2–3.0 s, eight starts).
constexpr int kClothFrictionSweeps = 64;
constexpr double kClothFrictionConverged = 1e-6;

/// Time constant of the low-pass filter on the DART normal force of each cloth vertex [s].
constexpr double kForceFilterTime = 0.05;

/// Low-passes each vertex's summed DART normal force over the steps it stays in contact. The
/// per-step LCP impulse between a force-controlled finger and a patch re-placed from the cloth
/// every step alternates between large and near-zero values (penetration correction one step,
/// separation the next) around the squeeze force, its mean; Coulomb's bound follows the mean.
void filter_normal_forces(int cloth_meshes, double h, WorldData& data) {
  InterfaceScratch& s = data.interface;
  const double alpha = std::min(1.0, h / kForceFilterTime);
  s.force_filtered.resize(static_cast<std::size_t>(cloth_meshes));
  s.force_step.resize(static_cast<std::size_t>(cloth_meshes));
  for (int c = 0; c < cloth_meshes; ++c) {
    const auto nv = static_cast<std::size_t>(data.meshes[static_cast<std::size_t>(c)].x0.rows());
    s.force_filtered[static_cast<std::size_t>(c)].resize(nv, 0.0);
    s.force_step[static_cast<std::size_t>(c)].resize(nv, -2);
  }
  std::vector<ContactGroup>& groups = s.groups;
  std::size_t g = 0;
  while (g < groups.size()) {
    const std::size_t end = vertex_end(groups, g);
    double raw = 0.0;
    int taken = 0;
    for (std::size_t k = g; k < end; ++k)
      if (takes_dart_force(groups[k])) {
        raw += groups[k].normal_force;
        ++taken;
      }
    if (taken > 0) {
      const auto c = static_cast<std::size_t>(groups[g].cloth);
      const auto i = static_cast<std::size_t>(groups[g].vertex);
      const bool continued = s.force_step[c][i] == data.step - 1;
      const double f = continued ? s.force_filtered[c][i] + alpha * (raw - s.force_filtered[c][i]) : raw;
      s.force_filtered[c][i] = f;
      s.force_step[c][i] = data.step;
      for (std::size_t k = g; k < end; ++k)
        if (takes_dart_force(groups[k]))
          groups[k].normal_force = raw > 0.0 ? groups[k].normal_force * f / raw : f / taken;
    }
    g = end;
  }
}

/// Time constant of the low-pass filter on the speed at which two bodies squeezing the cloth
/// draw apart [s]; and the filtered speed above which they squeeze it no more [m/s].
constexpr double kPartingFilterTime = 0.05;
constexpr double kPartingSpeed = 0.02;

/// Two bodies pressing one patch squeeze it only while they do not draw apart. A palm rising off
/// a crumpled cloth on a table still pressed patches the table pressed too, and their squeezed
/// vertices took the palm's normal velocity: the palm lifted the cloth a few centimetres with it.
/// A pair's closing speed is measured at one point, the patch's force-weighted contact point, so
/// that two pads turning together (a hand carrying a pinch round) do not part; it is low-passed
/// over the steps the pair keeps squeezing, as a force-controlled jaw's LCP impulses make it
/// jitter at ±4 cm/s step to step around a closed grip.
void release_parting_squeezes(double h, WorldData& data) {
  InterfaceScratch& s = data.interface;
  const RigidSide& rigid = data.rigid;
  const rigid::RigidWorld& world = *rigid.world;
  const std::size_t patches = s.squeeze.size();
  const std::size_t bodies = s.patch_force.size();
  // Per pair of bodies: Σ squeeze·closing speed, Σ squeeze, over the patches they squeeze.
  s.pair_closing.assign(bodies * bodies, Vec2::Zero());
  const auto pair = [&](std::size_t p) {
    const auto [a, b] = s.squeeze_bodies[p];
    return static_cast<std::size_t>(std::min(a, b)) * bodies +
           static_cast<std::size_t>(std::max(a, b));
  };
  for (std::size_t p = 0; p < patches; ++p) {
    if (!(s.squeeze[p] > 0.0)) continue;
    const rigid::BodyId patch = world.patches().body(static_cast<int>(p));
    Vec3 point = Vec3::Zero();
    double force = 0.0;
    std::array<Vec3, 2> normal{Vec3::Zero(), Vec3::Zero()};  // from the patch into each body
    const auto body = [&](std::size_t k) {
      return rigid.mesh_body[static_cast<std::size_t>(s.squeeze_bodies[p][k])];
    };
    for (std::size_t k = 0; k < 2; ++k)
      for (const rigid::ContactPoint& c : world.contacts(body(k)))
        if (c.other == patch) {
          point += c.f_n * c.p_W;
          force += c.f_n;
          normal[k] += c.f_n * c.n_W;
        }
    if (!(force > 0.0)) continue;
    point /= force;
    double closing = 0.0;  // Σ of each body's speed toward the patch at `point` [m/s]
    for (std::size_t k = 0; k < 2; ++k) {
      const rigid::BodyId b = body(k);
      const Vec3 v = world.point_velocity_W(b, world.pose_W(b).inverse() * point);
      if (normal[k].norm() > 0.0) closing -= v.dot(normal[k].normalized());
    }
    s.pair_closing[pair(p)] += s.squeeze[p] * Vec2(closing, 1.0);
  }
  const double alpha = std::min(1.0, h / kPartingFilterTime);
  s.closing_filtered.resize(bodies * bodies, 0.0);
  s.closing_step.resize(bodies * bodies, -2);
  for (std::size_t k = 0; k < bodies * bodies; ++k) {
    const Vec2& c = s.pair_closing[k];
    if (!(c.y() > 0.0)) continue;
    const double raw = c.x() / c.y();
    // A pair's patches come and go between steps: its filter goes on across gaps shorter than
    // its time constant.
    const bool recent =
        static_cast<double>(data.step - s.closing_step[k]) * h <= kPartingFilterTime;
    const double last = recent ? s.closing_filtered[k] : 0.0;
    s.closing_filtered[k] = last + alpha * (raw - last);
    s.closing_step[k] = data.step;
  }
  for (std::size_t p = 0; p < patches; ++p)
    if (s.squeeze[p] > 0.0 && s.closing_filtered[pair(p)] < -kPartingSpeed) s.squeeze[p] = 0.0;
}

/// Cloths stacked between two fingers (a patch pressed by two bodies): the squeeze passes
/// through the middle layers, which touch no finger and would feel only their repulsion. Each
/// contact of a middle-layer vertex (one in no patch) with a cloth vertex of the stack's patch
/// takes the squeeze — the smaller of the two sides' resultants — shared among those vertices,
/// when that is more than its repulsion; the group then names the patch (rigid_patch).
void squeeze_middle_layers(int cloth_meshes, double h, WorldData& data) {
  InterfaceScratch& s = data.interface;
  std::vector<ContactGroup>& groups = s.groups;
  const std::size_t patches = s.patch_force.empty() ? 0 : s.patch_force.front().size();
  s.squeeze.assign(patches, 0.0);
  s.squeeze_takers.assign(patches, 0);
  s.squeeze_bodies.assign(patches, {-1, -1});
  for (std::size_t p = 0; p < patches; ++p) {
    double first = 0.0, second = 0.0;  // the two largest body resultants
    std::array<int, 2>& bodies = s.squeeze_bodies[p];
    for (std::size_t m = 0; m < s.patch_force.size(); ++m) {
      const double f = s.patch_force[m][p];
      if (f > first) {
        second = first;
        bodies[1] = bodies[0];
        first = f;
        bodies[0] = static_cast<int>(m);
      } else if (f > second) {
        second = f;
        bodies[1] = static_cast<int>(m);
      }
    }
    s.squeeze[p] = second;
  }
  release_parting_squeezes(h, data);
  const auto stack_patch = [&](const ContactGroup& g) {
    if (g.other_mesh >= cloth_meshes ||
        s.patch_of[static_cast<std::size_t>(g.cloth)][static_cast<std::size_t>(g.vertex)] >= 0)
      return -1;
    for (int j : g.other_vertices) {
      if (j < 0) continue;
      const int p = s.patch_of[static_cast<std::size_t>(g.other_mesh)][static_cast<std::size_t>(j)];
      if (p >= 0 && s.squeeze[static_cast<std::size_t>(p)] > 0.0) return p;
    }
    return -1;
  };
  for (std::size_t g = 0; g < groups.size();) {
    const std::size_t end = vertex_end(groups, g);
    int counted = -1;  // each vertex counts once per patch
    for (std::size_t k = g; k < end; ++k) {
      const int p = stack_patch(groups[k]);
      if (p >= 0 && p != counted) {
        ++s.squeeze_takers[static_cast<std::size_t>(p)];
        counted = p;
      }
    }
    g = end;
  }
  for (ContactGroup& g : groups) {
    const int p = stack_patch(g);
    if (p < 0) continue;
    const auto pu = static_cast<std::size_t>(p);
    const double share = s.squeeze[pu] / s.squeeze_takers[pu];
    if (share <= g.normal_force) continue;
    g.normal_force = share;
    g.rigid_patch = p;
  }
}

}  // namespace

void assign_normal_forces(int cloth_meshes, double reach, double h, WorldData& data) {
  std::vector<ContactGroup>& groups = data.interface.groups;
  const RigidSide& rigid = data.rigid;
  if (!rigid.world) return;
  InterfaceScratch& s = data.interface;
  const rigid::PatchPool& pool = rigid.world->patches();
  const auto patch_index = [&](rigid::BodyId b) {
    for (int p = 0; p < pool.capacity(); ++p)
      if (pool.active(p) && pool.body(p).index == b.index) return p;
    return -1;
  };
  // The patch (placed at the end of the last step, pool slot = index in data.patches) that holds
  // each cloth vertex.
  s.patch_of.resize(static_cast<std::size_t>(cloth_meshes));
  for (int c = 0; c < cloth_meshes; ++c)
    s.patch_of[static_cast<std::size_t>(c)].assign(
        static_cast<std::size_t>(data.meshes[static_cast<std::size_t>(c)].x0.rows()), -1);
  const int placed = std::min(pool.capacity(), static_cast<int>(data.patches.size()));
  for (int p = 0; p < placed; ++p) {
    const RigidPatch& patch = data.patches[static_cast<std::size_t>(p)];
    if (!pool.active(p) || patch.cloths.size() != patch.vertices.size()) continue;
    for (std::size_t k = 0; k < patch.vertices.size(); ++k)
      s.patch_of[static_cast<std::size_t>(patch.cloths[k])]
                [static_cast<std::size_t>(patch.vertices[k])] = p;
  }
  // Per body mesh: the resultant normal force of its contacts with each patch.
  s.patch_force.resize(rigid.meshes.size());
  s.patch_takers.resize(rigid.meshes.size());
  for (std::size_t m = 0; m < rigid.meshes.size(); ++m) {
    s.patch_force[m].assign(static_cast<std::size_t>(pool.capacity()), 0.0);
    s.patch_takers[m].assign(static_cast<std::size_t>(pool.capacity()), 0);
    for (const rigid::ContactPoint& c : rigid.world->contacts(rigid.mesh_body[m])) {
      const int p = patch_index(c.other);
      if (p >= 0) s.patch_force[m][static_cast<std::size_t>(p)] += c.f_n;
    }
  }
  // Each group takes the force of the patch its body presses there: the vertex's own patch when
  // the body presses it, else the patch of the body's nearest contact point with a patch.
  for (ContactGroup& g : groups) {
    const int m = g.other_mesh - cloth_meshes;
    if (m < 0) continue;
    const auto mi = static_cast<std::size_t>(m);
    int p = s.patch_of[static_cast<std::size_t>(g.cloth)][static_cast<std::size_t>(g.vertex)];
    if (p < 0 || s.patch_force[mi][static_cast<std::size_t>(p)] <= 0.0) {
      p = -1;
      const Vec3 x = data.meshes[static_cast<std::size_t>(g.cloth)].x0.row(g.vertex).transpose();
      double best = reach;
      for (const rigid::ContactPoint& c : rigid.world->contacts(rigid.mesh_body[mi])) {
        const double d = (c.p_W - x).norm();
        const int q = patch_index(c.other);
        if (d < best && c.f_n > 0.0 && q >= 0) {
          best = d;
          p = q;
        }
      }
    }
    if (p < 0) continue;
    g.rigid_patch = p;
    ++s.patch_takers[mi][static_cast<std::size_t>(p)];
  }
  // Each body's resultant on a patch is shared among the vertices that took it (the paper's
  // per-contact rule, summed per patch: every vertex near the patch takes one share, and the
  // shares add up to the force the body exerts). The force acts along DART's contact normal,
  // so that normal (turned toward the vertex) is the group's: the friction plane is the one
  // orthogonal to fN. The proximity records' normals tilt near mesh edges and would give the
  // two jaws of a pinch non-parallel planes.
  for (ContactGroup& g : groups) {
    if (g.other_mesh < cloth_meshes || g.rigid_patch < 0) continue;  // cloth–cloth: repulsion
    const auto m = static_cast<std::size_t>(g.other_mesh - cloth_meshes);
    const auto p = static_cast<std::size_t>(g.rigid_patch);
    g.normal_force = s.patch_force[m][p] / s.patch_takers[m][p];
    Vec3 n = Vec3::Zero();
    for (const rigid::ContactPoint& c : rigid.world->contacts(rigid.mesh_body[m]))
      if (patch_index(c.other) == g.rigid_patch) n += c.f_n * c.n_W;
    if (n.norm() > 0.0) g.normal = n.dot(g.normal) >= 0.0 ? Vec3(n.normalized()) : Vec3(-n.normalized());
  }
  squeeze_middle_layers(cloth_meshes, h, data);
  filter_normal_forces(cloth_meshes, h, data);
}

std::optional<cloth::FrictionConstraint> grip_constraint(
    std::span<const ContactGroup> groups, int cloth_meshes, double coplanar_sin, double h,
    const std::function<GripSurface(const ContactGroup&)>& surface) {
  // The vertex's contacts with bodies make the constraint, whatever cloth it also touches (that
  // friction is dropped for the step: the grip dominates it). A pinched corner folds onto
  // itself within the repulsion thickness, and left to the per-vertex NCP after the solve it
  // crept out of the fingers (10–28 mm in a hand's key pinch).
  const auto body = [&](const ContactGroup& g) { return grips(g, cloth_meshes); };
  const auto first = std::find_if(groups.begin(), groups.end(), body);
  if (first == groups.end()) return std::nullopt;
  const Vec3 n0 = first->normal;
  double bound = 0.0, weight = 0.0;
  Vec3 u = Vec3::Zero();
  for (const ContactGroup& g : groups) {
    if (!body(g)) continue;
    if (g.other_vertices[0] < 0 || n0.cross(g.normal).norm() > coplanar_sin) return std::nullopt;
    const GripSurface s = surface(g);
    if (!s.actuated) return std::nullopt;
    bound += s.mu * g.normal_force * h;
    u += g.normal_force * s.velocity;
    weight += g.normal_force;
  }
  if (!(bound > 0.0 && weight > 0.0)) return std::nullopt;
  return cloth::FrictionConstraint{first->vertex, n0, u / weight, bound};
}

void stack_reactions(int cloth_meshes, double h, WorldData& data) {
  InterfaceScratch& s = data.interface;
  s.reaction.resize(static_cast<std::size_t>(cloth_meshes));
  for (int c = 0; c < cloth_meshes; ++c)
    s.reaction[static_cast<std::size_t>(c)].setZero(
        data.meshes[static_cast<std::size_t>(c)].x0.rows(), 3);
  const std::vector<ContactGroup>& groups = s.groups;
  for (std::size_t c = 0; c < s.friction.size(); ++c) {
    const cloth::FrictionOutcome& outcome = s.friction_outcome[c];
    if (outcome.impulse.size() != s.friction[c].size()) continue;  // not solved this step
    for (std::size_t k = 0; k < s.friction[c].size(); ++k) {
      const auto [first, end] = s.friction_groups[c][k];
      // The constraint's impulse splits among its gripping surfaces as their normal forces.
      double total = 0.0;
      bool layered = false;
      for (int g = first; g < end; ++g) {
        const ContactGroup& cg = groups[static_cast<std::size_t>(g)];
        if (grips(cg, cloth_meshes)) total += cg.normal_force;
        layered = layered || squeezed_layer(cg, cloth_meshes);
      }
      if (!layered || !(total > 0.0)) continue;
      for (int g = first; g < end; ++g) {
        const ContactGroup& cg = groups[static_cast<std::size_t>(g)];
        if (!squeezed_layer(cg, cloth_meshes)) continue;
        const Vec3 force = -(cg.normal_force / total) * outcome.impulse[k] / h;
        Points& r = s.reaction[static_cast<std::size_t>(cg.other_mesh)];
        for (std::size_t j = 0; j < 3; ++j)
          if (cg.other_vertices[j] >= 0)
            r.row(cg.other_vertices[j]) +=
                cg.other_weights[static_cast<Eigen::Index>(j)] * force.transpose();
      }
    }
  }
}

void friction_constraints(int cloth_meshes, double h, double coplanar_deg, WorldData& data) {
  const double coplanar_sin = std::sin(coplanar_deg * M_PI / 180.0);
  InterfaceScratch& s = data.interface;
  const auto nc = static_cast<std::size_t>(cloth_meshes);
  s.friction.resize(nc);
  s.friction_groups.resize(nc);
  s.friction_outcome.resize(nc);
  for (auto& list : s.friction) list.clear();
  for (auto& list : s.friction_groups) list.clear();
  const std::vector<ContactGroup>& groups = s.groups;
  // The touched surface's velocity now, at the group's heaviest record (one std::function for
  // the whole loop, not one per vertex).
  const std::function<GripSurface(const ContactGroup&)> surface = [&](const ContactGroup& cg) {
    GripSurface out;
    const bool cloth = cg.other_mesh < cloth_meshes;  // a squeezed stack's neighbouring layer
    const auto m = static_cast<std::size_t>(cg.other_mesh - (cloth ? 0 : cloth_meshes));
    out.actuated = cloth || data.rigid.mesh_coupled[m];
    const Points& v = cloth ? data.cloths[m].v : data.rigid.meshes[m].v;
    for (std::size_t j = 0; j < 3; ++j)
      if (cg.other_vertices[j] >= 0)
        out.velocity += cg.other_weights[static_cast<Eigen::Index>(j)] *
                        v.row(cg.other_vertices[j]).transpose();
    out.mu = collision::pair_friction(data.meshes[static_cast<std::size_t>(cg.cloth)],
                                      data.meshes[static_cast<std::size_t>(cg.other_mesh)]);
    return out;
  };
  std::size_t g = 0;
  while (g < groups.size()) {
    const std::size_t end = vertex_end(groups, g);
    const std::span<const ContactGroup> run(groups.data() + g, end - g);
    if (auto c = grip_constraint(run, cloth_meshes, coplanar_sin, h, surface)) {
      c->squeezed = squeezed(run, cloth_meshes, s.squeeze);
      s.friction[static_cast<std::size_t>(groups[g].cloth)].push_back(*c);
      s.friction_groups[static_cast<std::size_t>(groups[g].cloth)].emplace_back(
          static_cast<int>(g), static_cast<int>(end));
    }
    g = end;
  }
}

namespace {

/// Solves vertex friction `b`'s NCP again on the vertex's velocity without its own last answer
/// (block Gauss–Seidel with the pair friction) and moves x1 by the change; returns its size [m/s].
double solve_body_friction(BodyFriction& b, const std::vector<ContactGroup>& groups, double h,
                           double coplanar_sin, WorldData& data) {
  collision::CollisionMesh& mesh = data.meshes[static_cast<std::size_t>(b.cloth)];
  const Vec3 v = (mesh.x1.row(b.vertex) - mesh.x0.row(b.vertex)).transpose() / h - b.applied;
  for (std::size_t k = 0; k < b.count; ++k)
    b.contacts[k].relative_velocity = v - groups[b.source[k]].other_velocity;
  b.result = solve_friction(std::span<const FrictionContact>(b.contacts.data(), b.count),
                            mesh.mass[b.vertex], h, coplanar_sin);
  const Vec3 change = b.result.delta_v - b.applied;
  mesh.x1.row(b.vertex) += h * change.transpose();
  b.applied = b.result.delta_v;
  return change.norm();
}

/// Fills data.interface.body_friction: the vertices with contacts with bodies and props whose
/// friction the implicit step did not solve, each with those contacts (paper §4.2's NCP).
void collect_body_friction(int cloth_meshes, WorldData& data) {
  InterfaceScratch& s = data.interface;
  const std::vector<ContactGroup>& groups = s.groups;
  s.body_friction.clear();
  std::size_t g = 0;
  while (g < groups.size()) {
    const std::size_t end = vertex_end(groups, g);
    const auto c = static_cast<std::size_t>(groups[g].cloth);
    const int i = groups[g].vertex;
    const std::vector<std::uint8_t>& solved = s.friction_state[c];
    const bool implicit = !solved.empty() && solved[static_cast<std::size_t>(i)] != 0;
    if (collision::is_fixed(data.meshes[c], i) || implicit) {
      g = end;
      continue;
    }
    BodyFriction b;
    b.cloth = groups[g].cloth;
    b.vertex = i;
    b.first = g;
    b.end = end;
    for (std::size_t k = g; k < end && b.count < b.contacts.size(); ++k) {
      const ContactGroup& cg = groups[k];
      if (cg.other_mesh < cloth_meshes) continue;  // cloth: its pairs' friction
      b.contacts[b.count] = {
          cg.normal, cg.normal_force,
          collision::pair_friction(data.meshes[c],
                                   data.meshes[static_cast<std::size_t>(cg.other_mesh)]),
          Vec3::Zero()};
      b.source[b.count++] = k;
    }
    b.coupled = s.pair_corner[c][static_cast<std::size_t>(i)] != 0;
    if (b.count > 0) s.body_friction.push_back(b);
    g = end;
  }
}

/// Friction already solved in the implicit step: a stuck vertex is position-constrained unless
/// it is still closing on a surface. Returns how many were frozen.
int freeze_implicit_stuck(double h, WorldData& data) {
  const InterfaceScratch& s = data.interface;
  const std::vector<ContactGroup>& groups = s.groups;
  int frozen = 0;
  for (std::size_t g = 0; g < groups.size();) {
    const std::size_t end = vertex_end(groups, g);
    const auto c = static_cast<std::size_t>(groups[g].cloth);
    const int i = groups[g].vertex;
    collision::CollisionMesh& mesh = data.meshes[c];
    const std::vector<std::uint8_t>& solved = s.friction_state[c];
    if (!collision::is_fixed(mesh, i) && !solved.empty() &&
        solved[static_cast<std::size_t>(i)] == 1 &&
        !closing(groups, g, end, (mesh.x1.row(i) - mesh.x0.row(i)).transpose() / h)) {
      mesh.frozen[static_cast<std::size_t>(i)] = collision::kHeldByFriction;
      ++frozen;
    }
    g = end;
  }
  return frozen;
}

}  // namespace

int apply_friction(double h, double coplanar_deg,
                   const std::vector<collision::CollisionMesh*>& meshes, WorldData& data) {
  const int cloth_meshes = static_cast<int>(data.cloths.size());
  const double coplanar_sin = std::sin(coplanar_deg * M_PI / 180.0);
  InterfaceScratch& s = data.interface;
  const std::vector<ContactGroup>& groups = s.groups;

  // Cloth against cloth (itself or another): equal and opposite impulses per proximity pair, so
  // the cloths keep their momentum. Vertices whose grip the implicit step solved are driven by
  // the hand and weigh as a body does.
  collision::PairFrictionOptions options;
  options.dt = h;
  options.cloth_only = true;
  options.held = &s.friction_state;
  s.pairs.prepare(meshes, data.contacts.proximities, data.contacts.impulses, options);
  s.pair_corner.resize(static_cast<std::size_t>(cloth_meshes));
  for (int c = 0; c < cloth_meshes; ++c)
    s.pair_corner[static_cast<std::size_t>(c)].assign(
        static_cast<std::size_t>(data.meshes[static_cast<std::size_t>(c)].x0.rows()), 0);
  s.pairs.mark_corners(s.pair_corner);

  collect_body_friction(cloth_meshes, data);

  // Block Gauss–Seidel: a sweep over the pairs, then the NCPs of the vertices some pair moves,
  // until neither changes (a layer on a table: its friction with the layer above and with the
  // table are solved together, or the upper layer slid on, dragging the lower one each step).
  for (int sweep = 0; sweep < kClothFrictionSweeps; ++sweep) {
    double worst = s.pairs.sweep();
    for (BodyFriction& b : s.body_friction)
      if (sweep == 0 || b.coupled)
        worst = std::max(worst, solve_body_friction(b, groups, h, coplanar_sin, data));
    if (worst <= kClothFrictionConverged) break;
  }
  // Position constraints (paper §3, §7.2) and the NCPs' residuals.
  int frozen = 0, unsolved = 0, worst_cloth = -1, worst_vertex = -1;
  double worst = 0.0;
  for (const BodyFriction& b : s.body_friction) {
    collision::CollisionMesh& mesh = data.meshes[static_cast<std::size_t>(b.cloth)];
    const FrictionResult& r = b.result;
    const Vec3 v = (mesh.x1.row(b.vertex) - mesh.x0.row(b.vertex)).transpose() / h;
    // Static friction holds the vertex as a position constraint through the refinement steps
    // only against a hand, gripper or dynamic obstacle. Frozen against cloth or a table, it
    // took the impact zones' whole push of the layers above it (infinite mass), and a crumpled
    // cloth rose and crawled across a table on its own. Never freeze a vertex still closing on
    // a surface: the impact zones must be free to stop it (a frozen vertex driven into an
    // obstacle cannot be resolved).
    bool on_body = false;
    if (r.which == FrictionCase::static_at) {
      const int m = groups[b.source[static_cast<std::size_t>(r.anchor)]].other_mesh;
      on_body = data.rigid.mesh_coupled[static_cast<std::size_t>(m - cloth_meshes)];
    }
    if (on_body && !closing(groups, b.first, b.end, v)) {
      mesh.frozen[static_cast<std::size_t>(b.vertex)] = collision::kHeldByFriction;
      ++frozen;
    }
    const std::span<const FrictionContact> problem(b.contacts.data(), b.count);
    if (r.violation > kFrictionWarnViolation &&
        friction_violation(problem, mesh.mass[b.vertex], h, r, coplanar_sin) * h * h /
                mesh.mass[b.vertex] >
            kFrictionWarnMotion) {
      ++unsolved;
      if (r.violation > worst) {
        worst = r.violation;
        worst_cloth = b.cloth;
        worst_vertex = b.vertex;
      }
    }
  }
  frozen += freeze_implicit_stuck(h, data);
  // One warning per step: how many vertices, and the worst (relative to its problem's force scale).
  if (unsolved > 0) {
    char worst_text[32], bound_text[32];
    std::snprintf(worst_text, sizeof worst_text, "%.1e", worst);
    std::snprintf(bound_text, sizeof bound_text, "%.0e", kFrictionWarnViolation);
    data.warnings.add(data.step, std::string("friction NCP not solved to ") + bound_text +
                                     " of the force scale at " +
                                     std::to_string(unsolved) +
                                     (unsolved == 1 ? " vertex" : " vertices") + "; worst: cloth " +
                                     std::to_string(worst_cloth) + " vertex " +
                                     std::to_string(worst_vertex) + ", violation " + worst_text +
                                     " of its force scale");
  }
  return frozen;
}

}  // namespace dexcloth::coupling
