#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <utility>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/mesh_topology.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

// Random triangle soup: |F| faces over |V| vertices scattered in a cube of side `size`, with a
// random motion x0 → x1.
struct Soup {
  Points x0, x1;
  Triangles faces;
};

Soup random_soup(std::mt19937& rng, int nv, int nf, double size, double motion) {
  std::uniform_real_distribution<double> pos(0.0, size), mv(-motion, motion);
  std::uniform_int_distribution<int> pick(0, nv - 1);
  Soup s;
  s.x0.resize(nv, 3);
  s.x1.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    for (int d = 0; d < 3; ++d) s.x0(v, d) = pos(rng);
  }
  // Small triangles: a vertex and two of its index neighbours (so faces share vertices).
  s.faces.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    const int a = pick(rng);
    s.faces.row(f) << a, (a + 1) % nv, (a + 2) % nv;
    for (int k = 1; k < 3; ++k)
      s.x0.row(s.faces(f, k)) = s.x0.row(a) + Eigen::RowVector3d(mv(rng), mv(rng), mv(rng));
  }
  for (int v = 0; v < nv; ++v)
    for (int d = 0; d < 3; ++d) s.x1(v, d) = s.x0(v, d) + mv(rng);
  return s;
}

// Swept, inflated box of face f, computed independently of the BVH.
std::pair<Vec3, Vec3> box(const Soup& s, int f, double margin) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int k = 0; k < 3; ++k) {
    lo = lo.cwiseMin(s.x0.row(s.faces(f, k)).transpose())
             .cwiseMin(s.x1.row(s.faces(f, k)).transpose());
    hi = hi.cwiseMax(s.x0.row(s.faces(f, k)).transpose())
             .cwiseMax(s.x1.row(s.faces(f, k)).transpose());
  }
  return {lo.array() - margin, hi.array() + margin};
}

bool boxes_overlap(const std::pair<Vec3, Vec3>& a, const std::pair<Vec3, Vec3>& b) {
  return (a.first.array() <= b.second.array()).all() && (b.first.array() <= a.second.array()).all();
}

std::vector<std::pair<int, int>> sorted(const std::vector<FacePair>& pairs, bool unordered) {
  std::vector<std::pair<int, int>> out;
  for (const FacePair& p : pairs)
    out.emplace_back(unordered ? std::min(p.a, p.b) : p.a, unordered ? std::max(p.a, p.b) : p.b);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Bvh, MeshPairOverlapsEqualBruteForce) {
  std::mt19937 rng(12345);
  const double margin = 0.01;
  Soup a = random_soup(rng, 600, 500, 1.0, 0.03);
  Soup b = random_soup(rng, 500, 400, 1.0, 0.03);
  Bvh ta, tb;
  ta.build(a.faces, a.x0, a.x1, margin);
  tb.build(b.faces, b.x0, b.x1, margin);

  // Check after the build and again after moving the meshes and refitting.
  for (int round = 0; round < 2; ++round) {
    std::vector<FacePair> found;
    overlapping_faces(ta, tb, found);
    std::vector<std::pair<int, int>> expected;
    for (int f = 0; f < a.faces.rows(); ++f)
      for (int g = 0; g < b.faces.rows(); ++g)
        if (boxes_overlap(box(a, f, margin), box(b, g, margin))) expected.emplace_back(f, g);
    ASSERT_GT(expected.size(), 10u);
    EXPECT_EQ(sorted(found, false), expected);
    // Move mesh b and refit both trees.
    a.x1.array() += 0.02;
    b.x0 = b.x1;
    b.x1.col(0).array() -= 0.1;
    ta.refit(a.faces, a.x0, a.x1, margin);
    tb.refit(b.faces, b.x0, b.x1, margin);
  }
}

TEST(Bvh, SelfOverlapsEqualBruteForceWithAndWithoutAdjacency) {
  std::mt19937 rng(777);
  const double margin = 0.005;
  const Soup s = random_soup(rng, 800, 700, 1.0, 0.03);
  Bvh tree;
  tree.build(s.faces, s.x0, s.x1, margin);
  for (const bool skip : {false, true}) {
    std::vector<FacePair> found;
    self_overlapping_faces(tree, s.faces, skip, found);
    std::vector<std::pair<int, int>> expected;
    int adjacent = 0;
    for (int f = 0; f < s.faces.rows(); ++f) {
      for (int g = f + 1; g < s.faces.rows(); ++g) {
        if (!boxes_overlap(box(s, f, margin), box(s, g, margin))) continue;
        const bool adj = faces_adjacent(s.faces, f, g);
        adjacent += adj;
        if (skip && adj) continue;
        expected.emplace_back(f, g);
      }
    }
    ASSERT_GT(adjacent, 0);  // the soup has adjacent faces, so skipping is exercised
    EXPECT_EQ(sorted(found, true), expected);
  }
}

TEST(Bvh, QueryPiecesConcatenateToTheWholeQueryInItsOrder) {
  // Split for parallel searches, the pieces' pairs in order must be the query's, pair for pair.
  std::mt19937 rng(31);
  const double margin = 0.005;
  const Soup a = random_soup(rng, 600, 500, 1.0, 0.03), b = random_soup(rng, 500, 400, 1.0, 0.03);
  Bvh ta, tb;
  ta.build(a.faces, a.x0, a.x1, margin);
  tb.build(b.faces, b.x0, b.x1, margin);
  for (const bool self : {true, false}) {
    std::vector<FacePair> whole;
    if (self) {
      self_overlapping_faces(ta, a.faces, false, whole);
    } else {
      overlapping_faces(ta, tb, whole);
    }
    ASSERT_GT(whole.size(), 100u);
    for (const int pieces : {1, 7, 40}) {
      std::vector<BvhQuery> queries;
      const Bvh& other = self ? ta : tb;
      split_query(ta, other, self, pieces, queries);
      EXPECT_GE(queries.size(), static_cast<std::size_t>(pieces));
      std::vector<FacePair> joined;
      for (const BvhQuery& q : queries) run_query(ta, other, q, nullptr, joined);
      ASSERT_EQ(joined.size(), whole.size()) << self << " " << pieces;
      for (std::size_t k = 0; k < whole.size(); ++k) {
        EXPECT_EQ(joined[k].a, whole[k].a);
        EXPECT_EQ(joined[k].b, whole[k].b);
      }
    }
  }
}

TEST(MeshTopology, EveryEdgeAndVertexOwnedExactlyOnce) {
  Triangles faces(4, 3);
  faces << 0, 1, 2, 1, 3, 2, 2, 3, 4, 0, 2, 4;
  const MeshTopology t = build_topology(faces, 6);  // vertex 5 is in no face
  EXPECT_EQ(t.edges.size(), 8u);
  int owned_edges = 0, owned_vertices = 0;
  for (std::size_t f = 0; f < 4; ++f) {
    owned_edges += std::popcount(static_cast<unsigned>(t.owned_edges[f]));
    owned_vertices += std::popcount(static_cast<unsigned>(t.owned_vertices[f]));
    for (int k = 0; k < 3; ++k) {
      const auto& e =
          t.edges[static_cast<std::size_t>(t.face_edges[f][static_cast<std::size_t>(k)])];
      const int a = faces(static_cast<int>(f), k), b = faces(static_cast<int>(f), (k + 1) % 3);
      EXPECT_EQ(e[0], std::min(a, b));
      EXPECT_EQ(e[1], std::max(a, b));
    }
  }
  EXPECT_EQ(owned_edges, 8);
  EXPECT_EQ(owned_vertices, 5);
  // The faces around each vertex, in face order.
  const std::vector<std::vector<int>> around = {{0, 3}, {0, 1}, {0, 1, 2, 3}, {1, 2}, {2, 3}, {}};
  ASSERT_EQ(t.vertex_face_start.size(), 7u);
  for (std::size_t v = 0; v < 6; ++v)
    EXPECT_EQ(std::vector<int>(t.vertex_faces.begin() + t.vertex_face_start[v],
                               t.vertex_faces.begin() + t.vertex_face_start[v + 1]),
              around[v])
        << "vertex " << v;
}

TEST(MeshTopology, PiecesAreFacesJoinedByVerticesAndClosedMeansEveryEdgeTwiceOpposite) {
  const CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  const CollisionMesh body =
      join_obstacles(box, make_box(Vec3(0.0, -0.01, -0.01), Vec3(0.1, 0.01, 0.01)));
  const MeshTopology t = build_topology(body.faces, static_cast<int>(body.x0.rows()));
  EXPECT_TRUE(t.closed);
  ASSERT_EQ(t.pieces(), 2);
  for (std::size_t f = 0; f < 24; ++f) EXPECT_EQ(t.face_piece[f], f < 12 ? 0 : 1) << "face " << f;
  for (int k = 0; k < 2; ++k)
    for (int i = t.piece_face_start[static_cast<std::size_t>(k)];
         i < t.piece_face_start[static_cast<std::size_t>(k) + 1]; ++i)
      EXPECT_EQ(t.face_piece[static_cast<std::size_t>(t.piece_faces[static_cast<std::size_t>(i)])],
                k);
  // A face missing, or turned inside out: open.
  EXPECT_FALSE(build_topology(box.faces.topRows(11), 8).closed);
  Triangles turned = box.faces;
  std::swap(turned(3, 1), turned(3, 2));
  EXPECT_FALSE(build_topology(turned, 8).closed);
  const MeshTopology sheet =
      build_topology(make_sheet(3, 2, 0.3, 0.2, Vec3::Zero(), 1.0).faces, 12);
  EXPECT_FALSE(sheet.closed);
  EXPECT_EQ(sheet.pieces(), 1);
}
