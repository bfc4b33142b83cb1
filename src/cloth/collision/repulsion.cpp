#include "cloth/collision/repulsion.hpp"

#include <algorithm>
#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::collision {

namespace {

// The four corners of a pair resolved to their meshes, with inverse masses.
struct PairCorners {
  std::array<CollisionMesh*, 4> mesh{};
  std::array<int, 4> vertex{};
  std::array<double, 4> inv_mass{};
};

PairCorners resolve(const std::vector<CollisionMesh*>& meshes, const Proximity& p) {
  PairCorners c;
  for (int k = 0; k < 4; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    c.mesh[sk] = meshes[static_cast<std::size_t>(p.corner_mesh(k))];
    c.vertex[sk] = p.corner[sk];
    c.inv_mass[sk] = inverse_mass(*c.mesh[sk], c.vertex[sk]);
  }
  return c;
}

Vec3 velocity(const CollisionMesh& m, int v, double h) {
  return (m.x1.row(v) - m.x0.row(v)).transpose() / h;
}

// Relative velocity Σ w_k v_k of the pair's closest points.
Vec3 relative_velocity(const PairCorners& c, const Eigen::Vector4d& w, double h) {
  Vec3 v = Vec3::Zero();
  for (std::size_t k = 0; k < 4; ++k) v += w[static_cast<Eigen::Index>(k)] * velocity(*c.mesh[k], c.vertex[k], h);
  return v;
}

// Applies impulse J (vector) at the pair: corner k moves by h·w_k·J/m_k.
void apply_impulse(const PairCorners& c, const Eigen::Vector4d& w, const Vec3& impulse, double h) {
  for (std::size_t k = 0; k < 4; ++k) {
    if (c.inv_mass[k] == 0.0) continue;
    c.mesh[k]->x1.row(c.vertex[k]) +=
        (h * w[static_cast<Eigen::Index>(k)] * c.inv_mass[k] * impulse).transpose();
  }
}

}  // namespace

void apply_repulsion(const std::vector<CollisionMesh*>& meshes,
                     const std::vector<Proximity>& proximities, const RepulsionOptions& options,
                     std::vector<VertexContact>& contacts) {
  DEXCLOTH_DEMAND(options.dt > 0.0 && options.thickness > 0.0);
  const double h = options.dt;
  const std::size_t np = proximities.size();
  std::vector<double> lambda(np, 0.0), target(np, 0.0), inv_k(np, 0.0), friction(np, 0.0);

  // Target relative normal velocity of each pair (Bridson 2002 §7.2).
  for (std::size_t i = 0; i < np; ++i) {
    const Proximity& p = proximities[i];
    const PairCorners c = resolve(meshes, p);
    double k_eff = 0.0;
    for (std::size_t k = 0; k < 4; ++k) k_eff += p.w[static_cast<Eigen::Index>(k)] * p.w[static_cast<Eigen::Index>(k)] * c.inv_mass[k];
    inv_k[i] = k_eff;
    const double vn0 = p.normal.dot(relative_velocity(c, p.w, h));
    const double overlap = std::max(options.thickness - p.distance, 0.0);
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

  // Coulomb friction capped so it cannot reverse the relative tangential velocity (the
  // kinematic baseline): Δv_T = min(μ·Δv_N, |v_T|) with Δv_N = λ·K.
  if (options.friction) {
    for (std::size_t i = 0; i < np; ++i) {
      if (lambda[i] <= 0.0 || inv_k[i] == 0.0) continue;
      const Proximity& p = proximities[i];
      const PairCorners c = resolve(meshes, p);
      const Vec3 vr = relative_velocity(c, p.w, h);
      const Vec3 vt = vr - p.normal.dot(vr) * p.normal;
      const double vt_norm = vt.norm();
      if (vt_norm <= 0.0) continue;
      const double mu = pair_friction(*meshes[static_cast<std::size_t>(p.mesh[0])],
                                      *meshes[static_cast<std::size_t>(p.mesh[1])]);
      const double dv = std::min(mu * lambda[i] * inv_k[i], vt_norm);
      friction[i] = dv / inv_k[i];
      apply_impulse(c, p.w, -friction[i] / vt_norm * vt, h);
    }
  }

  // One record per cloth vertex of each pair that carries weight.
  contacts.clear();
  for (std::size_t i = 0; i < np; ++i) {
    const Proximity& p = proximities[i];
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
        vc.friction_impulse = std::abs(p.w[k]) * friction[i];
        vc.face_or_edge = side == 0 ? p.second : p.first;
        vc.weights = weights;
        vc.other_vertices = other_vertices;
        // inv_k: both sides' effective inverse masses (the sticking impulse is v_rel / inv_k).
        if (!vc.with_obstacle && inv_k[i] > 0.0)
          vc.friction_share = std::abs(p.w[k]) * c.inv_mass[static_cast<std::size_t>(k)] / inv_k[i];
        contacts.push_back(vc);
      }
    }
  }
}

}  // namespace dexcloth::collision
