#pragma once
/// Edges of a triangle mesh and which face "owns" each vertex and edge, so that primitive pairs
/// (vertex–face, edge–edge) can be generated exactly once from overlapping face pairs.
#include <array>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace dexcloth::collision {

/// Topology derived from a face list; rebuilt only when the faces change.
struct MeshTopology {
  std::vector<std::array<int, 2>> edges;       ///< |E| unique edges, (low, high) vertex index
  std::vector<std::array<int, 3>> face_edges;  ///< |F| edge k of face f joins corners k and k+1
  std::vector<std::array<int, 2>> edge_faces;  ///< |E| its first two faces (−1: none)
  std::vector<int> vertex_face_start;          ///< |V|+1 offsets into vertex_faces
  std::vector<int> vertex_faces;               ///< the faces around each vertex, by vertex
  std::vector<std::uint8_t> owned_vertices;    ///< |F| bit k: face f owns its corner k
  std::vector<std::uint8_t> owned_edges;       ///< |F| bit k: face f owns its edge k
  int num_vertices{};                          ///< |V| the topology was built for
};

/// Builds edges and ownership (a vertex or edge belongs to the first face that contains it) of
/// `faces` (|F|×3) over `num_vertices` vertices.
MeshTopology build_topology(const Triangles& faces, int num_vertices);

/// True when faces `f` and `g` of `faces` share at least one vertex.
bool faces_adjacent(const Triangles& faces, int f, int g);

}  // namespace dexcloth::collision
