#pragma once
/// Axis-aligned bounding volume hierarchy over a mesh's triangles: built once, refit every step
/// (or every response iteration) with the swept boxes of the triangles' motion x0 → x1.
#include <vector>

#include "core/types.hpp"

namespace dexcloth::collision {

/// A pair of overlapping faces: `a` in the first mesh (or the mesh itself), `b` in the second.
struct FacePair {
  int a{};
  int b{};
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
  /// Number of faces the tree was built over.
  int num_faces() const { return m_num_faces; }
  /// True when the tree holds no face.
  bool empty() const { return m_nodes.empty(); }

  /// Appends to `out` every pair (face of `a`, face of `b`) whose boxes overlap.
  friend void overlapping_faces(const Bvh& a, const Bvh& b, std::vector<FacePair>& out);
  /// Appends to `out` every pair (f, g), f ≠ g, of faces of one mesh whose boxes overlap, each
  /// unordered pair once; with `skip_adjacent`, pairs sharing a vertex of `faces` are left out.
  friend void self_overlapping_faces(const Bvh& bvh, const Triangles& faces, bool skip_adjacent,
                                     std::vector<FacePair>& out);

 private:
  struct Node {
    double lo[3]{};
    double hi[3]{};
    int right{-1};  ///< index of the right child (the left child is the next node); -1 for a leaf
    int face{-1};   ///< face of a leaf, -1 for an inner node
  };
  int build_range(int* begin, int* end, const std::vector<Vec3>& centroids);
  void face_box(Node& node, const Triangles& faces, const Points& x0, const Points& x1,
                double margin) const;

  std::vector<Node> m_nodes;
  int m_num_faces{};

  friend struct BvhTraversal;
};

void overlapping_faces(const Bvh& a, const Bvh& b, std::vector<FacePair>& out);
void self_overlapping_faces(const Bvh& bvh, const Triangles& faces, bool skip_adjacent,
                            std::vector<FacePair>& out);

}  // namespace dexcloth::collision
