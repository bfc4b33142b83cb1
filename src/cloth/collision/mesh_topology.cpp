#include "cloth/collision/mesh_topology.hpp"

#include <algorithm>

namespace dexcloth::collision {

MeshTopology build_topology(const Triangles& faces, int num_vertices) {
  MeshTopology topo;
  const int nf = static_cast<int>(faces.rows());
  topo.num_vertices = num_vertices;
  topo.face_edges.resize(static_cast<std::size_t>(nf));
  topo.owned_vertices.assign(static_cast<std::size_t>(nf), 0);
  topo.owned_edges.assign(static_cast<std::size_t>(nf), 0);

  // Sort (low, high, face, corner) records so equal edges are adjacent.
  struct HalfEdge {
    int lo, hi, face, corner;
  };
  std::vector<HalfEdge> half(static_cast<std::size_t>(3 * nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      half[static_cast<std::size_t>(3 * f + k)] = {std::min(a, b), std::max(a, b), f, k};
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& p, const HalfEdge& q) {
    if (p.lo != q.lo) return p.lo < q.lo;
    if (p.hi != q.hi) return p.hi < q.hi;
    return p.face < q.face;
  });

  // One edge per run of equal (lo, hi); the first (lowest) face owns it.
  for (std::size_t i = 0; i < half.size();) {
    const int e = static_cast<int>(topo.edges.size());
    topo.edges.push_back({half[i].lo, half[i].hi});
    topo.edge_faces.push_back({half[i].face, -1});
    topo.owned_edges[static_cast<std::size_t>(half[i].face)] |=
        static_cast<std::uint8_t>(1u << half[i].corner);
    std::size_t j = i;
    for (; j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi; ++j) {
      topo.face_edges[static_cast<std::size_t>(half[j].face)]
                     [static_cast<std::size_t>(half[j].corner)] = e;
      if (j == i + 1) topo.edge_faces.back()[1] = half[j].face;
    }
    i = j;
  }

  // The faces around each vertex.
  topo.vertex_face_start.assign(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) ++topo.vertex_face_start[static_cast<std::size_t>(faces(f, k)) + 1];
  for (std::size_t v = 0; v < static_cast<std::size_t>(num_vertices); ++v)
    topo.vertex_face_start[v + 1] += topo.vertex_face_start[v];
  topo.vertex_faces.resize(static_cast<std::size_t>(3 * nf));
  std::vector<int> next(topo.vertex_face_start.begin(), topo.vertex_face_start.end() - 1);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      topo.vertex_faces[static_cast<std::size_t>(next[static_cast<std::size_t>(faces(f, k))]++)] =
          f;

  // Each vertex belongs to the first face that lists it.
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(num_vertices), 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      auto& s = seen[static_cast<std::size_t>(faces(f, k))];
      if (s == 0) {
        s = 1;
        topo.owned_vertices[static_cast<std::size_t>(f)] |= static_cast<std::uint8_t>(1u << k);
      }
    }
  }
  return topo;
}

bool faces_adjacent(const Triangles& faces, int f, int g) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (faces(f, i) == faces(g, j)) return true;
  return false;
}

}  // namespace dexcloth::collision
