#include "coupling/patch_update.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "coupling/speculative_touches.hpp"

namespace dexcloth::coupling {

void vertex_normals(const Triangles& faces, const Points& x, Points& normals) {
  normals.setZero(x.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const int a = faces(f, 0), b = faces(f, 1), c = faces(f, 2);
    const Vec3 n = (x.row(b) - x.row(a)).transpose().cross((x.row(c) - x.row(a)).transpose());
    normals.row(a) += n.transpose();
    normals.row(b) += n.transpose();
    normals.row(c) += n.transpose();
  }
  for (Eigen::Index i = 0; i < normals.rows(); ++i) {
    const double len = normals.row(i).norm();
    if (len > 0.0) normals.row(i) /= len;
  }
}

Vec3 clustering_normal(const Vec3& n, std::span<const ContactGroup> groups, int cloth_meshes) {
  Vec3 sum = Vec3::Zero();
  for (const ContactGroup& g : groups)
    if (g.other_mesh >= cloth_meshes) sum += g.normal.dot(n) >= 0.0 ? g.normal : Vec3(-g.normal);
  return sum.norm() > 0.0 ? Vec3(sum.normalized()) : n;
}

Vec3 body_normal(const ContactGroup& group, const Points& x, const Triangles& faces,
                 const collision::MeshTopology& topology) {
  const std::array<int, 3>& v = group.other_vertices;
  const auto face_normal = [&](int f) -> Vec3 {
    const Vec3 a = x.row(faces(f, 0)).transpose();
    return (x.row(faces(f, 1)).transpose() - a).cross(x.row(faces(f, 2)).transpose() - a);
  };
  Vec3 n = Vec3::Zero();
  if (v[2] >= 0) {
    n = (x.row(v[1]) - x.row(v[0])).transpose().cross((x.row(v[2]) - x.row(v[0])).transpose());
    n.normalize();
  } else if (v[0] >= 0 && topology.num_vertices == x.rows()) {
    // The body's faces around the touching corner (or the edge's two ends), in face order: the
    // one facing the cloth most.
    const auto star = [&](int i) -> std::pair<int, int> {
      if (i < 0) return {0, 0};
      return {topology.vertex_face_start[static_cast<std::size_t>(i)],
              topology.vertex_face_start[static_cast<std::size_t>(i) + 1]};
    };
    auto [p, p_end] = star(v[0]);
    auto [q, q_end] = star(v[1]);
    const auto face_at = [&](int k) { return topology.vertex_faces[static_cast<std::size_t>(k)]; };
    double best = -1.0;
    while (p < p_end || q < q_end) {
      // The next face of the two ascending lists, once.
      const int f = q == q_end || (p < p_end && face_at(p) <= face_at(q)) ? face_at(p) : face_at(q);
      while (p < p_end && face_at(p) == f) ++p;
      while (q < q_end && face_at(q) == f) ++q;
      const Vec3 m = face_normal(f);
      const double len = m.norm();
      if (!(len > 0.0)) continue;
      const double facing = std::abs(m.dot(group.normal)) / len;
      if (facing > best) {
        best = facing;
        n = m / len;
      }
    }
  }
  if (!(n.norm() > 0.5)) return group.normal;
  return n.dot(group.normal) >= 0.0 ? n : Vec3(-n);
}

namespace {

/// How far inside the cloth's repulsion layers the fingers of a pinch rest, in thicknesses.
constexpr double kPinchMargin = 0.01;
/// Two clusters pressed from opposite sides are two layers when a vertex of one lies over the
/// other within this many thicknesses of its vertices' hull (join_facing_clusters).
constexpr double kOverlapThicknesses = 0.5;

/// The rigid surface points (at the rigid bodies' current poses) and normals touching the cloth
/// vertices of one cluster, from their contact groups' heaviest records, into `out`. A
/// speculative touch is on its fast body's predicted pose x + h·v moved back by one DART substep
/// (`last_substep` [s]) of the body's extrapolated velocity and pressed in by `press` [m]: about
/// where the body starts its last substep, so a box reaching there meets it within the step and
/// DART stops it. With one substep that is behind the surface of a body that sped up (by h
/// times its last change of velocity): the box then overlaps it, and DART holds it where it is.
void surface_touches(const std::vector<int>& cluster, const std::vector<ContactGroup>& groups,
                     int cloth_meshes, double last_substep, double press, const WorldData& data,
                     std::vector<SurfaceTouch>& out) {
  out.clear();
  for (int k : cluster) {
    const auto [first, end] = data.patch_vertex_groups[static_cast<std::size_t>(k)];
    for (int g = first; g < end; ++g) {
      const ContactGroup& group = groups[static_cast<std::size_t>(g)];
      if (group.other_mesh < cloth_meshes || group.other_vertices[0] < 0) continue;
      const auto body = static_cast<std::size_t>(group.other_mesh - cloth_meshes);
      // A speculative touch is on the body's predicted pose.
      const Points& x = group.speculative
                            ? data.meshes[static_cast<std::size_t>(group.other_mesh)].x1
                            : data.rigid.meshes[body].x;
      Vec3 point = Vec3::Zero();
      for (int j = 0; j < 3; ++j)
        if (group.other_vertices[static_cast<std::size_t>(j)] >= 0)
          point += group.other_weights[j] *
                   x.row(group.other_vertices[static_cast<std::size_t>(j)]).transpose();
      if (group.speculative) point -= last_substep * group.other_velocity + press * group.normal;
      const collision::MeshTopology& topology = data.contacts.candidates.topology(group.other_mesh);
      out.push_back({point, body_normal(group, x, data.rigid.meshes[body].faces, topology),
                     !data.rigid.mesh_coupled[body], group.speculative, static_cast<int>(body)});
    }
  }
}

/// The cloth layers of a cluster between two fingers: the cloths it holds vertices of, and the
/// cloths those vertices touch that have none in it (the middle layers of cloths stacked
/// between two fingers, which touch no finger).
int cloth_layers(const std::vector<int>& cluster, const std::vector<ContactGroup>& groups,
                 int cloth_meshes, const WorldData& data) {
  std::vector<char> held(static_cast<std::size_t>(cloth_meshes), 0), touched = held;
  for (int k : cluster) {
    held[static_cast<std::size_t>(data.patch_vertex_ids[static_cast<std::size_t>(k)].first)] = 1;
    const auto [first, end] = data.patch_vertex_groups[static_cast<std::size_t>(k)];
    for (int g = first; g < end; ++g)
      if (groups[static_cast<std::size_t>(g)].other_mesh < cloth_meshes)
        touched[static_cast<std::size_t>(groups[static_cast<std::size_t>(g)].other_mesh)] = 1;
  }
  int n = 0;
  for (int c = 0; c < cloth_meshes; ++c)
    n += held[static_cast<std::size_t>(c)] || touched[static_cast<std::size_t>(c)];
  return n;
}

}  // namespace

int update_patches(const WorldModel& model, int cloth_meshes, WorldData& data) {
  rigid::PatchPool& pool = data.rigid.world->patches();
  pool.deactivate_all();
  data.patches.clear();
  const double h = model.dt;
  // The step's contact groups, with the touches ahead of fast bodies when there are any.
  find_speculative_groups(model, cloth_meshes, data);
  if (!data.speculative.groups.empty())
    merge_speculative_groups(data.interface.groups, data.speculative.groups,
                             data.speculative.merged);
  const std::vector<ContactGroup>& groups =
      data.speculative.groups.empty() ? data.interface.groups : data.speculative.merged;
  // Between two bodies (a pinch) DART lets each rest its contact allowance deep in the patch;
  // the patch is thicker by that, less a small margin, so the fingers rest just inside the
  // cloth's two repulsion layers: the vertex stays in contact with both, and the layers barely
  // overlap. Fingers 2 × allowance closer (a patch of 2 × thickness) squeezed the cloth between
  // two repulsions that cannot both be met; it jittered across the gap and crept out of a grip
  // at 1.1 N* (2.5 mm over 1 s); at the layers' edge exactly, its contacts flickered.
  const double allowance = data.rigid.world ? data.rigid.world->contact_allowance() : 0.0;
  const int substeps = data.rigid.world ? data.rigid.world->substeps() : 1;
  const double pinched_thickness =
      2.0 * model.thickness + 2.0 * (allowance - kPinchMargin * model.thickness);
  int placed = 0;
  // Vertices of every cloth touching an actuated rigid body, once each, with the run of their
  // contact groups (the groups of one vertex are consecutive). All cloths are clustered
  // together: layers of different cloths between two fingers make one stack, as the layers of
  // a fold of one cloth do.
  data.patch_vertex_ids.clear();
  data.patch_vertex_groups.clear();
  data.patch_vertices.clear();
  const auto actuated = [&](const ContactGroup& g) {
    const int m = g.other_mesh - cloth_meshes;
    return m >= 0 && data.rigid.mesh_coupled[static_cast<std::size_t>(m)];
  };
  for (int c = 0; c < cloth_meshes; ++c) {
    const collision::CollisionMesh& mesh = data.meshes[static_cast<std::size_t>(c)];
    const std::size_t first_of_cloth = data.patch_vertex_ids.size();
    for (std::size_t first = 0, end = 0; first < groups.size(); first = end) {
      end = vertex_end(groups, first);
      const auto run = groups.begin() + static_cast<std::ptrdiff_t>(first);
      if (groups[first].cloth != c ||
          std::none_of(run, groups.begin() + static_cast<std::ptrdiff_t>(end), actuated))
        continue;
      data.patch_vertex_ids.emplace_back(c, groups[first].vertex);
      data.patch_vertex_groups.emplace_back(static_cast<int>(first), static_cast<int>(end));
    }
    if (data.patch_vertex_ids.size() == first_of_cloth) continue;
    vertex_normals(mesh.faces, mesh.x1, data.normals);
    for (std::size_t k = first_of_cloth; k < data.patch_vertex_ids.size(); ++k) {
      const int i = data.patch_vertex_ids[k].second;
      const auto [first, end] = data.patch_vertex_groups[k];
      const std::span<const ContactGroup> touching(groups.data() + first, groups.data() + end);
      const Vec3 n = clustering_normal(data.normals.row(i).transpose(), touching, cloth_meshes);
      data.patch_vertices.push_back({mesh.x1.row(i).transpose(),
                                     (mesh.x1.row(i) - mesh.x0.row(i)).transpose() / h, n,
                                     mesh.mass[i]});
    }
  }
  if (!data.patch_vertex_ids.empty()) {
    // Cluster (eqs. 9–11, on the touched surfaces' normals) and fit one thin box per cluster.
    auto clusters = cluster_vertices(data.patch_vertices, model.clusters);
    // A fold of a cloth, or layers of cloths, squeezed between two fingers clusters into one
    // layer per finger, each a free patch its finger pushes aside: join facing layers into one
    // stack.
    std::vector<std::vector<SurfaceTouch>>& touches = data.cluster_touches;
    touches.resize(clusters.size());
    for (std::size_t k = 0; k < clusters.size(); ++k)
      surface_touches(clusters[k], groups, cloth_meshes, h / substeps, allowance, data, touches[k]);
    const std::vector<int> layers = join_facing_clusters(
        clusters, touches, data.patch_vertices, 4.0 * model.thickness + model.clusters.offset,
        model.clusters.distance, kOverlapThicknesses * model.thickness);
    // The cloth keeps obstacles one repulsion thickness away on each side, so a patch as thick
    // as 2 × thickness makes a pinch close to where the repulsion of both jaws is just met;
    // thinner patches let the jaws in closer than the two repulsion layers, whose opposite
    // targets cannot both be met and the cloth is squeezed out sideways.
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      const std::vector<int>& cluster = clusters[k];
      RigidPatch patch = build_patch(data.patch_vertices, cluster, 2.0 * model.thickness,
                                     2.0 * model.thickness);
      // n layers between two fingers keep n + 1 repulsion thicknesses between them: the cloths
      // of a stack, those between its outer layers that touch no finger included (whether the
      // outer layers clustered apart or together), or the layers of a fold of one cloth.
      const int cloths = cloth_layers(cluster, groups, cloth_meshes, data);
      const int n = cloths > 1 ? cloths : layers[k];
      // Pressed onto a support (a table) instead, the cloth lies on it and the body rests one
      // repulsion thickness above each layer.
      if (!centre_between_surfaces(patch, touches[k],
                                   pinched_thickness + (n - 1) * model.thickness))
        lay_on_support(patch, touches[k],
                       n * model.thickness + allowance - kPinchMargin * model.thickness);
      patch.cloths.clear();
      for (int& v : patch.vertices) {
        const auto [c, i] = data.patch_vertex_ids[static_cast<std::size_t>(v)];
        patch.cloths.push_back(c);
        v = i;
      }
      data.patches.push_back(std::move(patch));
    }
  }
  // Largest patches first when the pool is too small.
  if (static_cast<int>(data.patches.size()) > pool.capacity()) {
    std::sort(data.patches.begin(), data.patches.end(),
              [](const RigidPatch& a, const RigidPatch& b) { return a.mass > b.mass; });
    data.warnings.add(data.step, std::to_string(data.patches.size()) +
                                     " rigid cloth patches exceed the pool of " +
                                     std::to_string(pool.capacity()) + "; the lightest are dropped");
  }
  for (const RigidPatch& patch : data.patches) {
    if (placed >= pool.capacity()) break;
    rigid::PatchState s;
    s.active = true;
    s.extents = Vec2(patch.size.x(), patch.size.y());
    s.thickness = patch.size.z();
    s.X_WP.linear() = patch.R;
    s.X_WP.translation() = patch.center;
    s.v_W = patch.linear_velocity;
    // Placed without turning. The rotation fitted to a flat cluster's vertex velocities mostly
    // measures how the cloth deforms (squeezed, rippling), not a turn: in a carried pinch it
    // tilted the box at about 1 rad/s (up to 8), so at the pads' contacts, 12 mm apart across
    // the box, the box drew away from both at 2–4 cm/s, DART needed no force to keep them out,
    // and the squeeze fell from 0.3–0.9 N to 0.005 N until the sheet slid out. The box still
    // turns as the contacts turn it, and is refitted from the cloth every step.
    s.w_W = Vec3::Zero();
    s.mass = patch.mass;
    // Patches of one layer never collide; patches of other cloths (stacked) press on each other.
    s.layer = *std::min_element(patch.cloths.begin(), patch.cloths.end());
    pool.set(placed++, s);
  }
  return placed;
}

}  // namespace dexcloth::coupling
