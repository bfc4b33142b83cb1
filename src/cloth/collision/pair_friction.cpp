#include "cloth/collision/pair_friction.hpp"

#include <algorithm>

#include "core/assert.hpp"

namespace dexcloth::collision {

void PairFriction::prepare(const std::vector<CollisionMesh*>& meshes,
                           const std::vector<Proximity>& proximities,
                           const std::vector<double>& normal_impulses,
                           const PairFrictionOptions& options) {
  DEXCLOTH_DEMAND(options.dt > 0.0 && normal_impulses.size() == proximities.size());
  proximities_ = &proximities;
  h_ = options.dt;
  pairs_.clear();
  for (std::size_t i = 0; i < proximities.size(); ++i) {
    const Proximity& p = proximities[i];
    if (!(normal_impulses[i] > 0.0)) continue;
    const CollisionMesh& a = *meshes[static_cast<std::size_t>(p.mesh[0])];
    const CollisionMesh& b = *meshes[static_cast<std::size_t>(p.mesh[1])];
    if (options.cloth_only && (a.obstacle || b.obstacle)) continue;
    const PairCorners c = resolve(meshes, p, options.held);
    const double inv_k = effective_inverse_mass(c, p.w);
    const double bound = pair_friction(a, b) * normal_impulses[i];
    if (inv_k == 0.0 || bound == 0.0) continue;
    pairs_.push_back({i, c, inv_k, bound, Vec3::Zero()});
  }
}

double PairFriction::sweep() {
  double worst = 0.0;
  for (Pair& f : pairs_) {
    const Proximity& p = (*proximities_)[f.index];
    const Vec3 vr = relative_velocity(f.corners, p.w, h_);
    const Vec3 vt = vr - p.normal.dot(vr) * p.normal;
    // Stop the pair, then project the accumulated impulse onto the disc ‖J‖ ≤ μ λ.
    Vec3 j = f.impulse - vt / f.inv_k;
    const double norm = j.norm();
    if (norm > f.bound) j *= f.bound / norm;
    const Vec3 dj = j - f.impulse;
    if (dj.isZero(0.0)) continue;
    f.impulse = j;
    apply_impulse(f.corners, p.w, dj, h_);
    worst = std::max(worst, dj.norm() * f.inv_k);
  }
  return worst;
}

void PairFriction::impulses(std::vector<Vec3>& out) const {
  out.assign(proximities_ == nullptr ? 0 : proximities_->size(), Vec3::Zero());
  for (const Pair& f : pairs_) out[f.index] = f.impulse;
}

void PairFriction::mark_corners(std::vector<std::vector<std::uint8_t>>& mask) const {
  for (const Pair& f : pairs_) {
    const Proximity& p = (*proximities_)[f.index];
    for (int k = 0; k < 4; ++k) {
      const auto m = static_cast<std::size_t>(p.corner_mesh(k));
      if (f.corners.inv_mass[static_cast<std::size_t>(k)] > 0.0 && m < mask.size())
        mask[m][static_cast<std::size_t>(p.corner[static_cast<std::size_t>(k)])] = 1;
    }
  }
}

void apply_pair_friction(const std::vector<CollisionMesh*>& meshes,
                         const std::vector<Proximity>& proximities,
                         const std::vector<double>& normal_impulses,
                         const PairFrictionOptions& options, std::vector<Vec3>& friction) {
  PairFriction pairs;
  pairs.prepare(meshes, proximities, normal_impulses, options);
  for (int sweep = 0; sweep < options.sweeps; ++sweep)
    if (pairs.sweep() <= kPairFrictionConverged) break;
  pairs.impulses(friction);
}

}  // namespace dexcloth::collision
