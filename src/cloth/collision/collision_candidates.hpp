#pragma once
/// Broad phase of collision handling: per-mesh BVHs and topology kept between steps, and the
/// primitive pairs (vertex–face, edge–edge) whose face boxes overlap, each generated once.
#include <array>
#include <memory>
#include <vector>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/collision_mesh.hpp"
#include "cloth/collision/mesh_topology.hpp"
#include "cloth/collision/rest_neighbours.hpp"
#include "cloth/collision/unfolded_subtrees.hpp"
#include "cloth/collision/unfolded_windows.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::collision {

/// Vertex `vertex` of mesh `vertex_mesh` against face `face` of mesh `face_mesh`.
struct VertexFacePair {
  int vertex_mesh{};
  int vertex{};
  int face_mesh{};
  int face{};
};

/// Edge `edge_a` of mesh `mesh_a` against edge `edge_b` of mesh `mesh_b` (indices into
/// `MeshTopology::edges`).
struct EdgeEdgePair {
  int mesh_a{};
  int edge_a{};
  int mesh_b{};
  int edge_b{};
};

/// Axis-aligned box of a primitive's motion, inflated by the broad phase's margin [m].
struct PrimitiveBox {
  double lo[3]{};
  double hi[3]{};
};

/// BVHs, topology and candidate primitive pairs of a collision scene. Keep one per simulation:
/// trees are built on first use (and when a mesh's vertex or face count changes) and refit after.
class CollisionCandidates {
 public:
  /// Refits every mesh's tree on the boxes of x0 ∪ x1 (`swept`) or of x0 alone, inflated by
  /// `margin` [m] (two primitives within 2·margin are found), then collects every vertex–face and
  /// edge–edge pair whose faces' boxes overlap and whose own boxes overlap: within each cloth
  /// mesh (unless its `self_collision` is off), between cloth meshes, between cloth and
  /// obstacles (never obstacle–obstacle). Pairs sharing a vertex are left out. Each pair
  /// appears once. Within a cloth with a planar rest shape, the pairs of whole subtrees of its
  /// tree (UnfoldedSubtrees), and of nodes whose rest boxes fit in a window of its rest plane
  /// (UnfoldedWindows), that are shown to hold none within 2·margin are left out too: swept,
  /// none within 2·margin at any time of the linear motion x0 → x1; otherwise, none but rest
  /// neighbours (set_rest_neighbour_distance; nothing is left out while that is 0). So every
  /// pair within 2·margin is found, but not every pair whose boxes overlap.
  void update(const std::vector<const CollisionMesh*>& meshes, bool swept, double margin);
  /// The same with the boxes of the obstacles searched beyond the thickness
  /// (CollisionMesh::beyond_thickness) inflated by `obstacle_margin` ≥ `margin` instead: their
  /// pairs with cloth within margin + obstacle_margin are found.
  void update(const std::vector<const CollisionMesh*>& meshes, bool swept, double margin,
              double obstacle_margin);
  /// The swept update again after some cloth vertices moved their x1, for the impact zones'
  /// next round: `moved` holds per mesh, per vertex, a nonzero flag where x1 changed since the
  /// last update, which was `update(meshes, true, margin)` of the same meshes (an empty list:
  /// none moved). Collects the pairs update would, among the face pairs with a flagged vertex
  /// only (no subtree or window is left out); a pair of unflagged faces, unchanged, is left to
  /// what the last update found of it. Meshes that differ in size from the last update's get a
  /// whole update instead.
  void update_moved(const std::vector<const CollisionMesh*>& meshes, double margin,
                    const std::vector<std::vector<std::uint8_t>>& moved);
  /// Forces a rebuild of trees and topology on the next `update` (after remeshing).
  void reset() { m_topology.clear(); }
  /// Runs the pair searches on `pool`'s threads (null: the calling thread only). The pairs found,
  /// and their order, do not depend on it.
  void set_pool(WorkerPool* pool) { m_pool = pool; }
  /// The pool set by set_pool, or null.
  WorkerPool* pool() const { return m_pool; }
  /// Keeps the unfolded subtrees' fits of this search's cloths where `other` keeps its own (a
  /// search over the same meshes, never run at the same time as this one), so that positions
  /// one of them fitted are not fitted again by the other: the step's proximity search at a
  /// step's start and the impact zones' swept search, whose x1 is the next step's start. The
  /// pairs found do not change.
  void share_fits(CollisionCandidates& other);
  /// Leaves out the vertex–face and edge–edge pairs of one cloth closer than `distance` [m] in
  /// its rest shape (0: none left out), which the proximity search drops anyway (rest
  /// neighbours), without testing each.
  void set_rest_neighbour_distance(double distance);

  /// Vertex–face pairs found by the last `update`.
  const std::vector<VertexFacePair>& vertex_face() const { return m_vf; }
  /// Edge–edge pairs found by the last `update`.
  const std::vector<EdgeEdgePair>& edge_edge() const { return m_ee; }
  /// Topology (edges, ownership) of mesh `m` as of the last `update`.
  const MeshTopology& topology(int m) const { return m_topology[static_cast<std::size_t>(m)]; }
  /// Mesh m's unfolded subtrees as the last `update` left them, or null (none built).
  const UnfoldedSubtrees* unfolded(int m) const {
    const auto k = static_cast<std::size_t>(m);
    return k < m_unfolded.size() && m_unfolded[k].num_nodes() > 0 ? &m_unfolded[k] : nullptr;
  }
  /// The windows the last `update` left mesh m's self pairs out by, or null (none used).
  const UnfoldedWindows* windows(int m) const {
    return m_skip.size() > static_cast<std::size_t>(m) ? m_skip[static_cast<std::size_t>(m)].windows
                                                       : nullptr;
  }

 private:
  /// The boxes of mesh m's vertices, edges and faces (x0, and x1 when `swept`), inflated; with
  /// `moved` (per vertex; null: all), of the moved vertices and their edges and faces only.
  void primitive_boxes(const CollisionMesh& mesh, std::size_t m, bool swept, double inflate,
                       const std::vector<std::uint8_t>* moved = nullptr);
  /// Collects the pairs of every mesh pair that may have some: within a self-colliding cloth,
  /// between cloths, between cloth and bodies. With `moved_meshes` (per mesh, nonzero where
  /// update_moved was given a moved vertex), only of the pairs of meshes with one, and of their
  /// face pairs touching a moved vertex (m_touched).
  void collect_all(const std::vector<const CollisionMesh*>& meshes,
                   const std::vector<std::uint8_t>* moved_meshes);
  /// Appends the pairs of meshes ma and mb (with `touched`, of face pairs touching a vertex
  /// update_moved flagged only).
  void collect(const std::vector<const CollisionMesh*>& meshes, int ma, int mb, bool touched);
  /// Appends the vertex–face and edge–edge pairs of `face_pairs` (of meshes ma, mb).
  void primitive_pairs(const std::vector<const CollisionMesh*>& meshes, int ma, int mb,
                       const std::vector<FacePair>& face_pairs, std::vector<VertexFacePair>& vf,
                       std::vector<EdgeEdgePair>& ee) const;

  /// Mesh m's rest neighbours at the distance set, or null (none set, or not a cloth).
  const RestNeighbours* rest_neighbours(int m) const;

  WorkerPool* m_pool{};
  double m_rest_distance{};
  std::vector<RestNeighbours> m_rest;                     // per mesh
  std::vector<UnfoldedSubtrees> m_unfolded;               // per mesh
  // Per mesh, where its unfolded subtrees keep their fits, shared with another search (null:
  // each keeps its own).
  std::shared_ptr<std::vector<std::unique_ptr<UnfoldedSubtrees::KeptFits>>> m_kept_fits;
  std::vector<std::array<UnfoldedWindows, 2>> m_windows;  // per mesh: proximity, swept
  std::vector<double> m_mean_edge;  // per mesh: of its rest plane, when its subtrees were built
  std::vector<QuerySkip> m_skip;    // per mesh: what its self query leaves out
  std::vector<std::vector<std::uint8_t>> m_touched;  // of update_moved: per mesh, per node
  double m_swept_margin{-1.0};      // margin of the last update, if swept (else −1)
  std::vector<BvhQuery> m_queries;  // pieces of a face-pair query
  // Each piece's face pairs and their primitive pairs.
  std::vector<std::vector<FacePair>> m_piece_pairs;
  std::vector<std::vector<VertexFacePair>> m_piece_vf;
  std::vector<std::vector<EdgeEdgePair>> m_piece_ee;
  std::vector<MeshTopology> m_topology;
  std::vector<Bvh> m_bvh;
  std::vector<std::vector<PrimitiveBox>> m_vertex_boxes;  // per mesh, per vertex
  std::vector<std::vector<PrimitiveBox>> m_edge_boxes;    // per mesh, per topology edge
  std::vector<std::vector<PrimitiveBox>> m_face_boxes;    // per mesh, per face
  std::vector<VertexFacePair> m_vf;
  std::vector<EdgeEdgePair> m_ee;
};

}  // namespace dexcloth::collision
