#pragma once
/// Axis-aligned bounding volume hierarchy over a mesh's triangles: built once, refit every step
/// (or every response iteration) with the swept boxes of the triangles' motion x0 → x1.
#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "core/worker_pool.hpp"

namespace dexcloth::collision {

/// A pair of overlapping faces: `a` in the first mesh (or the mesh itself), `b` in the second.
struct FacePair {
  int a{};
  int b{};
};

/// A threaded query's pieces per thread (enough for uneven pieces to even out) and the smallest
/// query (faces of its smaller tree) worth threads.
inline constexpr int kPiecesPerThread = 32;
inline constexpr int kParallelQueryFaces = 1000;

class UnfoldedWindows;

/// What a query may leave out, the caller having shown that none of those pairs matters.
struct QuerySkip {
  /// Of a self query, per node: the pairs within its subtree.
  const std::vector<std::uint8_t>* subtrees{};
  /// Of a self query: the pairs of nodes whose rest boxes fit together in a flagged window.
  const UnfoldedWindows* windows{};
  /// Per node of the first tree and of the second (the same for a self query): whether its
  /// subtree holds a face the query is about (touched_subtrees); the pairs of two subtrees
  /// that hold none are left out. Null: every face.
  const std::vector<std::uint8_t>* touched_a{};
  const std::vector<std::uint8_t>* touched_b{};
};

/// A piece of an overlap query (split_query): the pairs between subtree `i` of the first tree
/// and subtree `j` of the second, or, for `self`, the unordered pairs within subtree `i`.
struct BvhQuery {
  int i{};
  int j{};
  bool self{};
};

/// AABB tree with one triangle per leaf. Box of face f = bounding box of its three vertices at x0
/// and x1 (the swept triangle, for continuous collision detection), inflated by `margin` [m].
class Bvh {
 public:
  /// Builds the tree over `faces` (|F|×3) with positions `x0`, `x1` (|V|×3) [m]; median split
  /// along the longest axis of the face centroids.
  void build(const Triangles& faces, const Points& x0, const Points& x1, double margin);
  /// Recomputes every box for new positions, keeping the tree; `faces` must be the ones built.
  void refit(const Triangles& faces, const Points& x0, const Points& x1, double margin);
  /// The same for the nodes flagged in `touched` (touched_subtrees; empty: every node) only,
  /// the others' faces having kept their positions since the last refit.
  void refit(const Triangles& faces, const Points& x0, const Points& x1, double margin,
             const std::vector<std::uint8_t>& touched);
  /// Number of faces the tree was built over.
  int num_faces() const { return m_num_faces; }
  /// True when the tree holds no face.
  bool empty() const { return m_nodes.empty(); }
  /// Number of nodes (2·faces − 1). A node's left child is the next node, so children come after
  /// their parent and a reverse sweep sees every node's children before it.
  int num_nodes() const { return static_cast<int>(m_nodes.size()); }
  /// The face of leaf `node`, or -1 for an inner node.
  int leaf_face(int node) const { return m_nodes[static_cast<std::size_t>(node)].face; }
  /// The right child of inner node `node` (its left child is node + 1).
  int right_child(int node) const { return m_nodes[static_cast<std::size_t>(node)].right; }
  /// Faces under `node`; its subtree is the nodes [node, node + 2·faces − 1).
  int subtree_faces(int node) const { return m_nodes[static_cast<std::size_t>(node)].faces; }

  /// Appends to `out` every pair (face of `a`, face of `b`) whose boxes overlap.
  friend void overlapping_faces(const Bvh& a, const Bvh& b, std::vector<FacePair>& out);
  /// Appends to `out` every pair (f, g), f ≠ g, of faces of one mesh whose boxes overlap, each
  /// unordered pair once; with `skip_adjacent`, pairs sharing a vertex of `faces` are left out.
  friend void self_overlapping_faces(const Bvh& bvh, const Triangles& faces, bool skip_adjacent,
                                     std::vector<FacePair>& out);
  /// Splits the query of overlapping_faces(a, b) (or, with `self` and b the same tree as a, of
  /// self_overlapping_faces(a)) into at least `pieces` pieces where the trees allow, the biggest
  /// split first, such that the pieces' outputs (run_query, given the same `skip`),
  /// concatenated in order, are the whole query's in its order. A skipped piece is not split.
  friend void split_query(const Bvh& a, const Bvh& b, bool self, int pieces,
                          std::vector<BvhQuery>& out, const QuerySkip* skip);
  /// The same split for running on `pool` (null: one thread): into kPiecesPerThread pieces per
  /// thread when the query's smaller tree holds kParallelQueryFaces faces or more (waking the
  /// pool costs tens of µs), else one. Returns the pool to run the pieces on, or null.
  friend WorkerPool* split_query(const Bvh& a, const Bvh& b, bool self, WorkerPool* pool,
                                 std::vector<BvhQuery>& out, const QuerySkip* skip);
  /// Appends the pairs of one piece of a query to `out` (skipping faces adjacent in `faces`
  /// when it is not null, as self_overlapping_faces with skip_adjacent). With `skip`, the pairs
  /// it names are left out.
  friend void run_query(const Bvh& a, const Bvh& b, const BvhQuery& query, const Triangles* faces,
                        std::vector<FacePair>& out, const QuerySkip* skip);

 private:
  struct Node {
    double lo[3]{};
    double hi[3]{};
    int right{-1};  ///< index of the right child (the left child is the next node); -1 for a leaf
    int face{-1};   ///< face of a leaf, -1 for an inner node
    int faces{1};   ///< faces in the subtree
  };
  int build_range(int* begin, int* end, const std::vector<Vec3>& centroids);
  void face_box(Node& node, const Triangles& faces, const Points& x0, const Points& x1,
                double margin) const;

  std::vector<Node> m_nodes;
  int m_num_faces{};

  friend struct BvhTraversal;
};

/// Per node of `bvh` (built over `faces`) into `out`: 1 where its subtree holds a face with a
/// vertex flagged (nonzero) in `vertices`, else 0; for QuerySkip's touched_a and touched_b.
void touched_subtrees(const Bvh& bvh, const Triangles& faces,
                      const std::vector<std::uint8_t>& vertices, std::vector<std::uint8_t>& out);

void overlapping_faces(const Bvh& a, const Bvh& b, std::vector<FacePair>& out);
void self_overlapping_faces(const Bvh& bvh, const Triangles& faces, bool skip_adjacent,
                            std::vector<FacePair>& out);
void split_query(const Bvh& a, const Bvh& b, bool self, int pieces, std::vector<BvhQuery>& out,
                 const QuerySkip* skip = nullptr);
WorkerPool* split_query(const Bvh& a, const Bvh& b, bool self, WorkerPool* pool,
                        std::vector<BvhQuery>& out, const QuerySkip* skip = nullptr);
void run_query(const Bvh& a, const Bvh& b, const BvhQuery& query, const Triangles* faces,
               std::vector<FacePair>& out, const QuerySkip* skip = nullptr);

}  // namespace dexcloth::collision
