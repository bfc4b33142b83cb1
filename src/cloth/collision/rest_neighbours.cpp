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

std::uint16_t RestNeighbours::mask(int f, int g) const {
  if (m_start.empty()) return 0;
  const int first = m_start[static_cast<std::size_t>(f)];
  int count = m_start[static_cast<std::size_t>(f) + 1] - first;
  if (count == 0) return 0;
  // Binary search without branches on the data (the proximity search's hottest lookup): the
  // last entry not above g.
  const int* base = m_face.data() + first;
  while (count > 1) {
    const int half = count / 2;
    base = base[half] <= g ? base + half : base;
    count -= half;
  }
  return *base == g ? m_mask[static_cast<std::size_t>(base - m_face.data())] : std::uint16_t{0};
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

  const auto corners = [&](int f) {
    return std::array<int, 3>{faces(f, 0), faces(f, 1), faces(f, 2)};
  };
  // Bits of corner k of `f` against face `g` (a corner of g: a pair never tested, counted in).
  const auto vertex_face = [&](int f, int g, bool of_g) {
    const std::array<int, 3> face = corners(g);
    std::uint16_t bits = 0;
    for (int k = 0; k < 3; ++k) {
      const int v = faces(f, k);
      if (v == face[0] || v == face[1] || v == face[2] ||
          rest_vertex_face_distance(rest, v, face) < distance)
        bits |= static_cast<std::uint16_t>(1u << vertex_face_bit(of_g, k));
    }
    return bits;
  };
  struct Entry {
    int face{};
    std::uint16_t mask{};
  };
  std::vector<std::vector<Entry>> lists(static_cast<std::size_t>(faces.rows()));
  for (const FacePair& p : pairs) {
    std::uint16_t ab = vertex_face(p.a, p.b, false) | vertex_face(p.b, p.a, true);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const std::array<int, 2>& a = topology.edges[static_cast<std::size_t>(
            topology.face_edges[static_cast<std::size_t>(p.a)][static_cast<std::size_t>(i)])];
        const std::array<int, 2>& b = topology.edges[static_cast<std::size_t>(
            topology.face_edges[static_cast<std::size_t>(p.b)][static_cast<std::size_t>(j)])];
        if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1] ||
            rest_edge_edge_distance(rest, a, b) < distance)
          ab |= static_cast<std::uint16_t>(1u << edge_edge_bit(i, j));
      }
    if ((ab & kAll) == 0) continue;
    // The same mask seen from b: its corners' bits and the edge pairs transposed.
    std::uint16_t ba = static_cast<std::uint16_t>(((ab & 0x7u) << 3) | ((ab >> 3) & 0x7u));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (ab & (1u << edge_edge_bit(i, j)))
          ba |= static_cast<std::uint16_t>(1u << edge_edge_bit(j, i));
    lists[static_cast<std::size_t>(p.a)].push_back({p.b, ab});
    lists[static_cast<std::size_t>(p.b)].push_back({p.a, ba});
  }
  m_start.assign(1, 0);
  m_face.clear();
  m_mask.clear();
  for (std::vector<Entry>& l : lists) {
    std::sort(l.begin(), l.end(), [](const Entry& x, const Entry& y) { return x.face < y.face; });
    for (const Entry& e : l) {
      m_face.push_back(e.face);
      m_mask.push_back(e.mask);
    }
    m_start.push_back(static_cast<int>(m_face.size()));
  }
}

}  // namespace dexcloth::collision
