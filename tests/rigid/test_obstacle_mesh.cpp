#include <gtest/gtest.h>

#include <map>
#include <numbers>

#include "rigid/obstacle_mesh.hpp"

namespace dexcloth::rigid {
namespace {

/// Signed volume of a closed mesh (divergence theorem); positive iff faces wind outward.
double volume(const LocalMesh& m) {
  double v = 0.0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const Vec3 a = m.x.row(m.faces(f, 0)).transpose();
    const Vec3 b = m.x.row(m.faces(f, 1)).transpose();
    const Vec3 c = m.x.row(m.faces(f, 2)).transpose();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

TEST(ObstacleMesh, ClosedOutwardMeshesWithTheRightVolume) {
  // Box: exact. Sphere/capsule/cylinder: tessellated, within the stated relative tolerance.
  EXPECT_NEAR(volume(box_mesh(Vec3(0.1, 0.2, 0.3))), 0.006, 1e-12);
  const double pi = std::numbers::pi;
  const double r = 0.01;
  EXPECT_NEAR(volume(sphere_mesh(r, 48, 24)), 4.0 / 3.0 * pi * r * r * r, 0.02 * 4.0 / 3.0 * pi * r * r * r);
  const double cap = pi * r * r * 0.04 + 4.0 / 3.0 * pi * r * r * r;
  EXPECT_NEAR(volume(capsule_mesh(r, 0.04, 48, 12)), cap, 0.02 * cap);
  EXPECT_NEAR(volume(cylinder_mesh(r, 0.04, 64)), pi * r * r * 0.04, 0.01 * pi * r * r * 0.04);
  // Every edge is shared by exactly two faces in opposite directions (closed, consistent).
  const LocalMesh m = capsule_mesh(r, 0.04);
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) ++edges[{m.faces(f, k), m.faces(f, (k + 1) % 3)}];
  }
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
}

}  // namespace
}  // namespace dexcloth::rigid
