#include <gtest/gtest.h>

#include "cloth/collision/impact_zones.hpp"
#include "cloth/collision/intersection.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

constexpr double kHalf = 0.3;   // box half-width [m]
constexpr double kTop = 0.005;  // box top [m]; bottom at −kTop

// A 1 m sheet 5 cm above a thin 60 cm box, dropping 10 cm in one step (5 m/s over h = 20 ms).
struct DropScene {
  CollisionMesh sheet = make_sheet(24, 24, 1.0, 1.0, Vec3(-0.5, -0.5, 0.05), 1e-3);
  CollisionMesh box = make_box(Vec3(-kHalf, -kHalf, -kTop), Vec3(kHalf, kHalf, kTop));
  DropScene() { sheet.x1.col(2).array() -= 0.1; }
  std::vector<CollisionMesh*> meshes() { return {&sheet, &box}; }
  int intersections() const { return count_intersections({&sheet, &box}, true); }
};

}  // namespace

TEST(ImpactZones, FastSheetStopsOnThinBoxWithoutIntersections) {
  DropScene s;
  // Unresolved, the sheet tunnels: it ends entirely below the box, touching nothing.
  ASSERT_EQ(s.intersections(), 0);
  ASSERT_LT(s.sheet.x1.col(2).maxCoeff(), -kTop);
  ImpactZoneSolver solver;
  const ImpactZoneReport report = solver.resolve(s.meshes(), ImpactZoneOptions{});
  EXPECT_TRUE(report.converged);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  EXPECT_GT(report.impacts, 0);
  EXPECT_EQ(s.intersections(), 0);
  // Not through: every vertex above the box's top face stayed above it.
  int over = 0;
  for (int v = 0; v < s.sheet.x1.rows(); ++v) {
    if (std::abs(s.sheet.x0(v, 0)) < kHalf && std::abs(s.sheet.x0(v, 1)) < kHalf) {
      ++over;
      EXPECT_GE(s.sheet.x1(v, 2), kTop) << v;
    }
  }
  EXPECT_GT(over, 100);
  // Far from the box the sheet keeps its motion.
  EXPECT_DOUBLE_EQ(s.sheet.x1(0, 2), -0.05);
}

TEST(ImpactZones, SheetsWithCrossingTrajectoriesEndIntersectionFree) {
  // Sheet a falls from +5 cm to −5 cm, sheet b rises from −5 cm to +5 cm, offset sideways.
  CollisionMesh a = make_sheet(12, 12, 0.6, 0.6, Vec3(0, 0, 0.05), 1e-3);
  CollisionMesh b = make_sheet(10, 10, 0.5, 0.5, Vec3(0.033, 0.047, -0.05), 2e-3);
  a.x1.col(2).array() -= 0.1;
  b.x1.col(2).array() += 0.1;
  const int centre_a = 6 * 13 + 6, centre_b = 5 * 11 + 5;
  ASSERT_LT(a.x1(centre_a, 2), b.x1(centre_b, 2));  // unresolved, they pass through each other
  ImpactZoneSolver solver;
  const ImpactZoneReport report = solver.resolve({&a, &b}, ImpactZoneOptions{});
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(count_intersections({&a, &b}, true), 0);
  EXPECT_EQ(count_intersections({&a, &b}, false), 0);
  // They met rather than passed: a is still above b where they overlap.
  EXPECT_GT(a.x1(centre_a, 2), b.x1(centre_b, 2));
}

TEST(ImpactZones, FrozenVerticesAreUnchangedBitForBit) {
  DropScene s;
  // Corners move with the sheet; the centre vertex is held where it is, above the box.
  const int n = 25;
  const int centre = 12 * n + 12;
  s.sheet.x1.row(centre) = s.sheet.x0.row(centre);
  for (const int v : {0, n - 1, n * (n - 1), n * n - 1, centre})
    s.sheet.frozen[static_cast<std::size_t>(v)] = 1;
  const Points before = s.sheet.x1;
  const Points box_before = s.box.x1;
  ImpactZoneSolver solver;
  const ImpactZoneReport report = solver.resolve(s.meshes(), ImpactZoneOptions{});
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(s.intersections(), 0);
  for (int v = 0; v < s.sheet.x1.rows(); ++v) {
    if (s.sheet.frozen[static_cast<std::size_t>(v)] == 0) continue;
    for (int d = 0; d < 3; ++d) EXPECT_EQ(s.sheet.x1(v, d), before(v, d));
  }
  EXPECT_EQ(s.box.x1, box_before);
}

TEST(ImpactZones, ImpossibleConstraintIsReportedNotHidden) {
  // A frozen vertex driven through the box: no response can fix it, the solver must say so.
  DropScene s;
  const int n = 25;
  const int centre = 12 * n + 12;
  s.sheet.frozen[static_cast<std::size_t>(centre)] = 1;
  ImpactZoneSolver solver;
  ImpactZoneOptions options;
  options.max_iterations = 12;
  const ImpactZoneReport report = solver.resolve(s.meshes(), options);
  EXPECT_FALSE(report.converged);
  EXPECT_FALSE(report.warnings.empty());
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("fixed vertices"), std::string::npos)
      << report.warnings.front();
  // Every other vertex over the box stays above it.
  for (int v = 0; v < s.sheet.x1.rows(); ++v) {
    if (v != centre && std::abs(s.sheet.x0(v, 0)) < kHalf && std::abs(s.sheet.x0(v, 1)) < kHalf) {
      EXPECT_GE(s.sheet.x1(v, 2), kTop) << v;
    }
  }
}

TEST(ImpactZones, AZoneWhoseProjectionFailsMovesRigidlyWithTheMotionItCameWith) {
  // One round, one Gauss–Seidel sweep: the projection of the sheet's zone on the box does not
  // converge, and the fallback's rigid motion must be the zone's incoming motion (a uniform
  // drop of 10 cm), not the half-projected one. An infeasible zone's projection diverged to
  // metres and then NaN, and the rigid fallback spread that over 3290 vertices of a pinched
  // sheet.
  DropScene s;
  const Points incoming = s.sheet.x1;
  ImpactZoneSolver solver;
  ImpactZoneOptions options;
  options.max_iterations = 1;
  options.max_sweeps = 1;
  const ImpactZoneReport report = solver.resolve(s.meshes(), options);
  EXPECT_GT(report.rigid_zones, 0);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("moved rigidly"), std::string::npos);
  EXPECT_LT((s.sheet.x1 - incoming).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(ImpactZones, AVertexHeldByFrictionIsLetGoWhenAnObstacleRunsIntoIt) {
  // The same vertex held by static friction rather than by a handle: non-penetration comes
  // first, so it is released and the sheet ends free of the box.
  DropScene s;
  const int n = 25;
  const int centre = 12 * n + 12;
  s.sheet.frozen[static_cast<std::size_t>(centre)] = kHeldByFriction;
  ImpactZoneSolver solver;
  ImpactZoneOptions options;
  options.max_iterations = 12;
  const ImpactZoneReport report = solver.resolve(s.meshes(), options);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.released, 1);
  EXPECT_EQ(s.sheet.frozen[static_cast<std::size_t>(centre)], 0);
  EXPECT_EQ(s.intersections(), 0);
  EXPECT_GT(s.sheet.x1(centre, 2), kTop);  // stopped on the box top, not pushed through
}

TEST(ImpactZones, AHeldVertexRunningIntoAZoneKeptAtItsStartIsLetGoWithIt) {
  // Sheet a falls 10 cm through the still sheet b below it, its centre vertex held by static
  // friction (moving with a body). With only two rounds and 1000 projection sweeps (too few
  // for this zone), the zone is kept at its start-of-step positions in the second; the held
  // vertex, which would go on through b, is let go and kept at its start too, so the sheets end
  // free of each other.
  CollisionMesh a = make_sheet(12, 12, 0.6, 0.6, Vec3(0, 0, 0.05), 1e-3);
  CollisionMesh b = make_sheet(10, 10, 0.5, 0.5, Vec3(0.033, 0.047, 0.0), 2e-3);
  a.x1.col(2).array() -= 0.1;
  const int centre = 6 * 13 + 6;
  a.frozen[static_cast<std::size_t>(centre)] = kHeldByFriction;
  ImpactZoneSolver solver;
  ImpactZoneOptions options;
  options.max_iterations = 2;
  options.max_sweeps = 1000;
  const ImpactZoneReport report = solver.resolve({&a, &b}, options);
  bool kept = false;
  for (const std::string& w : report.warnings)
    kept = kept || w.find("kept at its start") != std::string::npos;
  EXPECT_TRUE(kept);
  EXPECT_GE(report.released, 1);
  EXPECT_EQ(a.frozen[static_cast<std::size_t>(centre)], 0);
  EXPECT_EQ(count_intersections({&a, &b}, true), 0);
}

namespace {

// A cloth triangle whose edge 0–1 crosses the top edge of `box_with_top_edge_on_y` (along y at
// x = z = 0) diagonally, `dip` [m] inside it there (negative: outside), its ends 5 mm out, over
// the top and beside the side; its third corner is far out.
CollisionMesh edge_across_box_edge(double dip) {
  const double a = 0.005;
  CollisionMesh cloth;
  cloth.x0.resize(3, 3);
  cloth.x0 << -dip - a, 0.0, -dip + a, -dip + a, 0.0, -dip - a, 0.005, 0.02, 0.02;
  cloth.x1 = cloth.x0;
  cloth.faces.resize(1, 3);
  cloth.faces << 0, 1, 2;
  cloth.mass = Eigen::VectorXd::Constant(3, 1e-4);
  cloth.frozen.assign(3, 0);
  return cloth;
}

CollisionMesh box_with_top_edge_on_y() {
  return make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.0, 0.05, 0.0));
}

}  // namespace

TEST(ImpactZones, AClothEdgeJustInsideABodysEdgeIsNotCarriedAlongAsTheBodyLeaves) {
  // The cloth edge dips 7 µm into the box; the box moves 2 mm away from it (down and to −x) and
  // the cloth stays. The edges' common perpendicular starts on the box's inner side; oriented by
  // that start, the impact held the cloth edge inside the box's edge and dragged it along (1.4
  // mm). Just inside, the side is the body's: the cloth leaves and stays where it is.
  CollisionMesh box = box_with_top_edge_on_y();
  const Vec3 away = Vec3(-1.0, 0.0, -1.0).normalized() * 0.002;
  box.x1 = box.x0.rowwise() + away.transpose();
  CollisionMesh cloth = edge_across_box_edge(7e-6);
  ImpactZoneSolver solver;
  const ImpactZoneReport report = solver.resolve({&cloth, &box}, ImpactZoneOptions{});
  EXPECT_TRUE(report.converged);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_EQ(cloth.x1, cloth.x0);
}

TEST(ImpactZones, AClothEdgeJustOutsideABodysEdgeIsStillPushedAlongAsTheBodyComes) {
  // The same edge 7 µm outside the box's edge, the box coming 2 mm toward it: it is pushed out
  // ahead of the box's edge, at least the box's motion along their common perpendicular.
  CollisionMesh box = box_with_top_edge_on_y();
  const Vec3 toward = Vec3(1.0, 0.0, 1.0).normalized() * 0.002;
  box.x1 = box.x0.rowwise() + toward.transpose();
  CollisionMesh cloth = edge_across_box_edge(-7e-6);
  ImpactZoneSolver solver;
  const ImpactZoneReport report = solver.resolve({&cloth, &box}, ImpactZoneOptions{});
  EXPECT_TRUE(report.converged);
  const Vec3 mid = 0.5 * (cloth.x1.row(0) + cloth.x1.row(1)).transpose();
  EXPECT_GT(mid.dot(toward.normalized()), 0.002);
}

TEST(ImpactZones, ClothSkimmingAnObstaclesFaceIsStoppedAlongItsNormalNotPushedSideways) {
  // A 2 cm patch 10 µm over the top of a box, sliding 1 cm along x and 12 µm down in the step:
  // it would end 2 µm inside. Met within the CCD tolerance 8 mm along, the start gap (taken
  // with the hit's weights) lies nearly along x, and the patch was pushed back 2.6 mm; the
  // impact's normal is now the face's, so it is lifted, not pushed back along its slide. In
  // the middle of the top its edges also cross the top's diagonal, no edge of the box's
  // surface: those edge–edge impacts take the plane's normal too (they had pushed it 1.5 mm).
  for (const Vec3& corner : {Vec3(0.1, -0.2, 0.0), Vec3(-0.01, -0.01, 0.0)}) {
    CollisionMesh box = make_box(Vec3(-kHalf, -kHalf, -kTop), Vec3(kHalf, kHalf, kTop));
    CollisionMesh patch = make_sheet(1, 1, 0.02, 0.02, corner + Vec3(0.0, 0.0, kTop + 1e-5), 1e-3);
    patch.x1 = patch.x0.rowwise() + Eigen::RowVector3d(0.01, 0.0, -1.2e-5);
    const Points slid = patch.x1;
    ImpactZoneSolver solver;
    const ImpactZoneReport report = solver.resolve({&patch, &box}, ImpactZoneOptions{});
    EXPECT_TRUE(report.converged);
    EXPECT_GT(report.impacts, 0);
    for (int v = 0; v < patch.x1.rows(); ++v) {
      EXPECT_NEAR(patch.x1(v, 0), slid(v, 0), 1e-12) << corner.x() << " " << v;
      EXPECT_NEAR(patch.x1(v, 1), slid(v, 1), 1e-12) << corner.x() << " " << v;
      EXPECT_GT(patch.x1(v, 2), kTop) << corner.x() << " " << v;
    }
  }
}
