#include "coupling/speculative_touches.hpp"

#include <algorithm>
#include <tuple>

#include "cloth/collision/proximity.hpp"

namespace dexcloth::coupling {

namespace {

/// A driven body moving more than this many repulsion thicknesses in a step is searched ahead.
/// A slower one comes within a thickness of the cloth at some step's start, where the patches
/// see it, before its predicted pose can pass through the cloth (a box landing at 0.7 m/s, 3.5
/// mm a step, lands cleanly without).
constexpr double kFastStepThicknesses = 0.5;

/// The reach ahead of a body in steps of its approach speed: the next cloth step sweeps it one
/// step on from its predicted pose (through cloth nearer than that), and a quarter step more
/// covers the speed it may gain meanwhile (a body falling at 1 m/s gains 5 %).
constexpr double kReachSteps = 1.25;

/// A body's vertex velocities in the next step, `v` and the change since the last step's `last`
/// again (a jaw closing under a constant force gains 0.09 m/s a step); `v` where there is none.
void expected_velocity(const Points& v, const Points& last, Points& out) {
  if (last.rows() == v.rows())
    out = 2.0 * v - last;
  else
    out = v;
}

/// `source` as the search sees it: at its end-of-step positions x1, not moving.
void at_end(const collision::CollisionMesh& source, collision::CollisionMesh& out) {
  out.x0 = source.x1;
  out.x1 = source.x1;
  out.faces = source.faces;
  out.mass = source.mass;
  out.frozen.clear();
  out.rest.resize(0, 3);
  out.obstacle = source.obstacle;
  out.self_collision = false;
  out.friction = source.friction;
}

}  // namespace

void find_speculative_groups(const WorldModel& model, int cloth_meshes, WorldData& data) {
  SpeculativeScratch& s = data.speculative;
  s.groups.clear();
  const double h = model.dt, thickness = model.thickness;
  const std::size_t bodies = data.rigid.meshes.size();
  s.velocity.resize(bodies);
  s.last_velocity.resize(bodies);
  s.fast.assign(bodies, 0);
  double fastest = 0.0;
  for (std::size_t m = 0; m < bodies; ++m) {
    const Points& v = data.rigid.meshes[m].v;
    if (!data.rigid.mesh_coupled[m] || v.rows() == 0) continue;  // DART does not stop these
    expected_velocity(v, s.last_velocity[m], s.velocity[m]);
    s.last_velocity[m] = v;
    const double speed = s.velocity[m].rowwise().norm().maxCoeff();
    if (h * speed <= kFastStepThicknesses * thickness) continue;
    s.fast[m] = 1;
    fastest = std::max(fastest, speed);
  }
  if (fastest == 0.0) return;
  const double reach = kReachSteps * h * fastest;
  // A cloth, then every body in its place (empty unless fast, so each keeps its tree and
  // topology while it stays fast).
  s.meshes.resize(1 + bodies);
  for (std::size_t m = 0; m < bodies; ++m) {
    collision::CollisionMesh& mesh = s.meshes[1 + m];
    if (s.fast[m]) {
      at_end(data.meshes[static_cast<std::size_t>(cloth_meshes) + m], mesh);
    } else {
      mesh.x0.resize(0, 3);
      mesh.x1.resize(0, 3);
      mesh.faces.resize(0, 3);
      mesh.mass.resize(0);
      mesh.frozen.clear();
      mesh.obstacle = true;
    }
  }
  if (s.candidates.size() != static_cast<std::size_t>(cloth_meshes))
    s.candidates.resize(static_cast<std::size_t>(cloth_meshes));
  std::vector<const collision::CollisionMesh*> view;
  for (const collision::CollisionMesh& m : s.meshes) view.push_back(&m);
  struct Found {
    ContactGroup group;
    double distance;
  };
  std::vector<Found> found;
  for (int c = 0; c < cloth_meshes; ++c) {
    at_end(data.meshes[static_cast<std::size_t>(c)], s.meshes[0]);
    s.candidates[static_cast<std::size_t>(c)].set_pool(data.contacts.candidates.pool());
    collision::find_proximities(view, reach, s.candidates[static_cast<std::size_t>(c)], s.found);
    for (const collision::Proximity& p : s.found) {
      // Cloth vertex against body face (a body's corner poking between cloth vertices has the
      // faces around it within reach of those vertices too).
      if (p.edge_edge || p.mesh[0] != 0 || p.mesh[1] == 0) continue;
      const int body = p.mesh[1] - 1;
      const Points& v = s.velocity[static_cast<std::size_t>(body)];
      Vec3 velocity = Vec3::Zero();
      for (int j = 1; j < 4; ++j)
        velocity -= p.w[j] * v.row(p.corner[static_cast<std::size_t>(j)]).transpose();
      const double approach = std::max(0.0, velocity.dot(p.normal));
      if (p.distance >= kReachSteps * h * approach) continue;
      ContactGroup g;
      g.cloth = c;
      g.vertex = p.first;
      g.other_mesh = cloth_meshes + body;
      g.normal = p.normal;
      g.other_velocity = velocity;
      g.other_vertices = {p.corner[1], p.corner[2], p.corner[3]};
      g.other_weights = Vec3(-p.w[1], -p.w[2], -p.w[3]);
      g.speculative = true;
      found.push_back({g, p.distance});
    }
  }
  // The nearest record of each (vertex, body).
  std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
    return std::tie(a.group.cloth, a.group.vertex, a.group.other_mesh, a.distance) <
           std::tie(b.group.cloth, b.group.vertex, b.group.other_mesh, b.distance);
  });
  for (std::size_t k = 0; k < found.size(); ++k)
    if (k == 0 || found[k].group.cloth != found[k - 1].group.cloth ||
        found[k].group.vertex != found[k - 1].group.vertex ||
        found[k].group.other_mesh != found[k - 1].group.other_mesh)
      s.groups.push_back(found[k].group);
}

void merge_speculative_groups(const std::vector<ContactGroup>& real,
                              const std::vector<ContactGroup>& speculative,
                              std::vector<ContactGroup>& out) {
  out.clear();
  std::vector<char> used(speculative.size(), 0);
  const auto vertex_less = [](const ContactGroup& a, const ContactGroup& b) {
    return std::tie(a.cloth, a.vertex) < std::tie(b.cloth, b.vertex);
  };
  for (std::size_t first = 0, end = 0; first < real.size(); first = end) {
    end = vertex_end(real, first);
    out.insert(out.end(), real.begin() + static_cast<std::ptrdiff_t>(first),
               real.begin() + static_cast<std::ptrdiff_t>(end));
    auto [lo, hi] =
        std::equal_range(speculative.begin(), speculative.end(), real[first], vertex_less);
    for (auto it = lo; it != hi; ++it) {
      used[static_cast<std::size_t>(it - speculative.begin())] = 1;
      const bool touched =
          std::any_of(real.begin() + static_cast<std::ptrdiff_t>(first),
                      real.begin() + static_cast<std::ptrdiff_t>(end),
                      [&](const ContactGroup& g) { return g.other_mesh == it->other_mesh; });
      if (!touched) out.push_back(*it);
    }
  }
  for (std::size_t k = 0; k < speculative.size(); ++k)
    if (!used[k]) out.push_back(speculative[k]);
}

}  // namespace dexcloth::coupling
