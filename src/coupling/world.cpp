#include "coupling/world.hpp"

#include "core/assert.hpp"

namespace dexcloth::coupling {

WorldData make_data(const WorldModel& model, RigidSide rigid) {
  WorldData data;
  data.rigid = std::move(rigid);
  data.rigid.world->export_obstacle_meshes(data.rigid.meshes);
  data.cloths.reserve(model.cloths.size());
  // Collision meshes: each cloth, then each rigid body's collision shapes.
  for (const ClothBody& body : model.cloths) {
    data.cloths.push_back(cloth::make_state(body.model, body.x_rest));
    collision::CollisionMesh mesh;
    mesh.x0 = mesh.x1 = body.x_rest;
    mesh.faces = body.model.faces;
    mesh.rest = body.x_rest;
    mesh.self_collision = model.self_collision;
    mesh.mass = body.model.mass;
    mesh.frozen.assign(static_cast<std::size_t>(body.x_rest.rows()), 0);
    mesh.friction = body.model.material.friction;
    data.meshes.push_back(std::move(mesh));
  }
  for (const rigid::ObstacleMesh& body : data.rigid.meshes) {
    collision::CollisionMesh mesh;
    mesh.x0 = mesh.x1 = body.x;
    mesh.faces = body.faces;
    mesh.mass = Eigen::VectorXd::Ones(body.x.rows());
    mesh.obstacle = true;
    mesh.friction = body.friction;
    data.meshes.push_back(std::move(mesh));
  }
  return data;
}

void set_threads(WorldModel& model, int threads) {
  DEXCLOTH_DEMAND(threads >= 1);
  model.threads = threads;
  // A small cloth's factorisation is done before the pool's threads would wake up.
  constexpr int kParallelVertices = 2000;
  for (ClothBody& body : model.cloths)
    body.model.solver.threads = body.model.num_vertices() >= kParallelVertices ? threads : 1;
}

bool state_is_finite(const WorldData& data) {
  for (const cloth::ClothState& s : data.cloths)
    if (!s.x.allFinite() || !s.v.allFinite()) return false;
  return true;
}

}  // namespace dexcloth::coupling
