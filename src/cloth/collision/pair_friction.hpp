#pragma once
/// Coulomb friction between the two sides of proximity pairs, as equal and opposite impulses
/// (Bridson et al. 2002, §7.2, solved to convergence). Pair i, with normal impulse λ_i from the
/// repulsion, takes a tangential impulse J_i with ‖J_i‖ ≤ μ λ_i: the one that stops its relative
/// tangential velocity (static) when that lies inside the disc, else the disc's rim against the
/// velocity left (sliding). Projected Gauss–Seidel over the pairs; every update moves the two
/// sides by opposite momenta, so friction of a cloth with itself or another cloth keeps the
/// cloths' momentum.
#include <cstdint>
#include <vector>

#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/pair_corners.hpp"
#include "cloth/collision/proximity.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Settings of the pair friction.
struct PairFrictionOptions {
  double dt{5e-3};         ///< step size h [s]; velocities are (x1 − x0)/h
  int sweeps{8};           ///< Gauss–Seidel sweeps at most (1: ARCSim's single capped pass)
  bool cloth_only{false};  ///< skip pairs with an obstacle (their friction is solved elsewhere)
  /// Per mesh, vertices taken as infinitely heavy besides the fixed ones (a grip drives them);
  /// null, or an empty or missing entry: none.
  const std::vector<std::vector<std::uint8_t>>* held{nullptr};
};

/// Sweeps stop once no pair's relative velocity changed more than this [m/s].
inline constexpr double kPairFrictionConverged = 1e-12;

/// The pair friction one sweep at a time, for callers that solve other friction in between
/// (block Gauss–Seidel).
class PairFriction {
 public:
  /// Takes the pairs of `proximities` whose normal impulse `normal_impulses[i]` [N·s] is
  /// positive and whose bound μλ (μ of the pair's two meshes) and effective mass are nonzero.
  /// The references must outlive the sweeps.
  void prepare(const std::vector<CollisionMesh*>& meshes, const std::vector<Proximity>& proximities,
               const std::vector<double>& normal_impulses, const PairFrictionOptions& options);
  /// One Gauss–Seidel sweep over the pairs, moving x1 of their movable corners; returns the
  /// largest change of a pair's relative velocity [m/s].
  double sweep();
  /// Each proximity's tangential impulse J_i [N·s], acting on its first primitive (zero where
  /// none).
  void impulses(std::vector<Vec3>& out) const;
  /// Sets mask[m][v] = 1 for every movable corner (mesh m < mask.size()) of a pair taken.
  void mark_corners(std::vector<std::vector<std::uint8_t>>& mask) const;

 private:
  struct Pair {
    std::size_t index;  ///< in proximities
    PairCorners corners;
    double inv_k;  ///< Σ w²/m
    double bound;  ///< μ λ
    Vec3 impulse;  ///< accumulated J
  };
  const std::vector<Proximity>* proximities_{nullptr};
  double h_{};
  std::vector<Pair> pairs_;
};

/// prepare, then up to options.sweeps sweeps until converged; `friction` receives the impulses.
void apply_pair_friction(const std::vector<CollisionMesh*>& meshes,
                         const std::vector<Proximity>& proximities,
                         const std::vector<double>& normal_impulses,
                         const PairFrictionOptions& options, std::vector<Vec3>& friction);

}  // namespace dexcloth::collision
