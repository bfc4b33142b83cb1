#pragma once
/// Subtrees of a cloth's BVH that are provably free of self-contact at a reach: their cloth is
/// close to an affine image of its (planar) rest shape, so two of their primitives far enough
/// apart at rest are farther apart than the reach, and the broad phase can leave out the pairs
/// within them without testing any.
#include <cstdint>
#include <vector>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/mesh_topology.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// For every node N of a cloth's BVH: the least-squares affine map G_N(u) = m + F (u − ū) of its
/// vertices from rest-plane coordinates u to positions x, and a bound ρ_N on how far any
/// of its vertices lies from G_N. For points p, q of N's faces, |x_p − x_q| ≥ σ_min(F)·|u_p −
/// u_q| − 2ρ_N, so when σ_min(F)·d − 2ρ_N ≥ reach, no two primitives of N whose rest distance
/// is d or more come within the reach. ρ_N is exact for subtrees of up to kMeasuredFaces faces
/// (measured at their vertices) and bounded above them: max over the children c of ρ_c +
/// max |G_c − G_N| over c's rest box (an affine difference, largest at a corner of the box).
///
/// Over a step's linear motion x0 → x1 the maps interpolate too: at time t every vertex is within
/// (1 − t)·ρ0 + t·ρ1 of (1 − t)·G0 + t·G1, whose σ_min is at least min(σ0, σ1) − ‖F1 − F0‖/2.
///
/// The fits of the last two positions an update saw are kept: positions bitwise equal to one of
/// them (a swept search's x0, which is the last one's x1 or, in the impact zones' next round, its
/// own x0) are not fitted again.
class UnfoldedSubtrees {
 public:
  /// Rest-plane coordinates of `rest` (|V|×3) and the rest boxes of `bvh`'s nodes over `faces`.
  /// A rest shape that is not planar gets a flatness allowance as large as its curvature, which
  /// leaves no subtree flagged.
  void build(const Points& rest, const Triangles& faces, const Bvh& bvh);
  /// Nodes of the tree it was built for (0: not built).
  int num_nodes() const { return m_nodes; }
  /// True when built for a tree of `bvh`'s node count.
  bool built_for(const Bvh& bvh) const { return m_nodes == bvh.num_nodes() && m_nodes > 0; }
  /// Flags the base subtrees of `bvh` (see kBaseFaces) and the nodes above them whose subtree
  /// holds no two primitives within `reach` [m] of each other at positions `x` unless their rest
  /// distance is below `rest_distance` [m] (rest neighbours). Runs on `pool`'s threads where the
  /// tree is big enough (null: the calling thread); the flags do not depend on it.
  void update(const Bvh& bvh, const Points& x, double rest_distance, double reach,
              WorkerPool* pool = nullptr);
  /// The same for the linear motion x0 → x1: flags the subtrees in which no two primitives that
  /// share no vertex come within `reach` of each other at any time of the motion.
  void update_swept(const Bvh& bvh, const Triangles& faces, const MeshTopology& topology,
                    const Points& x0, const Points& x1, double reach, WorkerPool* pool = nullptr);
  /// One flag per node (nonzero: no contact within its subtree), for run_query's skip.
  const std::vector<std::uint8_t>& flags() const { return m_flags; }
  /// The rest-plane coordinates of the vertices (|V|×2) [m] and the nodes' rest boxes (4 per
  /// node: {u0 lo, u1 lo, u0 hi, u1 hi}) [m], as built.
  const std::vector<double>& rest_plane() const { return m_uv; }
  const std::vector<double>& rest_boxes() const { return m_box; }
  /// The largest distance of a rest vertex from the rest plane [m].
  double flatness() const { return m_flatness; }
  /// The least distance in the rest plane between two primitives of `faces` that share no
  /// vertex [m] (computed on the first call after a build).
  double separation(const Triangles& faces, const MeshTopology& topology);

  /// Where the fits of the last two position sets are kept: an UnfoldedSubtrees' own, or one
  /// it shares with the UnfoldedSubtrees of another search over the same cloth (keep_fits_in).
  struct KeptFits;
  /// Keeps the fits in `kept` from now on, where another UnfoldedSubtrees of the same cloth
  /// built over an equal tree keeps them too (the two never updated at once), so that positions
  /// one of them fitted are not fitted again by the other. Ignored where `kept` holds the fits
  /// of another tree or rest shape; a build goes back to the object's own.
  void keep_fits_in(KeptFits* kept);
  /// Position sets fitted so far (not found among the kept ones).
  long fitted_sets() const { return m_fitted_sets; }

  /// Base subtrees, of up to this many faces under a bigger parent, get their fits from their
  /// vertices directly; the nodes within them are never flagged.
  static constexpr int kBaseFaces = 8;
  /// Subtrees of up to this many faces measure ρ at their vertices (exact); above, it is bounded
  /// through the children's fits.
  static constexpr int kMeasuredFaces = 32;

 private:
  struct Fit {
    double x[3]{};     // m, mean position of the vertices [m]
    double f[3][2]{};  // F, the map's linear part
    double rho{};      // bound on any vertex's distance from the map [m] (∞: no fit)
  };
  struct Moments {  // of positions x over a node's vertices (each base subtree's once)
    double sx[3]{}, sxu[3][2]{};
  };
  struct RestMoments {  // of the same vertices' rest-plane coordinates u, and what the fit needs
    double w{}, su[2]{}, suu[3]{};
    double u[2]{};        // ū
    double inverse[3]{};  // of their covariance, {00, 01, 11}; all 0: degenerate, no fit
  };
  // The fits of the nodes at and above the base subtrees (by m_fitted) at positions x, kept for
  // the next update: a swept search's x0 is the last one's x1 (the step's end is the next one's
  // start) or its own x0 (the impact zones' rounds), and a fit depends on its positions alone.
  struct Fits {
    Points x;  // the positions they are for
    std::vector<Fit> fit;
    bool valid{};
  };

 public:
  struct KeptFits {
    std::uint64_t tree{};  // signature of the tree and rest plane they are for (0: none yet)
    Fits sets[2];
    int recent{};  // the set used last
  };

 private:
  KeptFits& kept() { return m_shared != nullptr ? *m_shared : m_own; }
  // Sets `kept` up empty for this object's tree.
  void clear(KeptFits& kept) const;
  static void finish(RestMoments& rest);
  static Fit fit(const Moments& mo, const RestMoments& rest);
  // Largest |G_c(u) − G_n(u)| over the corners of rest box `box` {u0 lo, u1 lo, u0 hi, u1 hi}.
  static double deviation(const Fit& c, const double* uc, const Fit& n, const double* un,
                          const double* box);
  // Node i's moments at x, its fit and those of its descendants down to the base subtrees
  // stored in `fits` (ρ measured at the vertices up to kMeasuredFaces, bounded through the
  // children's fits above).
  Moments fit_subtree(const Bvh& bvh, int i, const Points& x, std::vector<Fit>& fits) const;
  // The same for a base subtree, from its vertices.
  Moments fit_base(int i, const Points& x, std::vector<Fit>& fits) const;
  // Node i's moments and fit from its children's.
  Moments fit_inner(const Bvh& bvh, int i, const Moments& left, const Moments& right,
                    const Points& x, std::vector<Fit>& fits) const;
  // The largest distance of node i's vertices at x from fit `ft` (with rest moments `rest`).
  double residual(int i, const Points& x, const Fit& ft, const RestMoments& rest) const;
  // Flags every fitted node of the subtrees [begin, end) from the fits of x0 (and x1).
  void flag(int begin, int end, const Fits& at0, const Fits* at1);
  // The fits at `x`: kept ones if made for the same positions (bitwise), else fitted anew on
  // `pool` into the kept set not in `busy` (null: either).
  const Fits& fits_at(const Bvh& bvh, const Points& x, const Fits* busy, WorkerPool* pool);
  void run(const Bvh& bvh, WorkerPool* pool);
  // The least distance in the rest plane between two primitives that share no vertex [m].
  double least_separation(const Triangles& faces, const MeshTopology& topology) const;

  int m_nodes{};
  double m_flatness{};              // largest distance of a rest vertex from the rest plane [m]
  double m_separation{-1.0};        // least_separation, once computed (< 0: not yet)
  std::vector<double> m_uv;         // |V|×2 rest-plane coordinates [m]
  std::vector<double> m_box;        // per node, rest box {u0 lo, u1 lo, u0 hi, u1 hi} [m]
  std::vector<RestMoments> m_rest;  // per node
  // The vertices of node i: m_vertices[m_vertex_begin[i] .. m_vertex_end[i]), each base
  // subtree's once (a subtree's base subtrees are listed together).
  std::vector<int> m_vertex_begin, m_vertex_end, m_vertices;
  std::vector<int> m_fitted;  // per node: its index in Fits::fit, or −1 (within a base subtree)
  int m_fitted_count{};       // nodes with an index
  std::uint64_t m_signature{};  // of the tree and the rest plane, for sharing kept fits
  KeptFits m_own;               // the fits kept, unless shared
  KeptFits* m_shared{};         // the fits kept, shared (null: m_own)
  long m_fitted_sets{};
  // Of the update running:
  const Points* m_x[2]{};  // positions (x1 null: not swept)
  double m_distance{};     // rest distance less the flatness allowance [m]
  double m_needed{};       // the reach with a margin for rounding [m]
  std::vector<std::uint8_t> m_flags;
};

}  // namespace dexcloth::collision
