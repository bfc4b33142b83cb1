#include "coupling/contact_forces.hpp"

#include <algorithm>
#include <limits>

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

void assign_normal_forces(int cloth_meshes, double reach, WorldData& data) {
  std::vector<ContactGroup>& groups = data.interface.groups;
  const RigidSide& rigid = data.rigid;
  if (!rigid.world) return;
  const rigid::PatchPool& pool = rigid.world->patches();
  const auto is_patch = [&](rigid::BodyId b) {
    for (int p = 0; p < pool.capacity(); ++p)
      if (pool.active(p) && pool.body(p).index == b.index) return true;
    return false;
  };
  // Count, per (body mesh, contact), how many vertices take it.
  std::vector<std::vector<int>>& takers = data.interface.takers;
  takers.resize(rigid.meshes.size());
  for (std::size_t m = 0; m < rigid.meshes.size(); ++m)
    takers[m].assign(rigid.world->contacts(rigid.mesh_body[m]).size(), 0);
  for (ContactGroup& g : groups) {
    const int m = g.other_mesh - cloth_meshes;
    if (m < 0) continue;
    const auto& contacts = rigid.world->contacts(rigid.mesh_body[static_cast<std::size_t>(m)]);
    const Vec3 x = data.meshes[static_cast<std::size_t>(g.cloth)].x0.row(g.vertex).transpose();
    double best = reach;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const double d = (contacts[c].p_W - x).norm();
      if (d < best && contacts[c].f_n > 0.0 && is_patch(contacts[c].other)) {
        best = d;
        g.rigid_contact = static_cast<int>(c);
      }
    }
    if (g.rigid_contact >= 0) ++takers[static_cast<std::size_t>(m)][static_cast<std::size_t>(g.rigid_contact)];
  }
  // Each contact's normal force is shared among the vertices that took it.
  for (ContactGroup& g : groups) {
    if (g.rigid_contact < 0) continue;
    const auto m = static_cast<std::size_t>(g.other_mesh - cloth_meshes);
    const auto& c = rigid.world->contacts(rigid.mesh_body[m])[static_cast<std::size_t>(g.rigid_contact)];
    g.normal_force = c.f_n / takers[m][static_cast<std::size_t>(g.rigid_contact)];
  }
}

int apply_friction(double h, WorldData& data) {
  const std::vector<ContactGroup>& groups = data.interface.groups;
  int frozen = 0;
  std::array<FrictionContact, kMaxVertexContacts> contacts;
  std::size_t g = 0;
  while (g < groups.size()) {
    // The groups of one vertex are consecutive.
    std::size_t end = g;
    while (end < groups.size() && groups[end].cloth == groups[g].cloth &&
           groups[end].vertex == groups[g].vertex)
      ++end;
    collision::CollisionMesh& mesh = data.meshes[static_cast<std::size_t>(groups[g].cloth)];
    const int i = groups[g].vertex;
    if (!collision::is_fixed(mesh, i)) {
      const Vec3 v = (mesh.x1.row(i) - mesh.x0.row(i)).transpose() / h;
      const int count = static_cast<int>(std::min<std::size_t>(end - g, kMaxVertexContacts));
      for (int k = 0; k < count; ++k) {
        const ContactGroup& cg = groups[g + static_cast<std::size_t>(k)];
        const collision::CollisionMesh& other = data.meshes[static_cast<std::size_t>(cg.other_mesh)];
        contacts[static_cast<std::size_t>(k)] = {cg.normal, cg.normal_force,
                                                 collision::pair_friction(mesh, other),
                                                 v - cg.other_velocity};
      }
      const FrictionResult r = solve_friction(
          std::span<const FrictionContact>(contacts.data(), static_cast<std::size_t>(count)),
          mesh.mass[i], h);
      mesh.x1.row(i) += h * r.delta_v.transpose();
      // Static friction: a position constraint through the refinement steps (paper §3, §7.2).
      if (r.which == FrictionCase::static_at) {
        mesh.frozen[static_cast<std::size_t>(i)] = 1;
        ++frozen;
      }
      if (!r.ok)
        data.warnings.add(data.step, "friction NCP at cloth " + std::to_string(groups[g].cloth) +
                                         " vertex " + std::to_string(i) + " not solved to tolerance");
    }
    g = end;
  }
  return frozen;
}

}  // namespace dexcloth::coupling
