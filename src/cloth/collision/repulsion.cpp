#include "cloth/collision/repulsion.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/collision/pair_corners.hpp"
#include "cloth/collision/pair_friction.hpp"
#include "core/assert.hpp"

namespace dexcloth::collision {

void apply_repulsion(const std::vector<CollisionMesh*>& meshes,
                     const std::vector<Proximity>& proximities, const RepulsionOptions& options,
                     std::vector<VertexContact>& contacts, std::vector<double>& impulses) {
  DEXCLOTH_DEMAND(options.dt > 0.0 && options.thickness > 0.0);
  const double h = options.dt;
  const std::size_t np = proximities.size();
  std::vector<double>& lambda = impulses;
  lambda.assign(np, 0.0);
  std::vector<double> target(np, 0.0), inv_k(np, 0.0);
  std::vector<Vec3> friction(np, Vec3::Zero());

  // Target relative normal velocity of each pair (Bridson 2002 §7.2).
  for (std::size_t i = 0; i < np; ++i) {
    const Proximity& p = proximities[i];
    const PairCorners c = resolve(meshes, p);
    const double k_eff = effective_inverse_mass(c, p.w);
    inv_k[i] = k_eff;
    const double vn0 = p.normal.dot(relative_velocity(c, p.w, h));
    const double overlap = options.thickness - p.distance;
    if (overlap <= 0.0) {
      // Beyond the thickness (an obstacle's pair within reach): close at most to it.
      target[i] = std::max(vn0, overlap / h);
      continue;
    }
    // Inelastic: stop the approach; spring: push apart by h·k·d, at most to 0.1·d/h.
    const double spring = std::min(std::max(vn0, 0.0) + h * options.stiffness * overlap * k_eff,
                                   0.1 * overlap / h);
    target[i] = std::max(vn0, spring);
  }

  // Gauss–Seidel on accumulated normal impulses λ ≥ 0 until every target is met.
  for (int sweep = 0; sweep < options.iterations; ++sweep) {
    double worst = 0.0;
    for (std::size_t i = 0; i < np; ++i) {
      if (inv_k[i] == 0.0) continue;
      const Proximity& p = proximities[i];
      const PairCorners c = resolve(meshes, p);
      const double vn = p.normal.dot(relative_velocity(c, p.w, h));
      const double dl = std::max(-lambda[i], (target[i] - vn) / inv_k[i]);
      if (dl == 0.0) continue;
      lambda[i] += dl;
      worst = std::max(worst, std::abs(dl) * inv_k[i]);
      apply_impulse(c, p.w, dl * p.normal, h);
    }
    if (worst <= 1e-12) break;
  }

  // Coulomb friction in one capped pass (the kinematic baseline): it cannot reverse the relative
  // tangential velocity, Δv_T = min(μ·Δv_N, |v_T|) with Δv_N = λ·K.
  if (options.friction) {
    PairFrictionOptions pair;
    pair.dt = h;
    pair.sweeps = 1;
    apply_pair_friction(meshes, proximities, lambda, pair, friction);
  }

  // One record per cloth vertex of each pair that carries weight, of the pairs within the
  // thickness and of those beyond it that the step closed to it.
  contacts.clear();
  for (std::size_t i = 0; i < np; ++i) {
    const Proximity& p = proximities[i];
    if (p.distance >= options.thickness && lambda[i] == 0.0) continue;
    const PairCorners c = resolve(meshes, p);
    for (int side = 0; side < 2; ++side) {
      const int mesh = p.mesh[static_cast<std::size_t>(side)];
      const int other = p.mesh[static_cast<std::size_t>(1 - side)];
      if (meshes[static_cast<std::size_t>(mesh)]->obstacle) continue;
      const int begin = side == 0 ? 0 : (p.edge_edge ? 2 : 1);
      const int end = side == 0 ? (p.edge_edge ? 2 : 1) : 4;
      const int other_begin = side == 0 ? end : 0;
      const int other_end = side == 0 ? 4 : begin;
      // Velocity and weights of the touching point on the other side.
      Vec3 other_velocity = Vec3::Zero();
      Vec3 weights = Vec3::Zero();
      std::array<int, 3> other_vertices{-1, -1, -1};
      double other_weight = 0.0;
      for (int k = other_begin; k < other_end; ++k) other_weight += std::abs(p.w[k]);
      for (int k = other_begin; k < other_end; ++k) {
        const double wk = std::abs(p.w[k]) / other_weight;
        other_velocity += wk * velocity(*c.mesh[static_cast<std::size_t>(k)], c.vertex[static_cast<std::size_t>(k)], h);
        weights[k - other_begin] = wk;
        other_vertices[static_cast<std::size_t>(k - other_begin)] = c.vertex[static_cast<std::size_t>(k)];
      }
      for (int k = begin; k < end; ++k) {
        if (p.w[k] == 0.0) continue;
        VertexContact vc;
        vc.mesh = mesh;
        vc.vertex = p.corner[static_cast<std::size_t>(k)];
        vc.other_mesh = other;
        vc.with_obstacle = meshes[static_cast<std::size_t>(other)]->obstacle;
        vc.kind = p.edge_edge ? ContactKind::EdgeEdge
                              : (side == 0 ? ContactKind::VertexFace : ContactKind::FaceVertex);
        vc.normal = side == 0 ? p.normal : Vec3(-p.normal);
        vc.distance = p.distance;
        vc.other_velocity = other_velocity;
        vc.normal_impulse = std::abs(p.w[k]) * lambda[i];
        vc.friction_impulse = std::abs(p.w[k]) * friction[i].norm();
        vc.face_or_edge = side == 0 ? p.second : p.first;
        vc.weights = weights;
        vc.other_vertices = other_vertices;
        contacts.push_back(vc);
      }
    }
  }
}

}  // namespace dexcloth::collision
