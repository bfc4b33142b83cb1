#include "cloth/collision/collision_mesh.hpp"

#include "core/assert.hpp"

namespace dexcloth::collision {

void demand_valid(const CollisionMesh& mesh) {
  const Eigen::Index n = mesh.x0.rows();
  DEXCLOTH_DEMAND(mesh.x1.rows() == n);
  DEXCLOTH_DEMAND(mesh.frozen.empty() || static_cast<Eigen::Index>(mesh.frozen.size()) == n);
  DEXCLOTH_DEMAND(mesh.rest.rows() == 0 || mesh.rest.rows() == n);
  if (!mesh.obstacle) {
    DEXCLOTH_DEMAND(mesh.mass.size() == n);
    for (Eigen::Index i = 0; i < n; ++i) DEXCLOTH_DEMAND(mesh.mass[i] > 0.0);
  }
  DEXCLOTH_DEMAND(mesh.faces.size() == 0 || (mesh.faces.minCoeff() >= 0 && mesh.faces.maxCoeff() < n));
}

}  // namespace dexcloth::collision
