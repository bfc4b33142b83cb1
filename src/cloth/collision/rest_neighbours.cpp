#include "cloth/collision/rest_neighbours.hpp"

#include <algorithm>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/closest_points.hpp"
#include "core/assert.hpp"

namespace dexcloth::collision {

double rest_vertex_face_distance(const Points& rest, int v, const std::array<int, 3>& f) {
  const Vec3 p = rest.row(v).transpose(), a = rest.row(f[0]).transpose(),
             b = rest.row(f[1]).transpose(), c = rest.row(f[2]).transpose();
  const Vec3 bary = closest_point_triangle(p, a, b, c);
  return (p - (bary[0] * a + bary[1] * b + bary[2] * c)).norm();
}

double rest_edge_edge_distance(const Points& rest, const std::array<int, 2>& e,
                               const std::array<int, 2>& g) {
  const Vec3 p0 = rest.row(e[0]).transpose(), p1 = rest.row(e[1]).transpose(),
             q0 = rest.row(g[0]).transpose(), q1 = rest.row(g[1]).transpose();
  const Vec2 su = closest_points_segments(p0, p1, q0, q1);
  return ((p0 + su[0] * (p1 - p0)) - (q0 + su[1] * (q1 - q0))).norm();
}

bool RestNeighbours::contains(const Lists& l, int i, int j) {
  if (l.start.empty()) return false;
  const auto first = l.list.begin() + l.start[static_cast<std::size_t>(i)];
  const auto last = l.list.begin() + l.start[static_cast<std::size_t>(i) + 1];
  return std::binary_search(first, last, j);
}

void RestNeighbours::fill(std::vector<std::vector<int>>& per_index, Lists& out) {
  out.start.assign(1, 0);
  out.list.clear();
  for (std::vector<int>& l : per_index) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    out.list.insert(out.list.end(), l.begin(), l.end());
    out.start.push_back(static_cast<int>(out.list.size()));
  }
}

void RestNeighbours::build(const Points& rest, const Triangles& faces, const MeshTopology& topology,
                           double distance) {
  DEXCLOTH_DEMAND(distance > 0.0 && rest.rows() == topology.num_vertices);
  m_distance = distance;
  // Candidates: faces whose rest boxes are within `distance` of each other (any primitive pair
  // closer than that lies on such a pair of faces).
  Bvh tree;
  tree.build(faces, rest, rest, 0.5 * distance);
  std::vector<FacePair> pairs;
  self_overlapping_faces(tree, faces, false, pairs);

  std::vector<std::vector<int>> vf(static_cast<std::size_t>(rest.rows()));
  std::vector<std::vector<int>> ee(topology.edges.size());
  std::vector<std::vector<int>> ff(static_cast<std::size_t>(faces.rows()));
  const auto corners = [&](int f) {
    return std::array<int, 3>{faces(f, 0), faces(f, 1), faces(f, 2)};
  };
  // Vertex–face pairs of corners of `f` against `g`; false if one is not a neighbour.
  const auto vertex_face = [&](int f, int g) {
    const std::array<int, 3> face = corners(g);
    bool all = true;
    for (int v : corners(f)) {
      if (v == face[0] || v == face[1] || v == face[2]) continue;
      if (rest_vertex_face_distance(rest, v, face) < distance)
        vf[static_cast<std::size_t>(v)].push_back(g);
      else
        all = false;
    }
    return all;
  };
  for (const FacePair& p : pairs) {
    bool all = vertex_face(p.a, p.b);
    all = vertex_face(p.b, p.a) && all;
    for (int ea : topology.face_edges[static_cast<std::size_t>(p.a)])
      for (int eb : topology.face_edges[static_cast<std::size_t>(p.b)]) {
        const std::array<int, 2>& a = topology.edges[static_cast<std::size_t>(ea)];
        const std::array<int, 2>& b = topology.edges[static_cast<std::size_t>(eb)];
        if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
        if (rest_edge_edge_distance(rest, a, b) < distance) {
          ee[static_cast<std::size_t>(ea)].push_back(eb);
          ee[static_cast<std::size_t>(eb)].push_back(ea);
        } else {
          all = false;
        }
      }
    if (all) {
      ff[static_cast<std::size_t>(p.a)].push_back(p.b);
      ff[static_cast<std::size_t>(p.b)].push_back(p.a);
    }
  }
  fill(vf, m_vf);
  fill(ee, m_ee);
  fill(ff, m_ff);
}

}  // namespace dexcloth::collision
