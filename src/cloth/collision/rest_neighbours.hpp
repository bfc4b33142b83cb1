#pragma once
/// Rest neighbours: pairs of primitives of one cloth closer than a distance in its rest shape
/// (bending neighbours, never contacts; see find_proximities). Listed once per cloth so that the
/// per-step proximity search can leave them out before testing them.
#include <array>
#include <vector>

#include "cloth/collision/mesh_topology.hpp"
#include "core/types.hpp"

namespace dexcloth::collision {

/// Distance in `rest` between vertex `v` and triangle `f` [m].
double rest_vertex_face_distance(const Points& rest, int v, const std::array<int, 3>& f);
/// Distance in `rest` between segments `e` and `g` [m].
double rest_edge_edge_distance(const Points& rest, const std::array<int, 2>& e,
                               const std::array<int, 2>& g);

/// The rest neighbours of one cloth at one distance: vertex–face pairs, edge–edge pairs (edges
/// as indexed by its MeshTopology) and face pairs all of whose primitive pairs are neighbours.
class RestNeighbours {
 public:
  /// Lists every vertex–face pair (vertex not a corner of the face) and edge–edge pair (no
  /// shared vertex) of `faces` whose distance in `rest` is below `distance` [m] (> 0).
  void build(const Points& rest, const Triangles& faces, const MeshTopology& topology,
             double distance);
  /// The distance the lists were built for (0: not built).
  double distance() const { return m_distance; }
  /// Whether vertex v and face f are closer than distance() at rest.
  bool vertex_face(int v, int f) const { return contains(m_vf, v, f); }
  /// Whether edges e and g are closer than distance() at rest.
  bool edge_edge(int e, int g) const { return contains(m_ee, e, g); }
  /// Whether every vertex–face and edge–edge pair of faces f and g (those sharing no vertex)
  /// is a rest neighbour.
  bool faces(int f, int g) const { return contains(m_ff, f, g); }

 private:
  /// Sorted lists per index: the entries of i at list[start[i] .. start[i+1]).
  struct Lists {
    std::vector<int> start, list;
  };
  static bool contains(const Lists& l, int i, int j);
  static void fill(std::vector<std::vector<int>>& per_index, Lists& out);

  double m_distance{};
  Lists m_vf, m_ee, m_ff;
};

}  // namespace dexcloth::collision
