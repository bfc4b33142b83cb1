#pragma once
/// Checks of the broad phase's self-contact culling (UnfoldedSubtrees, UnfoldedWindows) against
/// every pair of a mesh, and the sheets they run on.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <tuple>
#include <utility>

#include "cloth/collision/ccd.hpp"
#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/rest_neighbours.hpp"
#include "mesh_builders.hpp"

namespace dexcloth::collision::testing {

inline constexpr double kReach = 5e-3;                        // a 5 mm thickness
inline constexpr double kRestDistance = 0.5 * M_PI * kReach;  // the proximity search's fold length

/// A sheet of n × n quads with 5 mm edges, centred on the origin, with its flat rest shape.
inline CollisionMesh sheet(int n = 20) {
  const double size = 5e-3 * n;
  CollisionMesh m = make_sheet(n, n, size, size, Vec3(-0.5 * size, -0.5 * size, 0.0), 1e-4);
  m.rest = m.x0;
  return m;
}

/// Seeded uniform numbers in [0, 1).
struct Uniform {
  std::uint32_t state;
  double operator()() {
    state = state * 1664525u + 1013904223u;
    return static_cast<double>(state >> 8) / 16777216.0;
  }
};

// Distances at positions x (rest_neighbours.hpp's, which take any positions).
inline double distance_vertex_face(const Points& x, int v, const CollisionMesh& m, int f) {
  return rest_vertex_face_distance(x, v, {m.faces(f, 0), m.faces(f, 1), m.faces(f, 2)});
}

inline double distance_edge_edge(const Points& x, const std::array<int, 2>& e,
                                 const std::array<int, 2>& g) {
  return rest_edge_edge_distance(x, e, g);
}

/// Checks, by testing every pair, that the proximity candidates of `m` hold every vertex–face
/// and edge–edge pair within the reach at x0 that is not a rest neighbour. Returns how many
/// such pairs there are.
inline int expect_every_close_pair_found(const CollisionMesh& m) {
  CollisionCandidates candidates;
  candidates.set_rest_neighbour_distance(kRestDistance);
  candidates.update({&m}, false, 0.5 * kReach);
  const MeshTopology& topo = candidates.topology(0);
  std::set<std::pair<int, int>> vf, ee;
  for (const VertexFacePair& p : candidates.vertex_face()) vf.insert({p.vertex, p.face});
  for (const EdgeEdgePair& p : candidates.edge_edge())
    ee.insert({std::min(p.edge_a, p.edge_b), std::max(p.edge_a, p.edge_b)});
  int close = 0;
  for (int v = 0; v < m.x0.rows(); ++v) {
    for (int f = 0; f < m.faces.rows(); ++f) {
      if (v == m.faces(f, 0) || v == m.faces(f, 1) || v == m.faces(f, 2)) continue;
      if (distance_vertex_face(m.x0, v, m, f) >= kReach) continue;
      if (distance_vertex_face(m.rest, v, m, f) < kRestDistance) continue;
      ++close;
      EXPECT_TRUE(vf.count({v, f})) << "vertex " << v << " face " << f;
    }
  }
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    for (std::size_t g = e + 1; g < topo.edges.size(); ++g) {
      const std::array<int, 2>& a = topo.edges[e];
      const std::array<int, 2>& b = topo.edges[g];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      if (distance_edge_edge(m.x0, a, b) >= kReach) continue;
      if (distance_edge_edge(m.rest, a, b) < kRestDistance) continue;
      ++close;
      EXPECT_TRUE(ee.count({static_cast<int>(e), static_cast<int>(g)}))
          << "edges " << e << " " << g;
    }
  }
  return close;
}

/// Checks that every pair that continuous detection hits among all the swept candidates of `m`
/// (the same sheet without a rest shape: nothing left out) is among those that leave out
/// unfolded subtrees. Returns {hits, whether any subtree was left out}.
inline std::pair<int, bool> expect_every_collision_found(const CollisionMesh& m) {
  constexpr double kTolerance = 1e-6;
  CollisionCandidates culled, all;
  culled.update({&m}, true, kTolerance);
  CollisionMesh no_rest = m;
  no_rest.rest.resize(0, 3);
  all.update({&no_rest}, true, kTolerance);
  std::set<std::tuple<int, int>> vf, ee;
  for (const VertexFacePair& p : culled.vertex_face()) vf.insert({p.vertex, p.face});
  for (const EdgeEdgePair& p : culled.edge_edge()) ee.insert({p.edge_a, p.edge_b});
  const bool left_out = vf.size() + ee.size() < all.vertex_face().size() + all.edge_edge().size();
  const auto corners = [&](const std::array<int, 4>& v) {
    std::pair<Corners, Corners> c;
    for (std::size_t k = 0; k < 4; ++k) {
      c.first[k] = m.x0.row(v[k]).transpose();
      c.second[k] = m.x1.row(v[k]).transpose();
    }
    return c;
  };
  int hits = 0;
  for (const VertexFacePair& p : all.vertex_face()) {
    const auto [c0, c1] =
        corners({p.vertex, m.faces(p.face, 0), m.faces(p.face, 1), m.faces(p.face, 2)});
    if (!vertex_face_ccd(c0, c1, kTolerance)) continue;
    ++hits;
    EXPECT_TRUE(vf.count({p.vertex, p.face})) << "vertex " << p.vertex << " face " << p.face;
  }
  const auto& edges = all.topology(0).edges;
  for (const EdgeEdgePair& p : all.edge_edge()) {
    const auto& a = edges[static_cast<std::size_t>(p.edge_a)];
    const auto& b = edges[static_cast<std::size_t>(p.edge_b)];
    const auto [c0, c1] = corners({a[0], a[1], b[0], b[1]});
    if (!edge_edge_ccd(c0, c1, kTolerance)) continue;
    ++hits;
    EXPECT_TRUE(ee.count({p.edge_a, p.edge_b})) << "edges " << p.edge_a << " " << p.edge_b;
  }
  return {hits, left_out};
}

}  // namespace dexcloth::collision::testing
