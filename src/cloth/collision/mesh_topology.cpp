#include "cloth/collision/mesh_topology.hpp"

#include <algorithm>

#include "cloth/collision/collision_mesh.hpp"

namespace dexcloth::collision {

namespace {

/// Pieces of `faces`: faces joined by shared vertices (union–find over the vertices).
void add_pieces(const Triangles& faces, MeshTopology& topo) {
  const auto nv = static_cast<std::size_t>(topo.num_vertices);
  std::vector<int> parent(nv);
  for (std::size_t v = 0; v < nv; ++v) parent[v] = static_cast<int>(v);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  const auto nf = static_cast<std::size_t>(faces.rows());
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 1; k < 3; ++k) {
      const auto i = static_cast<Eigen::Index>(f);
      parent[static_cast<std::size_t>(root(faces(i, k)))] = root(faces(i, 0));
    }
  // Pieces numbered in the order of their first faces; their faces in the mesh's order.
  std::vector<int> piece_of_root(nv, -1);
  topo.face_piece.resize(nf);
  topo.piece_face_start.assign(1, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    int& piece =
        piece_of_root[static_cast<std::size_t>(root(faces(static_cast<Eigen::Index>(f), 0)))];
    if (piece < 0) {
      piece = static_cast<int>(topo.piece_face_start.size()) - 1;
      topo.piece_face_start.push_back(0);
    }
    topo.face_piece[f] = piece;
    ++topo.piece_face_start[static_cast<std::size_t>(piece) + 1];
  }
  for (std::size_t k = 1; k < topo.piece_face_start.size(); ++k)
    topo.piece_face_start[k] += topo.piece_face_start[k - 1];
  topo.piece_faces.resize(nf);
  std::vector<int> next(topo.piece_face_start.begin(), topo.piece_face_start.end() - 1);
  for (std::size_t f = 0; f < nf; ++f)
    topo.piece_faces[static_cast<std::size_t>(
        next[static_cast<std::size_t>(topo.face_piece[f])]++)] = static_cast<int>(f);
}

}  // namespace

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

  // One edge per run of equal (lo, hi); the first (lowest) face owns it. Closed: every run is
  // two faces, one going lo → hi, the other hi → lo.
  topo.closed = nf > 0;
  const auto forward = [&](const HalfEdge& h) { return faces(h.face, h.corner) == h.lo; };
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
    if (j != i + 2 || forward(half[i]) == forward(half[i + 1])) topo.closed = false;
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
  add_pieces(faces, topo);
  return topo;
}

bool faces_adjacent(const Triangles& faces, int f, int g) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (faces(f, i) == faces(g, j)) return true;
  return false;
}

bool coplanar(const Vec3& n0, const Vec3& n1) {
  constexpr double kCosine = 1.0 - 1e-6;
  return n0.dot(n1) >= kCosine * n0.norm() * n1.norm();
}

bool flat_edge(const Points& x, const Triangles& faces, const MeshTopology& topology, int edge) {
  const std::array<int, 2>& f = topology.edge_faces[static_cast<std::size_t>(edge)];
  return f[1] >= 0 && coplanar(face_normal(x, faces, f[0]), face_normal(x, faces, f[1]));
}

std::optional<Vec3> flat_vertex(const Points& x, const Triangles& faces,
                                const MeshTopology& topology, int v) {
  const auto first =
      static_cast<std::size_t>(topology.vertex_face_start[static_cast<std::size_t>(v)]);
  const auto end =
      static_cast<std::size_t>(topology.vertex_face_start[static_cast<std::size_t>(v) + 1]);
  if (first == end) return std::nullopt;
  const Vec3 normal = face_normal(x, faces, topology.vertex_faces[first]);
  for (std::size_t k = first; k < end; ++k) {
    const int f = topology.vertex_faces[k];
    const std::array<int, 3>& edges = topology.face_edges[static_cast<std::size_t>(f)];
    for (int c = 0; c < 3; ++c) {
      if (faces(f, c) != v) continue;  // its edges at v: c (to c + 1) and c + 2 (from c + 2)
      for (int e :
           {edges[static_cast<std::size_t>(c)], edges[static_cast<std::size_t>((c + 2) % 3)]})
        if (topology.edge_faces[static_cast<std::size_t>(e)][1] < 0) return std::nullopt;  // rim
    }
    if (!coplanar(face_normal(x, faces, f), normal)) return std::nullopt;
  }
  return normal;
}

bool on_flat_feature(const Points& x, const Triangles& faces, const MeshTopology& topology,
                     int face, const Vec3& bary) {
  for (int k = 0; k < 3; ++k) {
    const int next = (k + 1) % 3, other = (k + 2) % 3;  // edge k joins corners k and k + 1
    if (bary[other] == 0.0 && bary[k] > 0.0 && bary[next] > 0.0)
      return flat_edge(
          x, faces, topology,
          topology.face_edges[static_cast<std::size_t>(face)][static_cast<std::size_t>(k)]);
    if (bary[k] == 1.0) return flat_vertex(x, faces, topology, faces(face, k)).has_value();
  }
  return false;
}

}  // namespace dexcloth::collision
