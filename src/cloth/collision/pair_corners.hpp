#pragma once
/// The four corners of a proximity pair resolved to their meshes, and the pair's velocities and
/// impulses through its corner weights (shared by the repulsion and the pair friction).
#include <array>
#include <cstdint>
#include <vector>

#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/proximity.hpp"

namespace dexcloth::collision {

struct PairCorners {
  std::array<CollisionMesh*, 4> mesh{};
  std::array<int, 4> vertex{};
  std::array<double, 4> inv_mass{};  ///< 0 for fixed vertices (infinitely heavy)
};

/// Corners of `p`; with `held`, per mesh, a nonzero entry also makes a vertex infinitely heavy.
inline PairCorners resolve(const std::vector<CollisionMesh*>& meshes, const Proximity& p,
                           const std::vector<std::vector<std::uint8_t>>* held = nullptr) {
  PairCorners c;
  for (int k = 0; k < 4; ++k) {
    const auto sk = static_cast<std::size_t>(k);
    const auto m = static_cast<std::size_t>(p.corner_mesh(k));
    c.mesh[sk] = meshes[m];
    c.vertex[sk] = p.corner[sk];
    c.inv_mass[sk] = inverse_mass(*c.mesh[sk], c.vertex[sk]);
    if (held != nullptr && m < held->size() && !(*held)[m].empty() &&
        (*held)[m][static_cast<std::size_t>(c.vertex[sk])] != 0)
      c.inv_mass[sk] = 0.0;
  }
  return c;
}

/// Velocity (x1 − x0)/h of vertex `v` of `m`.
inline Vec3 velocity(const CollisionMesh& m, int v, double h) {
  return (m.x1.row(v) - m.x0.row(v)).transpose() / h;
}

/// Relative velocity Σ w_k v_k of the pair's closest points.
inline Vec3 relative_velocity(const PairCorners& c, const Eigen::Vector4d& w, double h) {
  Vec3 v = Vec3::Zero();
  for (std::size_t k = 0; k < 4; ++k)
    v += w[static_cast<Eigen::Index>(k)] * velocity(*c.mesh[k], c.vertex[k], h);
  return v;
}

/// Inverse effective mass Σ w_k²/m_k of the pair along any direction.
inline double effective_inverse_mass(const PairCorners& c, const Eigen::Vector4d& w) {
  double k_eff = 0.0;
  for (std::size_t k = 0; k < 4; ++k)
    k_eff += w[static_cast<Eigen::Index>(k)] * w[static_cast<Eigen::Index>(k)] * c.inv_mass[k];
  return k_eff;
}

/// Applies impulse J at the pair: corner k moves by h·w_k·J/m_k. The weights of the two sides
/// sum to +1 and −1, so the movable corners' momenta change by J and −J.
inline void apply_impulse(const PairCorners& c, const Eigen::Vector4d& w, const Vec3& impulse,
                          double h) {
  for (std::size_t k = 0; k < 4; ++k) {
    if (c.inv_mass[k] == 0.0) continue;
    c.mesh[k]->x1.row(c.vertex[k]) +=
        (h * w[static_cast<Eigen::Index>(k)] * c.inv_mass[k] * impulse).transpose();
  }
}

}  // namespace dexcloth::collision
