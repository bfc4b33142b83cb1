#pragma once
/// Windows of a cloth's rest plane in which the cloth is provably free of self-contact at a
/// reach, however it curves: the pairs of BVH nodes whose rest boxes fit together in such a
/// window can be left out of the broad phase. They complement UnfoldedSubtrees, whose affine
/// fits fail on wrinkled cloth: a wrinkle of radius R bends a patch of side L by about L²/8R away
/// from any plane, but turns its faces only by about L/R.
///
/// The bound. Let the window's cloth (its rest region Q convex and covered once by the mesh) map
/// piecewise linearly to positions x, with per-face Jacobians J_f (3×2), and let J₀ be 3×2 with
/// orthonormal columns. For rest points p, q in Q, x(q) − x(p) = ∫ J(u(t))·(q − p) dt along the
/// segment, which stays in Q; projected on J₀·e (e the unit direction of q − p) every part of
/// the integral is at least λ_min(sym(J_fᵀJ₀))·|q − p|. So |x(q) − x(p)| ≥ κ·|q − p| with
/// κ = min over Q's faces of λ_min(sym(J_fᵀJ₀)), and two primitives of the window whose rest
/// distance is d are at least κ·d apart. J₀ is the rotation of the faces' mean Jacobian (its
/// polar factor). A face turned by α against J₀, unstretched, has λ_min ≥ cos α.
///
/// Windows are squares of side 2s at every multiple of the stride s, so any rest box of side at
/// most s lies within one (BvhTraversal asks `skips`); a second level of windows, of stride 2s,
/// holds the pairs of nodes too wide for the first (pairs along the border between two big
/// subtrees, which the swept search, whose κ need only be positive, mostly leaves out there).
/// Q is the window (grown by a hair for rounding) clipped to the mesh's rest bounding box; a
/// window counts only when the faces overlapping Q cover it exactly once, with one orientation
/// and no mesh boundary inside it (no hole, slit, fold or second layer in the rest plane), else
/// it is never flagged.
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "cloth/collision/mesh_topology.hpp"
#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::collision {

class UnfoldedWindows {
 public:
  /// Levels of windows, of strides s, 2s, ...: a level's window holds four times the faces of
  /// the one below, and the κ test reads all of them, so that in pinch_move's swept search more
  /// levels than two cost more than they leave out.
  static constexpr int kLevels = 2;

  /// Windows of stride `stride` [m] (wider if the cloth spans over 8,000 of them) over the
  /// rest-plane coordinates `uv` (|V|×2, a planar rest shape's) of `faces`, for a BVH whose nodes
  /// have the rest boxes `boxes` (4 per node: {u0 lo, u1 lo, u0 hi, u1 hi}).
  void build(std::span<const double> uv, const Triangles& faces, const MeshTopology& topology,
             std::span<const double> boxes, double stride);
  /// True when built with `stride` for a tree of `nodes` nodes.
  bool built_for(int nodes, double stride) const {
    return m_nodes == nodes && m_stride == stride && nodes > 0;
  }
  /// Prepares the windows' flags at positions `x` (|V|×3): a window is flagged when no two
  /// points of its cloth within it whose rest-plane distance is at least `distance` [m] come
  /// within `reach` [m] of each other. Each window's flag is worked out when first asked for (most
  /// windows of a cloth whose subtrees are unfolded never are).
  void update(const Points& x, double distance, double reach, WorkerPool* pool = nullptr);
  /// The same over the linear motion x0 → x1: at every time of it.
  void update_swept(const Points& x0, const Points& x1, double distance, double reach,
                    WorkerPool* pool = nullptr);

  /// Whether the pairs between the subtrees of nodes i and j (i = j: within one) can be left
  /// out: their rest boxes fit together in a flagged window. Safe on several threads at once.
  bool skips(int i, int j) const {
    // Window (c0, c1) of a level spans its cells c..c + 1 on each axis: the boxes' lowest cell
    // and their highest one at most one above it (and, where both are one cell, the window one
    // lower). A level's cells are the first level's halved as often as its stride is doubled.
    const Cells& a = m_cells[static_cast<std::size_t>(i)];
    const Cells& b = m_cells[static_cast<std::size_t>(j)];
    int c0 = a.lo[0] < b.lo[0] ? a.lo[0] : b.lo[0];
    int c1 = a.lo[1] < b.lo[1] ? a.lo[1] : b.lo[1];
    int h0 = a.hi[0] > b.hi[0] ? a.hi[0] : b.hi[0];
    int h1 = a.hi[1] > b.hi[1] ? a.hi[1] : b.hi[1];
    std::size_t level = 0;
    while (h0 > c0 + 1 || h1 > c1 + 1) {
      if (++level == m_levels.size()) return false;
      c0 >>= 1;
      c1 >>= 1;
      h0 >>= 1;
      h1 >>= 1;
    }
    const Level& l = m_levels[level];
    if (flagged(l.window(c0, c1))) return true;
    const bool lower0 = h0 == c0 && c0 > 0, lower1 = h1 == c1 && c1 > 0;
    return (lower0 && flagged(l.window(c0 - 1, c1))) || (lower1 && flagged(l.window(c0, c1 - 1))) ||
           (lower0 && lower1 && flagged(l.window(c0 - 1, c1 - 1)));
  }
  /// Nodes of the tree it was built for.
  int num_nodes() const { return m_nodes; }
  /// Windows of every level, each level's row-major over its cells, the first level first.
  std::size_t num_windows() const { return m_covered.size(); }
  /// Levels of windows (the first of stride s, each next one of twice the stride).
  int num_levels() const { return static_cast<int>(m_levels.size()); }
  /// The windows of `level`: [first, first + columns · rows).
  std::size_t first_window(int level) const {
    return m_levels[static_cast<std::size_t>(level)].first;
  }
  std::size_t level_windows(int level) const {
    const Level& l = m_levels[static_cast<std::size_t>(level)];
    return static_cast<std::size_t>(l.columns) * static_cast<std::size_t>(l.rows);
  }
  /// Whether window w's cloth covers it once (only those can be flagged).
  bool covered(std::size_t w) const { return m_covered[w] != 0; }
  /// Whether window w is flagged at the last update.
  bool flagged(std::size_t w) const {
    const std::uint8_t state = m_state[w].load(std::memory_order_relaxed);
    return (state == kUnknown ? resolve(w) : state) == kFlagged;
  }

 private:
  static constexpr std::uint8_t kUnknown = 0, kNotFlagged = 1, kFlagged = 2;
  // Whether κ of window w at the face Jacobians m_jacobian[s] (s < m_sets) is at least
  // m_needed (false at once where a face's falls below it).
  bool unfolded(std::size_t w) const;
  // Works out window w's flag and keeps it.
  std::uint8_t resolve(std::size_t w) const;
  void jacobians(int s, const Points& x, WorkerPool* pool);
  void start(int sets, double distance, double reach);

  struct Cells {  // of a node's rest box: ⌊(lo − origin)/s⌋ and ⌊(hi − origin)/s⌋ per axis
    std::int16_t lo[2];
    std::int16_t hi[2];
  };
  struct Level {
    std::size_t first{};  // its first window
    int columns{}, rows{};
    // The index of its window (c0, c1), row-major after `first`.
    std::size_t window(int c0, int c1) const {
      return first + static_cast<std::size_t>(c1) * static_cast<std::size_t>(columns) +
             static_cast<std::size_t>(c0);
    }
  };

  int m_nodes{};
  double m_stride{};
  double m_origin[2]{};
  std::vector<Level> m_levels;
  std::vector<Cells> m_cells;           // per node, of the first level
  std::vector<int> m_face_start;        // per window: its faces m_faces[start .. next start)
  std::vector<int> m_faces;             //
  std::vector<std::uint8_t> m_covered;  // per window
  // Per window, of the last update: kUnknown until asked for (threads asking at once work it
  // out alike).
  mutable std::vector<std::atomic<std::uint8_t>> m_state;
  bool m_any_covered{};  // whether any window is covered once (else no Jacobians are needed)
  int m_sets{};          // of the last update: 1, or 2 (swept)
  double m_needed{};     // of the last update: the κ a flag needs
  std::vector<double> m_rest_inverse;  // per face: inverse of its rest edge matrix, 4 entries
  std::vector<int> m_corners;          // per face: its three vertices
  std::vector<double> m_jacobian[2];   // per face: J_f at x0 (and x1), 6 entries column-major
};

}  // namespace dexcloth::collision
