#include "cloth/collision/cloth_contacts.hpp"

#include <algorithm>

namespace dexcloth::collision {

void detect_cloth_contacts(const std::vector<CollisionMesh*>& meshes,
                           const RepulsionOptions& options, ClothContacts& data) {
  const std::vector<const CollisionMesh*> view(meshes.begin(), meshes.end());
  find_proximities(view, options.thickness, data.candidates, data.proximities,
                   data.proximity_scratch);
  apply_repulsion(meshes, data.proximities, options, data.contacts, data.impulses);
}

ContactVertexSets contact_vertex_sets(const std::vector<VertexContact>& contacts, int mesh) {
  ContactVertexSets sets;
  for (const VertexContact& c : contacts) {
    if (c.mesh != mesh) continue;
    (c.with_obstacle ? sets.obstacle : sets.cloth).push_back(c.vertex);
  }
  for (std::vector<int>* s : {&sets.obstacle, &sets.cloth}) {
    std::sort(s->begin(), s->end());
    s->erase(std::unique(s->begin(), s->end()), s->end());
  }
  return sets;
}

}  // namespace dexcloth::collision
