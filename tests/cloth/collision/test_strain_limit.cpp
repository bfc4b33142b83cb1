#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "cloth/collision/strain_limit.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

// Singular values of every face's deformation gradient, measured independently.
std::vector<double> stretches(const Points& x, const Triangles& faces, const std::vector<Mat2>& dm_inv) {
  std::vector<double> s;
  for (int f = 0; f < faces.rows(); ++f) {
    Mat32 ds;
    ds.col(0) = (x.row(faces(f, 1)) - x.row(faces(f, 0))).transpose();
    ds.col(1) = (x.row(faces(f, 2)) - x.row(faces(f, 0))).transpose();
    const Vec2 sv = Eigen::JacobiSVD<Mat32>(ds * dm_inv[static_cast<std::size_t>(f)]).singularValues();
    s.push_back(sv[0]);
    s.push_back(sv[1]);
  }
  return s;
}

}  // namespace

TEST(StrainLimit, HeavilyStretchedRandomMeshEndsWithinBounds) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), noise(-0.01, 0.01);
  // Rest shape: a 12×12 grid of 1 cm cells with jittered vertices (material space).
  CollisionMesh m = make_sheet(12, 12, 0.12, 0.12, Vec3::Zero(), 1e-4);
  const int nv = static_cast<int>(m.x0.rows());
  Points2 rest(nv, 2);
  for (int v = 0; v < nv; ++v) rest.row(v) << m.x0(v, 0) + 0.01 * jitter(rng), m.x0(v, 1) + 0.01 * jitter(rng);
  std::vector<Mat2> dm_inv;
  for (int f = 0; f < m.faces.rows(); ++f) {
    Mat2 dm;
    dm.col(0) = (rest.row(m.faces(f, 1)) - rest.row(m.faces(f, 0))).transpose();
    dm.col(1) = (rest.row(m.faces(f, 2)) - rest.row(m.faces(f, 0))).transpose();
    dm_inv.push_back(dm.inverse());
  }
  // Deformed: stretched 1.8× along x, 1.3× along y, bent out of plane, plus noise; random masses.
  Points x(nv, 3);
  Eigen::VectorXd mass(nv);
  std::uniform_real_distribution<double> mass_dist(0.5e-4, 2e-4);
  for (int v = 0; v < nv; ++v) {
    x.row(v) << 1.8 * rest(v, 0) + noise(rng), 1.3 * rest(v, 1) + noise(rng),
        0.05 * std::sin(20.0 * rest(v, 0)) + noise(rng);
    mass[v] = mass_dist(rng);
  }
  std::vector<std::uint8_t> frozen(static_cast<std::size_t>(nv), 0);
  frozen[0] = 1;
  frozen[static_cast<std::size_t>(nv / 2)] = 1;
  // Both frozen vertices sit where their rest distance allows (within the bounds).
  x.row(nv / 2) = x.row(0) + Eigen::RowVector3d(rest(nv / 2, 0) - rest(0, 0), rest(nv / 2, 1) - rest(0, 1), 0.0);
  const Points before = x;

  StrainLimitOptions options;
  options.min_stretch = 0.95;
  options.max_stretch = 1.1;
  const auto initial = stretches(x, m.faces, dm_inv);
  ASSERT_GT(*std::max_element(initial.begin(), initial.end()), 1.5);

  const StrainLimitReport report = limit_strain(x, m.faces, dm_inv, mass, frozen, options);
  EXPECT_TRUE(report.converged) << report.violation;
  for (const double s : stretches(x, m.faces, dm_inv)) {
    EXPECT_GE(s, options.min_stretch - 1e-3);
    EXPECT_LE(s, options.max_stretch + 1e-3);
  }
  for (const int v : {0, nv / 2})
    for (int d = 0; d < 3; ++d) EXPECT_EQ(x(v, d), before(v, d));
}

TEST(StrainLimit, TriangleWithinBoundsIsNotMoved) {
  CollisionMesh m = make_sheet(1, 1, 1.0, 1.0, Vec3::Zero(), 1.0);
  std::vector<Mat2> dm_inv;
  for (int f = 0; f < 2; ++f) {
    Mat2 dm;
    dm.col(0) = (m.x0.row(m.faces(f, 1)) - m.x0.row(m.faces(f, 0))).leftCols<2>().transpose();
    dm.col(1) = (m.x0.row(m.faces(f, 2)) - m.x0.row(m.faces(f, 0))).leftCols<2>().transpose();
    dm_inv.push_back(dm.inverse());
  }
  Points x = m.x0;
  x.col(0) *= 1.05;
  const Points before = x;
  const StrainLimitReport report = limit_strain(x, m.faces, dm_inv, m.mass, {}, StrainLimitOptions{});
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(x, before);
}

TEST(StrainLimit, SingleTriangleKeepsItsMassWeightedCentre) {
  Triangles faces(1, 3);
  faces << 0, 1, 2;
  Points x(3, 3);
  x << 0, 0, 0, 3, 0, 0, 0, 1, 0;  // 3× stretched along x
  Eigen::VectorXd mass(3);
  mass << 1.0, 2.0, 5.0;
  const Vec3 centre_before = (mass.transpose() * x).transpose() / mass.sum();
  const StrainLimitReport report =
      limit_strain(x, faces, {Mat2::Identity()}, mass, {}, StrainLimitOptions{});
  EXPECT_TRUE(report.converged);
  const double stretch = (x.row(1) - x.row(0)).norm();
  EXPECT_GE(stretch, 0.9 - 1e-3);
  EXPECT_LE(stretch, 1.1 + 1e-3);
  EXPECT_GT((x.row(1) - x.row(0)).x(), 0.0);  // not flipped
  const Vec3 centre_after = (mass.transpose() * x).transpose() / mass.sum();
  EXPECT_NEAR((centre_after - centre_before).norm(), 0.0, 1e-12);
}
