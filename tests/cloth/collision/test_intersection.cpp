#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "cloth/collision/intersection.hpp"
#include "cloth/collision/predicates.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;

namespace {

__extension__ typedef __int128 Int128;

// Exact sign of orient2d for points (0.5 + i·2⁻⁵³, 0.5 + j·2⁻⁵³), (12, 12), (24, 24) in integer
// arithmetic (all coordinates are integers once scaled by 2⁵³).
int kettner_sign(int i, int j) {
  const Int128 unit = Int128(1) << 53;
  const Int128 px = unit / 2 + i, py = unit / 2 + j, q = 12 * unit, r = 24 * unit;
  const Int128 det = (q - px) * (r - py) - (q - py) * (r - px);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

}  // namespace

TEST(Predicates, ExactOnKettnersNearlyCollinearGrid) {
  // The classroom example where naive floating-point orientation gives wrong signs (Kettner et
  // al. 2008); every sign must match integer arithmetic, in 2-D and lifted to 3-D.
  const double u = std::ldexp(1.0, -53);
  int zero = 0, positive = 0, negative = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const Vec2 p(0.5 + i * u, 0.5 + j * u), q(12, 12), r(24, 24);
      const int expected = kettner_sign(i, j);
      ASSERT_EQ(orient2d(p, q, r), expected) << i << ", " << j;
      ASSERT_EQ(orient3d(Vec3(p.x(), p.y(), 0), Vec3(12, 12, 0), Vec3(24, 24, 0), Vec3(0, 0, 1)),
                expected)
          << i << ", " << j;
      zero += expected == 0;
      positive += expected > 0;
      negative += expected < 0;
    }
  }
  // The grid straddles the line, so all three answers occur.
  EXPECT_GT(zero, 0);
  EXPECT_GT(positive, 0);
  EXPECT_GT(negative, 0);
}

TEST(TriangleIntersection, CrossingTriangles) {
  EXPECT_TRUE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.4, 1}));
  // A triangle piercing the other's interior with none of its edges' ends inside.
  EXPECT_TRUE(triangles_intersect({-1, -1, 0}, {2, -1, 0}, {-1, 2, 0},
                                  {0, 0, -1}, {1, 0, -1}, {0.5, 0.5, 1}));
}

TEST(TriangleIntersection, TouchingAtAVertexCounts) {
  // b0 lies exactly on vertex a1; the triangles are otherwise apart.
  EXPECT_TRUE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {1, 0, 0}, {2, 0, 1}, {2, 1, 1}));
  // b0 on the interior of a's face (vertex–face touch).
  EXPECT_TRUE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0.25, 0.25, 0}, {0.25, 0.25, 1}, {1, 1, 1}));
}

TEST(TriangleIntersection, CoplanarOverlappingAndContained) {
  EXPECT_TRUE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0.5, 0.5, 0}, {-0.5, 0.2, 0}, {0.3, -0.4, 0}));
  // b strictly inside a: no edges cross, containment must still count.
  EXPECT_TRUE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0.1, 0.1, 0}, {0.2, 0.1, 0}, {0.1, 0.2, 0}));
  EXPECT_TRUE(triangles_intersect({0.1, 0.1, 0}, {0.2, 0.1, 0}, {0.1, 0.2, 0},
                                  {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
}

TEST(TriangleIntersection, CoplanarDisjoint) {
  EXPECT_FALSE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                   {0.6, 0.6, 0}, {1.5, 0.6, 0}, {0.6, 1.5, 0}));
  // Separated by the diagonal by one ulp-sized gap.
  EXPECT_FALSE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                   {0.5, 0.5000000000000002, 0}, {1, 1, 0}, {0.5000000000000002, 0.5000000000000002, 0}));
}

TEST(TriangleIntersection, Separated) {
  EXPECT_FALSE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                   {0, 0, 1e-12}, {1, 0, 1e-12}, {0, 1, 1e-12}));
  // Non-parallel planes, but the line of intersection misses one triangle.
  EXPECT_FALSE(triangles_intersect({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                   {2, 2, -1}, {3, 2, 1}, {2, 3, 1}));
}

TEST(CountIntersections, SharedEdgeIsNotCountedButAFoldThroughIs) {
  CollisionMesh m;
  m.x0.resize(6, 3);
  m.x0 << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0,  // two triangles sharing edge (1, 2)
      0.2, 0.2, -0.5, 0.3, 0.3, 0.5;            // plus a far triangle's two corners
  m.x1 = m.x0;
  m.faces.resize(2, 3);
  m.faces << 0, 1, 2, 1, 3, 2;
  m.mass = Eigen::VectorXd::Ones(6);
  EXPECT_EQ(count_intersections({&m}, false), 0);
  // Add a triangle (4, 5, 3) that shares vertex 3 with face 1 and pierces face 0: adjacent to
  // face 1 (skipped), not to face 0 (counted).
  m.faces.conservativeResize(3, 3);
  m.faces.row(2) << 4, 5, 3;
  EXPECT_EQ(count_intersections({&m}, false), 1);
  // Obstacle–obstacle pairs are ignored; cloth–obstacle pairs count.
  CollisionMesh obstacle = m;
  obstacle.obstacle = true;
  CollisionMesh a = obstacle, b = obstacle;
  EXPECT_EQ(count_intersections({&a, &b}, true), 0);
  CollisionMesh cloth = m;
  cloth.faces.conservativeResize(1, 3);  // face (0, 1, 2) only
  CollisionMesh tri = m;
  tri.obstacle = true;
  tri.faces.resize(1, 3);
  tri.faces << 4, 5, 3;
  EXPECT_EQ(count_intersections({&cloth, &tri}, true), 1);
}

namespace {

/// A 40×40-quad sheet (3,200 faces) of side 1 m in the plane through `centre` spanned by `u`, `v`.
CollisionMesh crossing_sheet(const Vec3& centre, const Vec3& u, const Vec3& v) {
  const int n = 40;
  CollisionMesh m;
  m.x0.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.x0.row(j * (n + 1) + i) =
          (centre + (i / double(n) - 0.5) * u + (j / double(n) - 0.5) * v).transpose();
  m.x1 = m.x0;
  m.faces.resize(2 * n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.faces.row(2 * (j * n + i)) << a, b, d;
      m.faces.row(2 * (j * n + i) + 1) << a, d, c;
    }
  m.mass = Eigen::VectorXd::Ones(m.x0.rows());
  return m;
}

}  // namespace

TEST(CountIntersections, OnAPoolTheCountIsTheSame) {
  // Two large sheets crossing along a line: the pool's threads must count exactly the pairs one
  // thread counts.
  CollisionMesh a = crossing_sheet(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY());
  CollisionMesh b = crossing_sheet(Vec3(0.013, 0.007, 0.0), Vec3::UnitX(), Vec3(0, 0.6, 0.8));
  const std::vector<const CollisionMesh*> meshes{&a, &b};
  const int serial = count_intersections(meshes, false);
  ASSERT_GT(serial, 40);
  for (int threads : {2, 3}) {
    WorkerPool pool(threads);
    EXPECT_EQ(count_intersections(meshes, false, &pool), serial) << threads << " threads";
  }
}

TEST(CountIntersections, KeptTreesCountAsFreshOnes) {
  // The second sheet turned in the first one's plane through a run of frames (the crossing
  // line turns, and with it the pairs along it), the trees kept from frame to frame and refit;
  // then a mesh with fewer faces in its place, whose tree must be built anew. Each count is a
  // fresh one's. (Without self-collision: the flat sheets' own touching pairs are slow to test
  // exactly and cross nothing.)
  CollisionMesh a = crossing_sheet(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY());
  a.self_collision = false;
  std::vector<Bvh> trees;
  std::set<int> counts;
  for (int frame = 0; frame < 6; ++frame) {
    const double angle = 0.1 * frame;
    CollisionMesh b =
        crossing_sheet(Vec3(0.013, 0.007, 0.0), Vec3(std::cos(angle), std::sin(angle), 0.0),
                       Vec3(-0.6 * std::sin(angle), 0.6 * std::cos(angle), 0.8));
    b.self_collision = false;
    const std::vector<const CollisionMesh*> meshes{&a, &b};
    const int fresh = count_intersections(meshes, false);
    EXPECT_EQ(count_intersections(meshes, false, trees), fresh) << frame;
    counts.insert(fresh);
  }
  EXPECT_GE(counts.size(), 3u);
  CollisionMesh c = crossing_sheet(Vec3(0.013, 0.007, 0.25), Vec3::UnitX(), Vec3::UnitZ());
  c.faces.conservativeResize(c.faces.rows() / 2, 3);  // its lower half, across the first sheet
  c.self_collision = false;
  const std::vector<const CollisionMesh*> halved{&a, &c};
  const int fresh = count_intersections(halved, false);
  EXPECT_GT(fresh, 0);
  EXPECT_EQ(count_intersections(halved, false, trees), fresh);
}
