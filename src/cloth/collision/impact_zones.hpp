#pragma once
/// Final collision response: every impact that continuous collision detection finds on x0 → x1 is
/// resolved by inelastic projection of impact zones (Harmon et al. 2008, as in ARCSim), with
/// rigid-zone and stay-at-start fallbacks so no collision is ever left silently.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cloth/collision/ccd.hpp"
#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/obstacle_pieces.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Settings of impact-zone resolution.
struct ImpactZoneOptions {
  double offset{1.5e-4};       ///< separation along each impact's normal that projection
                               ///< enforces at x1 [m] (a few % of the 5 mm thickness); a pair
                               ///< that starts closer keeps its start separation instead
                               ///< (at least 10·ccd_tolerance), so the start state is feasible
  double ccd_tolerance{1e-6};  ///< distance at which CCD reports contact [m]
  int max_iterations{40};      ///< detect–respond rounds; past half of them zones move rigidly,
                               ///< past three quarters they stay at x0
  int max_sweeps{5000};        ///< Gauss–Seidel sweeps of one zone's projection
  double violation_tolerance{0.05};  ///< a projection has converged when no constraint is
                                     ///< violated by more than this fraction of `offset` (and
                                     ///< every pair stays beyond `ccd_tolerance`)
};

/// What `ImpactZoneSolver::resolve` did.
struct ImpactZoneReport {
  int iterations{};   ///< detect–respond rounds that found impacts
  int impacts{};      ///< impacts found over all rounds (constraints)
  int zones{};        ///< distinct impact zones at the end
  int rigid_zones{};  ///< zones that fell back to rigid motion or to staying at x0
  int released{};     ///< vertices held by friction let go because an obstacle ran into them
  bool converged{};   ///< the last detection found no impact, and no fixed–fixed collision
                      ///< (frozen vertex against obstacle) exists
  std::vector<std::string> warnings;  ///< fallbacks taken and anything left unresolved
};

/// Impact-zone collision response with its scratch kept between steps.
class ImpactZoneSolver {
 public:
  /// Moves x1 of the movable vertices of `meshes` (never obstacles or frozen vertices) until no
  /// vertex–face or edge–edge pair collides on the linear motion x0 → x1. Each round: CCD on all
  /// candidate pairs; new impacts join zones (union of the movable vertices they involve); each
  /// zone with new impacts is projected: min Σ m_i‖x_i − x̂_i‖² subject to n·Σ w_k x_k ≥ offset for
  /// all its impacts (normal n and weights w fixed at detection, offset capped by the start
  /// separation as `ImpactZoneOptions::offset` says), by Gauss–Seidel on the dual
  /// (λ ≥ 0). A zone whose projection does not converge moves rigidly with its mass-weighted
  /// linear and angular velocity (Bridson et al. 2002); a rigid zone hit again stays at x0. Never
  /// aborts; every fallback and any impact left after `max_iterations` is reported in warnings.
  ImpactZoneReport resolve(const std::vector<CollisionMesh*>& meshes,
                           const ImpactZoneOptions& options);
  /// Runs the broad phase on `pool`'s threads (null: the calling thread); see
  /// CollisionCandidates::set_pool.
  void set_pool(WorkerPool* pool) { m_candidates.set_pool(pool); }
  /// CollisionCandidates::share_fits: the swept search keeps its cloths' fits with `other`'s.
  void share_fits(CollisionCandidates& other) { m_candidates.share_fits(other); }

 private:
  struct Corner {
    int mesh{};
    int vertex{};
    int gid{};
    double inv_mass{};
  };
  struct Impact {
    std::array<Corner, 4> corner{};
    Eigen::Vector4d w{Eigen::Vector4d::Zero()};
    Vec3 normal{Vec3::Zero()};
    double t{};
    double target{};  // separation n·Σ w x the projection enforces [m]
    double slack{};   // violation of the target a converged projection may leave [m]
    double lambda{};
  };

  /// Tests the candidate pairs for new impacts: all of them, or with `moved_only` those with a
  /// face touching a vertex the last round moved (m_moved; the others move as they did then).
  int find_impacts(const std::vector<CollisionMesh*>& meshes, const ImpactZoneOptions& options,
                   bool moved_only);
  /// Turns `impact`'s normal to point out of the obstacle when its cloth primitive starts inside
  /// the obstacle, less than `offset` from it (see the definition); true when it did.
  bool orient_outward(const std::vector<CollisionMesh*>& meshes, bool edge_edge,
                      const std::array<int, 4>& mesh, const std::array<int, 2>& primitive,
                      const Corners& x0, double offset, Impact& impact);
  int find_root(int gid);
  /// Mesh and vertex index of global vertex id `gid`.
  std::pair<CollisionMesh*, int> locate(const std::vector<CollisionMesh*>& meshes, int gid) const;
  /// Projects the zone of `impacts` (members `members`) on its constraints; on failure leaves
  /// the members' x1 as it found them and returns false.
  bool project(const std::vector<CollisionMesh*>& meshes, const std::vector<int>& impacts,
               const std::vector<int>& members, const ImpactZoneOptions& options);
  /// The Gauss–Seidel sweeps of `project`; true when converged.
  bool gauss_seidel(const std::vector<CollisionMesh*>& meshes, const std::vector<int>& impacts,
                    const ImpactZoneOptions& options);
  void move_rigidly(const std::vector<CollisionMesh*>& meshes, const std::vector<int>& members);
  void stay_at_start(const std::vector<CollisionMesh*>& meshes, const std::vector<int>& members);
  /// Lets go the friction-held corners of `impacts` and adds them to the zone of `members`.
  void release_held_corners(const std::vector<CollisionMesh*>& meshes,
                            const std::vector<int>& impacts, std::vector<int>& members);

  CollisionCandidates m_candidates;
  std::vector<const CollisionMesh*> m_view;
  std::vector<Impact> m_impacts;
  std::vector<ObstaclePieces> m_pieces;        // per mesh: closed obstacles' pieces at x0
  std::vector<std::uint8_t> m_pieces_ready;    // per mesh: m_pieces updated this resolve
  std::vector<int> m_offset;                   // first global vertex id of each mesh
  std::vector<int> m_parent;                   // union–find over global vertex ids
  std::vector<std::uint8_t> m_level;           // per global id: 0 project, 1 rigid, 2 stay at x0
  std::vector<std::pair<int, int>> m_by_root;  // (zone root, impact index)
  std::vector<int> m_zone_impacts;
  std::vector<int> m_zone_members;
  std::vector<Vec3> m_zone_x1;  // the members' x1 before a projection
  // Per mesh, per vertex: moved by this round's responses (the zones' members).
  std::vector<std::vector<std::uint8_t>> m_moved;
  bool m_count_fixed{};         // test pairs whose corners are all fixed (first round only)
  int m_fixed_impacts{};        // such pairs found colliding
  int m_released{};             // friction-held vertices let go this resolve
};

}  // namespace dexcloth::collision
