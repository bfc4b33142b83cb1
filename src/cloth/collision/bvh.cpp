#include "cloth/collision/bvh.hpp"

#include <algorithm>
#include <array>
#include <numeric>

#include "cloth/collision/mesh_topology.hpp"
#include "cloth/collision/unfolded_windows.hpp"
#include "core/assert.hpp"

namespace dexcloth::collision {

void Bvh::face_box(Node& node, const Triangles& faces, const Points& x0, const Points& x1,
                   double margin) const {
  for (int d = 0; d < 3; ++d) {
    double lo = x0(faces(node.face, 0), d), hi = lo;
    for (int k = 0; k < 3; ++k) {
      const int v = faces(node.face, k);
      lo = std::min({lo, x0(v, d), x1(v, d)});
      hi = std::max({hi, x0(v, d), x1(v, d)});
    }
    node.lo[d] = lo - margin;
    node.hi[d] = hi + margin;
  }
}

int Bvh::build_range(int* begin, int* end, const std::vector<Vec3>& centroids) {
  const int index = static_cast<int>(m_nodes.size());
  m_nodes.emplace_back();
  if (end - begin == 1) {
    m_nodes[static_cast<std::size_t>(index)].face = *begin;
    return index;
  }
  // Split at the median along the longest axis of the centroids' bounds.
  Vec3 lo = centroids[static_cast<std::size_t>(*begin)], hi = lo;
  for (int* it = begin; it != end; ++it) {
    lo = lo.cwiseMin(centroids[static_cast<std::size_t>(*it)]);
    hi = hi.cwiseMax(centroids[static_cast<std::size_t>(*it)]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  int* mid = begin + (end - begin) / 2;
  std::nth_element(begin, mid, end, [&](int f, int g) {
    return centroids[static_cast<std::size_t>(f)][axis] <
           centroids[static_cast<std::size_t>(g)][axis];
  });
  build_range(begin, mid, centroids);
  const int right = build_range(mid, end, centroids);
  m_nodes[static_cast<std::size_t>(index)].right = right;
  m_nodes[static_cast<std::size_t>(index)].faces = static_cast<int>(end - begin);
  return index;
}

void Bvh::build(const Triangles& faces, const Points& x0, const Points& x1, double margin) {
  m_num_faces = static_cast<int>(faces.rows());
  m_nodes.clear();
  if (m_num_faces == 0) return;
  m_nodes.reserve(static_cast<std::size_t>(2 * m_num_faces - 1));
  std::vector<Vec3> centroids(static_cast<std::size_t>(m_num_faces));
  for (int f = 0; f < m_num_faces; ++f) {
    centroids[static_cast<std::size_t>(f)] =
        (x0.row(faces(f, 0)) + x0.row(faces(f, 1)) + x0.row(faces(f, 2))).transpose() / 3.0;
  }
  std::vector<int> order(static_cast<std::size_t>(m_num_faces));
  std::iota(order.begin(), order.end(), 0);
  build_range(order.data(), order.data() + order.size(), centroids);
  refit(faces, x0, x1, margin);
}

void Bvh::refit(const Triangles& faces, const Points& x0, const Points& x1, double margin) {
  refit(faces, x0, x1, margin, {});
}

void Bvh::refit(const Triangles& faces, const Points& x0, const Points& x1, double margin,
                const std::vector<std::uint8_t>& touched) {
  DEXCLOTH_DEMAND(faces.rows() == m_num_faces &&
                  (touched.empty() || touched.size() == m_nodes.size()));
  // Children come after their parent, so a reverse sweep sees children first.
  for (std::size_t i = m_nodes.size(); i-- > 0;) {
    if (!touched.empty() && touched[i] == 0) continue;
    Node& n = m_nodes[i];
    if (n.face >= 0) {
      face_box(n, faces, x0, x1, margin);
      continue;
    }
    const Node& l = m_nodes[i + 1];
    const Node& r = m_nodes[static_cast<std::size_t>(n.right)];
    for (int d = 0; d < 3; ++d) {
      n.lo[d] = std::min(l.lo[d], r.lo[d]);
      n.hi[d] = std::max(l.hi[d], r.hi[d]);
    }
  }
}

/// Recursive pairwise descent over one or two trees (no allocation beyond `out`).
struct BvhTraversal {
  const std::vector<Bvh::Node>& na;
  const std::vector<Bvh::Node>& nb;
  const Triangles* faces;  // set for a self query that skips adjacent faces
  std::vector<FacePair>& out;
  const QuerySkip* skip{};  // the pairs to leave out

  // Whether `skip` leaves out the pairs within subtree i, or those between subtrees i and j.
  static bool skips_self(const QuerySkip* skip, int i) {
    return skip != nullptr &&
           ((skip->subtrees != nullptr && (*skip->subtrees)[static_cast<std::size_t>(i)] != 0) ||
            (skip->windows != nullptr && skip->windows->skips(i, i)) ||
            (skip->touched_a != nullptr && (*skip->touched_a)[static_cast<std::size_t>(i)] == 0));
  }
  static bool skips_pair(const QuerySkip* skip, int i, int j) {
    return skip != nullptr &&
           ((skip->windows != nullptr && skip->windows->skips(i, j)) ||
            (skip->touched_a != nullptr && (*skip->touched_a)[static_cast<std::size_t>(i)] == 0 &&
             (*skip->touched_b)[static_cast<std::size_t>(j)] == 0));
  }

  static bool overlap(const Bvh::Node& p, const Bvh::Node& q) {
    return p.lo[0] <= q.hi[0] && q.lo[0] <= p.hi[0] && p.lo[1] <= q.hi[1] && q.lo[1] <= p.hi[1] &&
           p.lo[2] <= q.hi[2] && q.lo[2] <= p.hi[2];
  }
  static double extent(const Bvh::Node& n) {
    return (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2]);
  }
  /// Whether pair(p, q) descends p (else q): the bigger inner node, or the only one.
  static bool descends_first(const Bvh::Node& p, const Bvh::Node& q) {
    const bool leaf_p = p.face >= 0, leaf_q = q.face >= 0;
    return leaf_q || (!leaf_p && extent(p) >= extent(q));
  }

  // Pairs between subtree i of `na` and subtree j of `nb`.
  void pair(int i, int j) {
    if (overlap(na[static_cast<std::size_t>(i)], nb[static_cast<std::size_t>(j)])) descend(i, j);
  }
  // pair(i, j) for boxes known to overlap: each child pair's boxes are tested before descending.
  // The tests are written out, not calls of pair(): GCC then inlines descend into pair and
  // recurses through pair, calling it for disjoint boxes too.
  void descend(int i, int j) {
    if (skips_pair(skip, i, j)) return;
    const Bvh::Node& p = na[static_cast<std::size_t>(i)];
    const Bvh::Node& q = nb[static_cast<std::size_t>(j)];
    const bool leaf_p = p.face >= 0, leaf_q = q.face >= 0;
    if (leaf_p && leaf_q) {
      if (faces != nullptr && faces_adjacent(*faces, p.face, q.face)) return;
      out.push_back({p.face, q.face});
      return;
    }
    // Descend the bigger (or the only inner) node.
    if (descends_first(p, q)) {
      if (overlap(na[static_cast<std::size_t>(i) + 1], q)) descend(i + 1, j);
      if (overlap(na[static_cast<std::size_t>(p.right)], q)) descend(p.right, j);
    } else {
      if (overlap(p, nb[static_cast<std::size_t>(j) + 1])) descend(i, j + 1);
      if (overlap(p, nb[static_cast<std::size_t>(q.right)])) descend(i, q.right);
    }
  }

  // Unordered pairs within subtree i of a single tree.
  void self(int i) {
    const Bvh::Node& n = na[static_cast<std::size_t>(i)];
    if (n.face >= 0) return;
    if (skips_self(skip, i)) return;
    self(i + 1);
    self(n.right);
    pair(i + 1, n.right);
  }
};

void touched_subtrees(const Bvh& bvh, const Triangles& faces,
                      const std::vector<std::uint8_t>& vertices, std::vector<std::uint8_t>& out) {
  DEXCLOTH_DEMAND(faces.rows() == bvh.num_faces());
  out.assign(static_cast<std::size_t>(bvh.num_nodes()), 0);
  // Children come after their parent, so a reverse sweep sees children first.
  for (int i = bvh.num_nodes(); i-- > 0;) {
    const int f = bvh.leaf_face(i);
    const auto k = static_cast<std::size_t>(i);
    if (f >= 0) {
      for (int c = 0; c < 3; ++c)
        if (vertices[static_cast<std::size_t>(faces(f, c))] != 0) out[k] = 1;
    } else {
      out[k] = out[k + 1] | out[static_cast<std::size_t>(bvh.right_child(i))];
    }
  }
}

void overlapping_faces(const Bvh& a, const Bvh& b, std::vector<FacePair>& out) {
  if (a.empty() || b.empty()) return;
  BvhTraversal t{a.m_nodes, b.m_nodes, nullptr, out, nullptr};
  t.pair(0, 0);
}

void self_overlapping_faces(const Bvh& bvh, const Triangles& faces, bool skip_adjacent,
                            std::vector<FacePair>& out) {
  if (bvh.empty()) return;
  BvhTraversal t{bvh.m_nodes, bvh.m_nodes, skip_adjacent ? &faces : nullptr, out, nullptr};
  t.self(0);
}

void split_query(const Bvh& a, const Bvh& b, bool self, int pieces, std::vector<BvhQuery>& out,
                 const QuerySkip* skip) {
  out.clear();
  if (a.empty() || b.empty()) return;
  out.push_back({0, 0, self});
  const auto& na = a.m_nodes;
  DEXCLOTH_DEMAND(!self || &a == &b);
  const auto& nb = b.m_nodes;
  // The pieces a query's recursion makes of it, in its order (BvhTraversal::self and pair);
  // none for a pair of disjoint boxes or of two leaves, which split no further.
  const auto size = [&](const BvhQuery& q) {
    const Bvh::Node& p = na[static_cast<std::size_t>(q.i)];
    if (q.self)
      return p.face >= 0 || BvhTraversal::skips_self(skip, q.i)
                 ? 0.0
                 : static_cast<double>(p.faces) * p.faces;
    const Bvh::Node& r = nb[static_cast<std::size_t>(q.j)];
    if ((p.face >= 0 && r.face >= 0) || !BvhTraversal::overlap(p, r) ||
        BvhTraversal::skips_pair(skip, q.i, q.j))
      return 0.0;
    return static_cast<double>(p.faces) * r.faces;
  };
  while (static_cast<int>(out.size()) < pieces) {
    std::size_t biggest = 0;
    for (std::size_t k = 1; k < out.size(); ++k)
      if (size(out[k]) > size(out[biggest])) biggest = k;
    if (size(out[biggest]) == 0.0) break;
    const BvhQuery q = out[biggest];
    const Bvh::Node& p = na[static_cast<std::size_t>(q.i)];
    std::array<BvhQuery, 3> parts;
    std::size_t count = 0;
    if (q.self) {
      parts = {BvhQuery{q.i + 1, q.i + 1, true}, BvhQuery{p.right, p.right, true},
               BvhQuery{q.i + 1, p.right, false}};
      count = 3;
    } else if (BvhTraversal::descends_first(p, nb[static_cast<std::size_t>(q.j)])) {
      parts[0] = {q.i + 1, q.j, false};
      parts[1] = {p.right, q.j, false};
      count = 2;
    } else {
      const Bvh::Node& r = nb[static_cast<std::size_t>(q.j)];
      parts[0] = {q.i, q.j + 1, false};
      parts[1] = {q.i, r.right, false};
      count = 2;
    }
    out.erase(out.begin() + static_cast<std::ptrdiff_t>(biggest));
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(biggest), parts.begin(),
               parts.begin() + static_cast<std::ptrdiff_t>(count));
  }
}

WorkerPool* split_query(const Bvh& a, const Bvh& b, bool self, WorkerPool* pool,
                        std::vector<BvhQuery>& out, const QuerySkip* skip) {
  const bool threaded = pool != nullptr && pool->threads() > 1 &&
                        std::min(a.num_faces(), b.num_faces()) >= kParallelQueryFaces;
  split_query(a, b, self, threaded ? kPiecesPerThread * pool->threads() : 1, out, skip);
  return threaded ? pool : nullptr;
}

void run_query(const Bvh& a, const Bvh& b, const BvhQuery& query, const Triangles* faces,
               std::vector<FacePair>& out, const QuerySkip* skip) {
  if (a.empty() || b.empty()) return;
  DEXCLOTH_DEMAND(skip == nullptr ||
                  (((skip->subtrees == nullptr && skip->windows == nullptr) || &a == &b) &&
                   (skip->subtrees == nullptr || skip->subtrees->size() == a.m_nodes.size()) &&
                   (skip->windows == nullptr || skip->windows->num_nodes() == a.num_nodes()) &&
                   (skip->touched_a == nullptr ||
                    (skip->touched_b != nullptr && skip->touched_a->size() == a.m_nodes.size() &&
                     skip->touched_b->size() == b.m_nodes.size()))));
  BvhTraversal t{a.m_nodes, b.m_nodes, faces, out, skip};
  if (query.self) {
    t.self(query.i);
  } else {
    t.pair(query.i, query.j);
  }
}

}  // namespace dexcloth::collision
