#pragma once
/// Edges of a triangle mesh and which face "owns" each vertex and edge, so that primitive pairs
/// (vertex–face, edge–edge) can be generated exactly once from overlapping face pairs.
#include <array>
#include <cstdint>
#include <optional>
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
  std::vector<int> face_piece;                 ///< |F| its piece: faces joined by shared
                                               ///< vertices (a body's shapes are appended as
                                               ///< separate pieces), numbered by first face
  std::vector<int> piece_face_start;           ///< pieces+1 offsets into piece_faces
  std::vector<int> piece_faces;                ///< the faces of each piece, by piece
  bool closed{};  ///< every edge has exactly two faces, running along it in opposite directions
                  ///< (a closed, consistently oriented surface, which has an inside)
  int num_vertices{};  ///< |V| the topology was built for

  /// Number of pieces.
  int pieces() const {
    return piece_face_start.empty() ? 0 : static_cast<int>(piece_face_start.size()) - 1;
  }
};

/// Builds edges, ownership (a vertex or edge belongs to the first face that contains it), pieces
/// and closedness of `faces` (|F|×3) over `num_vertices` vertices.
MeshTopology build_topology(const Triangles& faces, int num_vertices);

/// True when faces `f` and `g` of `faces` share at least one vertex.
bool faces_adjacent(const Triangles& faces, int f, int g);

/// True when face normals (of any length) `n0` and `n1` agree to about 0.1°.
bool coplanar(const Vec3& n0, const Vec3& n1);

/// True when `edge` of (`x`, `faces`) joins two coplanar faces: no feature of an obstacle's
/// surface (the diagonal of a box's or a table's flat side).
bool flat_edge(const Points& x, const Triangles& faces, const MeshTopology& topology, int edge);

/// The normal of the flat region vertex `v` lies inside (all its faces coplanar, none of its
/// edges on the mesh's boundary), if it does.
std::optional<Vec3> flat_vertex(const Points& x, const Triangles& faces,
                                const MeshTopology& topology, int v);

/// Whether the point of `face` with barycentric weights `bary` lies on a flat edge (one weight
/// exactly 0) or a flat vertex (one weight 1) of the mesh.
bool on_flat_feature(const Points& x, const Triangles& faces, const MeshTopology& topology,
                     int face, const Vec3& bary);

}  // namespace dexcloth::collision
