#pragma once
/// Rest neighbours: pairs of primitives of one cloth closer than a distance in its rest shape
/// (bending neighbours, never contacts; see find_proximities). Listed once per cloth so that the
/// per-step proximity search can leave them out before testing them.
#include <array>
#include <cstdint>
#include <vector>

#include "cloth/collision/mesh_topology.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Distance in `rest` between vertex `v` and triangle `f` [m].
double rest_vertex_face_distance(const Points& rest, int v, const std::array<int, 3>& f);
/// Distance in `rest` between segments `e` and `g` [m].
double rest_edge_edge_distance(const Points& rest, const std::array<int, 2>& e,
                               const std::array<int, 2>& g);

/// The rest neighbours of one cloth at one distance, by face pair: for faces f and g, a mask of
/// which of their 15 primitive pairs are closer than the distance at rest (a pair sharing a
/// vertex counts as one). Bits: corner k of f against g (k), corner k of g against f (3 + k),
/// edge i of f against edge j of g (6 + 3i + j), edges as MeshTopology::face_edges orders them.
class RestNeighbours {
 public:
  /// Every primitive pair of the faces.
  static constexpr std::uint16_t kAll = 0x7fff;
  static constexpr int vertex_face_bit(bool of_g, int corner) { return (of_g ? 3 : 0) + corner; }
  static constexpr int edge_edge_bit(int i, int j) { return 6 + 3 * i + j; }

  /// Finds the masks of every face pair of `faces` with a primitive pair closer than
  /// `distance` [m] (> 0) in `rest`.
  void build(const Points& rest, const Triangles& faces, const MeshTopology& topology,
             double distance);
  /// The distance the masks were built for (0: not built).
  double distance() const { return m_distance; }
  /// The mask of faces f and g (0: no rest neighbours between them).
  std::uint16_t mask(int f, int g) const;

 private:
  double m_distance{};
  std::vector<int> m_start;  // |F|+1: face f's entries at [m_start[f], m_start[f + 1])
  std::vector<int> m_face;   // the other face of each entry, sorted within each face's range
  std::vector<std::uint16_t> m_mask;  // the mask of each entry
};

}  // namespace dexcloth::collision
