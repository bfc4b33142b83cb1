#include "coupling/patch_update.hpp"

#include <algorithm>

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

int update_patches(const WorldModel& model, int cloth_meshes, WorldData& data) {
  rigid::PatchPool& pool = data.rigid.world->patches();
  pool.deactivate_all();
  data.patches.clear();
  const double h = model.dt;
  const std::vector<ContactGroup>& groups = data.interface.groups;
  int placed = 0;
  for (int c = 0; c < cloth_meshes; ++c) {
    const collision::CollisionMesh& mesh = data.meshes[static_cast<std::size_t>(c)];
    // Vertices of this cloth touching an actuated rigid body, once each.
    data.patch_vertex_ids.clear();
    for (const ContactGroup& g : groups) {
      const int m = g.other_mesh - cloth_meshes;
      if (g.cloth == c && m >= 0 && data.rigid.mesh_actuated[static_cast<std::size_t>(m)] &&
          (data.patch_vertex_ids.empty() || data.patch_vertex_ids.back() != g.vertex))
        data.patch_vertex_ids.push_back(g.vertex);
    }
    if (data.patch_vertex_ids.empty()) continue;
    vertex_normals(mesh.faces, mesh.x1, data.normals);
    data.patch_vertices.clear();
    for (int i : data.patch_vertex_ids)
      data.patch_vertices.push_back({mesh.x1.row(i).transpose(),
                                     (mesh.x1.row(i) - mesh.x0.row(i)).transpose() / h,
                                     data.normals.row(i).transpose(), mesh.mass[i]});
    // Cluster (eqs. 9–11) and fit one thin box per cluster.
    const auto clusters = cluster_vertices(data.patch_vertices, model.clusters);
    // The cloth keeps obstacles one repulsion thickness away on each side, so a patch as thick
    // as 2 × thickness makes a pinch close to where the repulsion of both jaws is just met;
    // thinner patches let the jaws in closer than the two repulsion layers, whose opposite
    // targets cannot both be met and the cloth is squeezed out sideways.
    const double thickness = 2.0 * model.thickness;
    for (const auto& cluster : clusters) {
      RigidPatch patch = build_patch(data.patch_vertices, cluster, thickness, 2.0 * model.thickness);
      for (int& k : patch.vertices) k = data.patch_vertex_ids[static_cast<std::size_t>(k)];
      patch.cloth = c;
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
    s.w_W = patch.angular_velocity;
    s.mass = patch.mass;
    s.layer = patch.cloth;  // patches of stacked cloths press on each other
    pool.set(placed++, s);
  }
  return placed;
}

}  // namespace dexcloth::coupling
