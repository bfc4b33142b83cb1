#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <tuple>
#include <vector>

#include "coupling/rigid_patch.hpp"

using namespace dexcloth;
using namespace dexcloth::coupling;

namespace {

/// A flat 5×4 lattice of vertices with spacing 5 mm, centred at `c`, normal +z, mass 1 g each.
std::vector<PatchVertex> lattice(const Vec3& c) {
  std::vector<PatchVertex> out;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      out.push_back({c + Vec3(0.005 * i, 0.005 * j, 0), Vec3::Zero(), Vec3::UnitZ(), 1e-3});
  return out;
}

}  // namespace

TEST(RigidPatch, ClustersSplitByDistanceNormalAndOffset) {
  std::vector<PatchVertex> v = lattice(Vec3::Zero());
  const auto far = lattice(Vec3(0.2, 0, 0));  // 0.2 m away: beyond δw
  v.insert(v.end(), far.begin(), far.end());
  v.push_back({Vec3(0.005, 0.005, 0.0), Vec3::Zero(), Vec3(std::sin(0.5236), 0, std::cos(0.5236)),
               1e-3});  // 30° normal
  v.push_back(
      {Vec3(0.0, 0.0, 0.005), Vec3::Zero(), Vec3::UnitZ(), 1e-3});  // 5 mm above: offset > δd
  const auto clusters = cluster_vertices(v, ClusterParams{});
  ASSERT_EQ(clusters.size(), 4u);
  EXPECT_EQ(clusters[0].size(), 20u);
  EXPECT_EQ(clusters[1].size(), 20u);
  EXPECT_EQ(clusters[2], std::vector<int>{40});
  EXPECT_EQ(clusters[3], std::vector<int>{41});
}

TEST(RigidPatch, ClusteringIsTransitive) {
  // A line of vertices 30 mm apart: neighbours join, the ends (90 mm apart) join through them.
  std::vector<PatchVertex> v;
  for (int i = 0; i < 4; ++i)
    v.push_back({Vec3(0.03 * i, 0, 0), Vec3::Zero(), Vec3::UnitZ(), 1e-3});
  EXPECT_EQ(cluster_vertices(v, ClusterParams{}).size(), 1u);
  ClusterParams tight;
  tight.distance = 0.02;
  EXPECT_EQ(cluster_vertices(v, tight).size(), 4u);
}

TEST(RigidPatch, MinimumAreaRectangleOfARotatedRectangle) {
  const double angle = 0.4;
  const Vec2 u(std::cos(angle), std::sin(angle)), w(-u.y(), u.x());
  std::vector<Vec2> pts;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> a(-1.0, 1.0);
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) pts.push_back(Vec2(0.1, 0.2) + sx * 0.02 * u + sy * 0.01 * w);
  for (int k = 0; k < 50; ++k)
    pts.push_back(Vec2(0.1, 0.2) + 0.02 * a(rng) * u + 0.01 * a(rng) * w);
  const Rectangle2 r = min_area_rectangle(pts);
  EXPECT_NEAR(r.extent.x() * r.extent.y(), 0.04 * 0.02, 1e-15);
  EXPECT_NEAR(std::abs(r.axis.dot(u)) + std::abs(r.axis.dot(w)), 1.0,
              1e-12);  // aligned with a side
  EXPECT_NEAR((r.center - Vec2(0.1, 0.2)).norm(), 0.0, 1e-14);
}

TEST(RigidPatch, RotatingRigidClusterGivesItsExactVelocities) {
  // A tilted flat cluster moving rigidly: v_i = v0 + ω × (x_i − c).
  const Mat3 R = Eigen::AngleAxisd(0.3, Vec3(1, 2, 0.5).normalized()).toRotationMatrix();
  const Vec3 c(0.1, -0.2, 0.5), v0(0.3, -0.1, 0.2), omega(1.5, -0.7, 2.0);
  std::vector<PatchVertex> v;
  std::vector<int> cluster;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec3 x = c + R * Vec3(0.004 * i - 0.01, 0.004 * j - 0.004, 0.0);
      v.push_back({x, v0 + omega.cross(x - c), R.col(2), 1e-3 * (1 + (i + j) % 3)});
      cluster.push_back(static_cast<int>(v.size()) - 1);
    }
  const RigidPatch p = build_patch(v, cluster, 1e-3, 1e-3);
  double mass = 0.0;
  for (const auto& pv : v) mass += pv.mass;
  EXPECT_NEAR(p.mass, mass, 1e-18);
  EXPECT_NEAR((p.angular_velocity - omega).norm(), 0.0, 1e-10);
  // The box centre's velocity is the rigid velocity field at that point.
  EXPECT_NEAR((p.linear_velocity - (v0 + omega.cross(p.center - c))).norm(), 0.0, 1e-10);
  EXPECT_NEAR(std::abs(p.R.col(2).dot(R.col(2))), 1.0, 1e-12);  // plane normal
  EXPECT_GT(p.R.col(2).dot(R.col(2)), 0.0);                     // oriented like the vertices
  EXPECT_NEAR(p.size.x() * p.size.y(), 0.02 * 0.008, 1e-12);    // 20 mm × 8 mm rectangle
  EXPECT_DOUBLE_EQ(p.size.z(), 1e-3);
  EXPECT_NEAR((p.R.transpose() * p.R - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_GT(p.R.determinant(), 0.0);
}

TEST(RigidPatch, SingleVertexPatchHasMinimumSizeAndItsVelocity) {
  const std::vector<PatchVertex> v{{Vec3(0, 0, 1), Vec3(0.1, 0, 0), Vec3::UnitZ(), 2e-3}};
  const std::vector<int> cluster{0};
  const RigidPatch p = build_patch(v, cluster, 1e-3, 5e-3);
  EXPECT_EQ(p.size, Vec3(5e-3, 5e-3, 1e-3));
  EXPECT_EQ(p.linear_velocity, Vec3(0.1, 0, 0));
  EXPECT_EQ(p.angular_velocity, Vec3::Zero());
  EXPECT_EQ(p.center, Vec3(0, 0, 1));
}

namespace {

/// The patch of the 5×4 lattice at the origin, 10 mm thick (centre (0.01, 0.0075, 0), normal +z).
RigidPatch lattice_patch() {
  const std::vector<PatchVertex> v = lattice(Vec3::Zero());
  std::vector<int> all(v.size());
  std::iota(all.begin(), all.end(), 0);
  return build_patch(v, all, 0.010, 0.010);
}

/// Offsets of the patch's faces along its normal from the cloth plane z = 0 [m].
std::pair<double, double> faces(const RigidPatch& p) {
  const double c = p.center.z() * p.R(2, 2);
  return {c - 0.5 * p.size.z(), c + 0.5 * p.size.z()};
}

}  // namespace

TEST(RigidPatch, APatchBetweenTwoFingersIsCentredBetweenThemWhereverTheClothLies) {
  // Fingers 3 mm above and 4.5 mm below the cloth; most touches see the pad faces, a few the
  // fingers' rounded flanks a bit farther away.
  RigidPatch p = lattice_patch();
  ASSERT_NEAR(p.R.col(2).z(), 1.0, 1e-12);
  const Vec3 v0 = p.linear_velocity;
  std::vector<SurfaceTouch> touches;
  for (int k = 0; k < 5; ++k) touches.push_back({Vec3(0.002 * k, 0, 0.003), -Vec3::UnitZ()});
  touches.push_back({Vec3(0.02, 0, 0.0036), -Vec3(0.2, 0, 1).normalized()});
  for (int k = 0; k < 5; ++k) touches.push_back({Vec3(0.002 * k, 0.01, -0.0045), Vec3::UnitZ()});
  touches.push_back({Vec3(0.02, 0.01, -0.0051), Vec3(0.2, 0, 1).normalized()});
  centre_between_surfaces(p, touches, 0.0104);
  const auto [bottom, top] = faces(p);
  EXPECT_NEAR(0.5 * (top + bottom), -0.00075, 1e-12);  // midway between the pad faces
  EXPECT_NEAR(top - bottom, 0.0104, 1e-12);            // the thickness asked for
  EXPECT_NEAR(p.center.x(), 0.01, 1e-12);              // rectangle unchanged
  EXPECT_NEAR(p.size.x() * p.size.y(), 0.020 * 0.015, 1e-12);
  EXPECT_NEAR((p.linear_velocity - v0).norm(), 0.0, 1e-12);  // not rotating: same velocity
}

TEST(RigidPatch, APatchTouchedOnOneSideOrByFlanksOnlyStaysOnTheCloth) {
  // One finger 4 mm above; below, only a surface facing 60° away from the normal (a flank).
  RigidPatch p = lattice_patch();
  const Vec3 c0 = p.center;
  const std::vector<SurfaceTouch> touches{
      {Vec3(0.01, 0.0075, 0.004), -Vec3::UnitZ()},
      {Vec3(0.0, 0.0, -0.002), Vec3(std::sqrt(3.0), 0, 1).normalized()}};
  centre_between_surfaces(p, touches, 0.0104);
  EXPECT_NEAR((p.center - c0).norm(), 0.0, 1e-15);
  EXPECT_NEAR(p.size.z(), 0.010, 1e-15);
  // The same flank within 20° of the normal counts: the box turns to the bisector of the two
  // surfaces (16.7° apart) and sits midway between the two touch points along it.
  const Vec3 flank = Vec3(0.3, 0, 1).normalized();
  const std::vector<SurfaceTouch> both{touches[0], {Vec3(0.0, 0.0, -0.002), flank}};
  centre_between_surfaces(p, both, 0.0104);
  const Vec3 n = p.R.col(2);
  EXPECT_NEAR(n.dot(Vec3::UnitZ()), n.dot(flank), 1e-12);
  EXPECT_NEAR(n.y(), 0.0, 1e-12);
  EXPECT_NEAR((both[0].point - p.center).dot(n), -(both[1].point - p.center).dot(n), 1e-12);
  EXPECT_NEAR(p.size.z(), 0.0104, 1e-15);
  EXPECT_NEAR((p.R.transpose() * p.R - Mat3::Identity()).norm(), 0.0, 1e-12);
}

namespace {

/// The lattice's patch fitted to its vertices turned `degrees` about y.
RigidPatch tilted_patch(double degrees) {
  std::vector<PatchVertex> v = lattice(Vec3::Zero());
  const Mat3 tilt = Eigen::AngleAxisd(degrees * M_PI / 180.0, Vec3::UnitY()).toRotationMatrix();
  for (PatchVertex& pv : v) {
    pv.x = tilt * pv.x;
    pv.n = tilt * pv.n;
  }
  std::vector<int> all(v.size());
  std::iota(all.begin(), all.end(), 0);
  return build_patch(v, all, 0.010, 0.010);
}

/// Horizontal pads touching the cloth 3 mm above and 4 mm below `c`.
std::vector<SurfaceTouch> horizontal_pads(const Vec3& c) {
  std::vector<SurfaceTouch> touches;
  for (int k = 0; k < 3; ++k) {
    touches.push_back({c + Vec3(0.004 * k, 0, 0.003), -Vec3::UnitZ()});
    touches.push_back({c + Vec3(0.004 * k, 0.002, -0.004), Vec3::UnitZ()});
  }
  return touches;
}

}  // namespace

TEST(RigidPatch, APatchFittedToTiltedClothIsTurnedToTheFingersItIsSqueezedBetween) {
  // Cloth crumpled in a pinch: the vertices fit a plane tilted 15° about y, while the pads are
  // horizontal, 3 mm above and 4 mm below the centre. The box turns flat (a tilted box would
  // sink its corners into the pads) and keeps its centre's velocity.
  RigidPatch p = tilted_patch(15.0);
  ASSERT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), std::cos(15.0 * M_PI / 180.0), 1e-9);
  const Vec3 c0 = p.center, v0 = p.linear_velocity;
  centre_between_surfaces(p, horizontal_pads(c0), 0.0104);
  EXPECT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(p.center.z() - c0.z(), -0.0005, 1e-12);  // midway between z = +3 and −4 mm
  EXPECT_NEAR(p.center.x() - c0.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.size.z(), 0.0104, 1e-15);
  EXPECT_NEAR((p.linear_velocity - v0).norm(), 0.0, 1e-12);
}

TEST(RigidPatch, APatchFittedMoreThanTwentyDegreesOffTheFingersIsStillTurnedToThem) {
  // As above with the fitted plane 25° off the pads (cloth bent round a pad's edge joined the
  // cluster): no pad faces the fitted normal within 20°, so the faces are sought about the
  // touches' own median normal, and the box still turns flat between the pads at the thickness
  // asked for. A flank touch at 50° is outvoted.
  RigidPatch p = tilted_patch(25.0);
  ASSERT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), std::cos(25.0 * M_PI / 180.0), 1e-9);
  const Vec3 c0 = p.center;
  std::vector<SurfaceTouch> touches = horizontal_pads(c0);
  touches.push_back(
      {c0 + Vec3(0.012, 0, 0.002),
       Vec3(-(Eigen::AngleAxisd(50.0 * M_PI / 180.0, Vec3::UnitY()) * Vec3::UnitZ()))});
  centre_between_surfaces(p, touches, 0.0104);
  EXPECT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(p.center.z() - c0.z(), -0.0005, 1e-12);
  EXPECT_NEAR(p.size.z(), 0.0104, 1e-15);
  EXPECT_NEAR((p.R.transpose() * p.R - Mat3::Identity()).norm(), 0.0, 1e-12);
}

TEST(RigidPatch, APatchBetweenTwoFingersFacesThePadThatTouchesMostOnEachSide) {
  // Each finger's pad (bodies 1 above, 3 below: three touches each, horizontal, 3 mm above and
  // 4 mm below the centre) and two other links of each finger bent 15° away behind it (bodies
  // 2, 5 above and 4, 6 below: two touches each, 2 and 0.5 mm farther out). Most touches are the
  // links', so their medians would tilt the box 15° and shift it; the box faces the pads.
  RigidPatch p = tilted_patch(0.0);
  const Vec3 c0 = p.center;
  std::vector<SurfaceTouch> touches = horizontal_pads(c0);
  for (std::size_t k = 0; k < touches.size(); ++k)
    touches[k].body = touches[k].normal.z() < 0 ? 1 : 3;
  const Vec3 tilted_down = Eigen::AngleAxisd(15.0 * M_PI / 180.0, Vec3::UnitY()) * Vec3::UnitZ();
  for (int link : {2, 5, 4, 6})
    for (int k = 0; k < 2; ++k) {
      const bool above = link == 2 || link == 5;
      SurfaceTouch t{c0 + Vec3(-0.006 - 0.003 * k, 0.001 * link, above ? 0.005 : -0.0045),
                     above ? Vec3(-tilted_down) : tilted_down};
      t.body = link;
      touches.push_back(t);
    }
  centre_between_surfaces(p, touches, 0.0104);
  EXPECT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(p.center.z() - c0.z(), -0.0005, 1e-12);  // midway between the pads
  EXPECT_NEAR(p.size.z(), 0.0104, 1e-15);
}

/// Patch vertices at `points` (normal +z, 1 g, at rest).
std::vector<PatchVertex> vertices_at(std::initializer_list<Vec3> points) {
  std::vector<PatchVertex> v;
  for (const Vec3& x : points) v.push_back({x, Vec3::Zero(), Vec3::UnitZ(), 1e-3});
  return v;
}

TEST(RigidPatch, AFoldSqueezedBetweenTwoFingersIsOneStack) {
  // Clusters 0 and 1: the two layers of a fold, 5 mm apart, pressed by the thumb from below
  // (normal +z at z = −5 mm) and by the index from above (normal −z at z = +10 mm), one over the
  // other. Cluster 2: a layer pressed from below only, 60 mm away. Cluster 3: pressed from both
  // sides already. Cluster 4: touches nothing rigid.
  const std::vector<PatchVertex> v = vertices_at(
      {Vec3(0, 0, 0), Vec3(0.004, 0, 0), Vec3(0.001, 0.001, 0.005), Vec3(0.003, 0.004, 0.005),
       Vec3(0.06, 0, 0.005), Vec3(0, 0.03, 0), Vec3(0.1, 0, 0)});
  std::vector<std::vector<int>> clusters{{0, 1}, {2, 3}, {4}, {5}, {6}};
  std::vector<std::vector<SurfaceTouch>> touches(5);
  touches[0] = {{Vec3(0, 0, -0.005), Vec3::UnitZ()}, {Vec3(0.004, 0, -0.005), Vec3::UnitZ()}};
  touches[1] = {{Vec3(0.002, 0.003, 0.010), -Vec3::UnitZ()}};
  touches[2] = {{Vec3(0.06, 0, 0.010), -Vec3::UnitZ()}};
  touches[3] = {{Vec3(0, 0.03, -0.005), Vec3::UnitZ()}, {Vec3(0, 0.03, 0.005), -Vec3::UnitZ()}};
  const std::vector<std::vector<SurfaceTouch>> original = touches;
  const std::vector<int> layers = join_facing_clusters(clusters, touches, v, 0.023, 0.04, 0.0025);
  ASSERT_EQ(clusters.size(), 4u);
  ASSERT_EQ(touches.size(), 4u);
  EXPECT_EQ(touches[0].size(), 3u);  // the stack's touches: both fingers'
  EXPECT_EQ(touches[1].size(), 1u);
  EXPECT_EQ(clusters[0], (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(layers, (std::vector<int>{2, 1, 1, 1}));
  EXPECT_EQ(clusters[1], std::vector<int>{4});
  // Farther apart than max_gap (15 mm between the surfaces against 12 mm): not joined.
  std::vector<std::vector<int>> apart{{0, 1}, {2, 3}};
  std::vector<std::vector<SurfaceTouch>> two{original[0], original[1]};
  const std::vector<int> single = join_facing_clusters(apart, two, v, 0.012, 0.04, 0.0025);
  EXPECT_EQ(single, (std::vector<int>{1, 1}));
  // A layer split in two pieces under one finger, facing a layer under the other: one stack of
  // two layers, not three.
  const std::vector<PatchVertex> p =
      vertices_at({Vec3(0, 0, 0), Vec3(0.008, 0, 0), Vec3(0.001, 0, 0.005)});
  std::vector<std::vector<int>> pieces{{0}, {1}, {2}};
  std::vector<std::vector<SurfaceTouch>> pressed{{{Vec3(0, 0, -0.005), Vec3::UnitZ()}},
                                                 {{Vec3(0.008, 0, -0.005), Vec3::UnitZ()}},
                                                 {{Vec3(0.004, 0, 0.005), -Vec3::UnitZ()}}};
  EXPECT_EQ(join_facing_clusters(pieces, pressed, p, 0.023, 0.04, 0.0025), std::vector<int>{2});
  EXPECT_EQ(pieces[0], (std::vector<int>{0, 1, 2}));
  // Two layers pressed from the same side are not a stack.
  std::vector<std::vector<int>> same{{0}, {1}};
  std::vector<std::vector<SurfaceTouch>> below{{{Vec3(0, 0, -0.005), Vec3::UnitZ()}},
                                               {{Vec3(0, 0, 0.005), Vec3::UnitZ()}}};
  EXPECT_EQ(join_facing_clusters(same, below, v, 0.023, 0.04, 0.0025), (std::vector<int>{1, 1}));
}

TEST(RigidPatch, ALayerSteppedBetweenTwoFingersIsOneStackOfOneLayer) {
  // One layer crumpled into a step: its part at z = 0 (x ≤ 9 mm) touches the index above, its
  // part 6 mm lower (x ≥ 18 mm) the thumb below; side by side, neither over the other. Joined,
  // so both fingers squeeze one box, but one layer thick: they press the step flat.
  const std::vector<PatchVertex> v =
      vertices_at({Vec3(0, 0, 0), Vec3(0.009, 0, 0), Vec3(0, 0.009, 0), Vec3(0.009, 0.009, 0),
                   Vec3(0.018, 0, -0.006), Vec3(0.027, 0, -0.006), Vec3(0.018, 0.009, -0.006)});
  std::vector<std::vector<int>> clusters{{0, 1, 2, 3}, {4, 5, 6}};
  std::vector<std::vector<SurfaceTouch>> touches{{{Vec3(0.004, 0.004, 0.005), -Vec3::UnitZ()}},
                                                 {{Vec3(0.022, 0.004, -0.011), Vec3::UnitZ()}}};
  EXPECT_EQ(join_facing_clusters(clusters, touches, v, 0.023, 0.04, 0.0025), std::vector<int>{1});
  EXPECT_EQ(clusters[0], (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
  // The same parts with the lower one slid under the upper one (a fold): two layers.
  std::vector<PatchVertex> folded = v;
  for (int k = 4; k < 7; ++k) folded[static_cast<std::size_t>(k)].x.x() -= 0.018;
  std::vector<std::vector<int>> fold{{0, 1, 2, 3}, {4, 5, 6}};
  std::vector<std::vector<SurfaceTouch>> pressed{{{Vec3(0.004, 0.004, 0.005), -Vec3::UnitZ()}},
                                                 {{Vec3(0.004, 0.004, -0.011), Vec3::UnitZ()}}};
  EXPECT_EQ(join_facing_clusters(fold, pressed, folded, 0.023, 0.04, 0.0025), std::vector<int>{2});
}

TEST(RigidPatch, APatchOfTwoVerticesPressedFromOppositeSidesHasAFiniteFrame) {
  // The two layers of a fold, one vertex each, with opposite normals.
  std::vector<PatchVertex> v(2);
  v[0] = {Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3::UnitZ(), 1e-3};
  v[1] = {Vec3(0.001, 0, 0.005), Vec3(0.01, 0, 0), -Vec3::UnitZ(), 1e-3};
  const std::vector<int> both{0, 1};
  const RigidPatch p = build_patch(v, both, 0.010, 0.010);
  EXPECT_TRUE(p.R.allFinite());
  EXPECT_TRUE(p.center.allFinite());
  EXPECT_TRUE(p.linear_velocity.allFinite());
  EXPECT_NEAR((p.R.transpose() * p.R - Mat3::Identity()).norm(), 0.0, 1e-12);
}

TEST(RigidPatch, VerticesAlongALineTakeTheirNormalAboutIt) {
  // Four vertices along x (a row along a finger's edge) with normals tilted 10° about x from +z:
  // any plane through the line fits them; the patch's must hold their mean normal.
  const Vec3 n(0.0, -std::sin(10.0 * M_PI / 180.0), std::cos(10.0 * M_PI / 180.0));
  std::vector<PatchVertex> v;
  for (int k = 0; k < 4; ++k) v.push_back({Vec3(0.005 * k, 0.0, 0.0), Vec3::Zero(), n, 1e-4});
  const std::vector<int> all{0, 1, 2, 3};
  const RigidPatch p = build_patch(v, all, 0.010, 0.010);
  EXPECT_NEAR(p.R.col(2).dot(n), 1.0, 1e-9);
  EXPECT_NEAR(std::abs(p.R.col(0).dot(Vec3::UnitX())), 1.0, 1e-9);  // the long side along x
  EXPECT_NEAR(p.size.x(), 0.015, 1e-12);
}

namespace {

/// A rounded fingertip's touch at `c` + `offset`, its surface normal (toward the cloth) turned
/// `degrees` about y from straight down.
SurfaceTouch fingertip(const Vec3& c, const Vec3& offset, double degrees) {
  return {c + offset,
          Vec3(-(Eigen::AngleAxisd(degrees * M_PI / 180.0, Vec3::UnitY()) * Vec3::UnitZ()))};
}

/// The table's touches 2 mm below `c` (a support: no controller drives it).
std::vector<SurfaceTouch> table_below(const Vec3& c) {
  std::vector<SurfaceTouch> touches;
  for (int k = 0; k < 3; ++k)
    touches.push_back({c + Vec3(0.004 * k, 0.0, -0.002), Vec3::UnitZ(), true});
  return touches;
}

}  // namespace

TEST(RigidPatch, AClothPressedOntoATableByAFingerIsNotCentredBetweenThemAsBetweenTwoFingers) {
  // A pad facing the table 3 mm above the cloth, which lies 2 mm up: as two fingers these would
  // make a 10.4 mm box centred between them, holding the pad two thicknesses over the table.
  RigidPatch p = lattice_patch();
  const Vec3 c0 = p.center;
  std::vector<SurfaceTouch> touches = table_below(c0);
  touches.push_back({c0 + Vec3(0.004, 0.0, 0.003), -Vec3::UnitZ()});
  EXPECT_FALSE(centre_between_surfaces(p, touches, 0.0104));
  EXPECT_NEAR((p.center - c0).norm(), 0.0, 1e-15);
  // Laid on the table instead: from its surface (2 mm below the cloth) up 5.2 mm.
  ASSERT_TRUE(lay_on_support(p, touches, 0.0052));
  const auto [bottom, top] = faces(p);
  EXPECT_NEAR(bottom, c0.z() - 0.002, 1e-12);
  EXPECT_NEAR(top, c0.z() + 0.0032, 1e-12);
  EXPECT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);
  // Two driven fingers still centre it between them, the table's touches aside.
  RigidPatch q = lattice_patch();
  touches.push_back({c0 + Vec3(0.004, 0.002, -0.0045), Vec3::UnitZ()});
  ASSERT_TRUE(centre_between_surfaces(q, touches, 0.0104));
  const auto [q_bottom, q_top] = faces(q);
  EXPECT_NEAR(0.5 * (q_top + q_bottom), c0.z() - 0.00075, 1e-12);
}

TEST(RigidPatch, AClothThatAThumbTipPressesOntoATableLiesFlatOnTheTable) {
  // The cloth's fitted plane tilted 35° (bent round the thumb's rounded tip, whose surface
  // normals are 50° from straight down): the box turns to the table, not to the cloth or the
  // thumb, and lies on it. Fitted and centred on the cloth, a tilted box sank half into the
  // table and the thumb pushed it aside.
  RigidPatch p = tilted_patch(35.0);
  const Vec3 c0 = p.center, v0 = p.linear_velocity;
  std::vector<SurfaceTouch> touches = table_below(c0);
  touches.push_back(fingertip(c0, Vec3(0.002, 0, 0.003), 50.0));
  touches.push_back(fingertip(c0, Vec3(0.006, 0, 0.004), 45.0));
  ASSERT_FALSE(centre_between_surfaces(p, touches, 0.0104));
  ASSERT_TRUE(lay_on_support(p, touches, 0.0052));
  EXPECT_NEAR(p.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR((p.R.transpose() * p.R - Mat3::Identity()).norm(), 0.0, 1e-12);
  const auto [bottom, top] = faces(p);
  EXPECT_NEAR(bottom, c0.z() - 0.002, 1e-12);
  EXPECT_NEAR(top - bottom, 0.0052, 1e-12);
  EXPECT_NEAR((p.linear_velocity - v0).norm(), 0.0, 1e-12);  // not rotating: same velocity
}

TEST(RigidPatch, AFingerBesideTheClothOrATableAloneDoesNotLayItOnTheTable) {
  RigidPatch p = lattice_patch();
  const Vec3 c0 = p.center;
  const std::vector<SurfaceTouch> table = table_below(c0);
  // A finger's side, its normal 80° from straight down: it pushes the cloth along the table,
  // not onto it.
  std::vector<SurfaceTouch> side = table;
  side.push_back(fingertip(c0, Vec3(-0.003, 0, 0.001), 80.0));
  EXPECT_FALSE(lay_on_support(p, side, 0.0052));
  // Only the table, or a finger only (no support).
  EXPECT_FALSE(lay_on_support(p, table, 0.0052));
  const std::vector<SurfaceTouch> finger{{c0 + Vec3(0, 0, 0.003), -Vec3::UnitZ()}};
  EXPECT_FALSE(lay_on_support(p, finger, 0.0052));
  EXPECT_NEAR((p.center - c0).norm(), 0.0, 1e-15);
  EXPECT_NEAR(p.size.z(), 0.010, 1e-15);
  // The same finger at 60° does press it.
  std::vector<SurfaceTouch> pressing = table;
  pressing.push_back(fingertip(c0, Vec3(-0.003, 0, 0.002), 60.0));
  EXPECT_TRUE(lay_on_support(p, pressing, 0.0052));
}

TEST(RigidPatch, ABoxUnderAFastBodyReachesUpToWhereTheBodyWillBe) {
  // Speculative touches (SurfaceTouch::ahead) of a body predicted 9 mm above the cloth, which
  // lies 2 mm above the table: the box lies on the table and reaches up to them, so DART stops
  // the body there; a touch ahead nearer than the box's own height leaves it as it is.
  RigidPatch p = lattice_patch();
  const Vec3 c0 = p.center;
  std::vector<SurfaceTouch> touches = table_below(c0);
  for (int k = 0; k < 3; ++k)
    touches.push_back({c0 + Vec3(0.004 * k, 0.001, 0.009), -Vec3::UnitZ(), false, true});
  ASSERT_TRUE(lay_on_support(p, touches, 0.0052));
  auto [bottom, top] = faces(p);
  EXPECT_NEAR(bottom, c0.z() - 0.002, 1e-12);
  EXPECT_NEAR(top, c0.z() + 0.009, 1e-12);
  RigidPatch near = lattice_patch();
  for (int k = 3; k < 6; ++k) touches[static_cast<std::size_t>(k)].point.z() = c0.z() + 0.001;
  ASSERT_TRUE(lay_on_support(near, touches, 0.0052));
  std::tie(bottom, top) = faces(near);
  EXPECT_NEAR(top - bottom, 0.0052, 1e-12);
  // The same touches not ahead (a body already there) take the box's own height.
  RigidPatch now = lattice_patch();
  for (int k = 3; k < 6; ++k) {
    touches[static_cast<std::size_t>(k)].point.z() = c0.z() + 0.009;
    touches[static_cast<std::size_t>(k)].ahead = false;
  }
  ASSERT_TRUE(lay_on_support(now, touches, 0.0052));
  std::tie(bottom, top) = faces(now);
  EXPECT_NEAR(top - bottom, 0.0052, 1e-12);
}

TEST(RigidPatch, ABoxBetweenTwoFastFingersFillsTheGapBetweenWhereTheyWillBe) {
  // Fingers predicted 8 mm above and 7 mm below the cloth: the box fills the 15 mm between them,
  // centred; predicted closer than the pinch's thickness, the box keeps that thickness.
  RigidPatch p = lattice_patch();
  std::vector<SurfaceTouch> touches;
  for (int k = 0; k < 3; ++k) {
    touches.push_back({Vec3(0.004 * k, 0, 0.008), -Vec3::UnitZ(), false, true});
    touches.push_back({Vec3(0.004 * k, 0.01, -0.007), Vec3::UnitZ(), false, true});
  }
  ASSERT_TRUE(centre_between_surfaces(p, touches, 0.0104));
  auto [bottom, top] = faces(p);
  EXPECT_NEAR(bottom, -0.007, 1e-12);
  EXPECT_NEAR(top, 0.008, 1e-12);
  RigidPatch q = lattice_patch();
  for (SurfaceTouch& t : touches) t.point.z() *= 0.5;
  ASSERT_TRUE(centre_between_surfaces(q, touches, 0.0104));
  std::tie(bottom, top) = faces(q);
  EXPECT_NEAR(top - bottom, 0.0104, 1e-12);
  EXPECT_NEAR(0.5 * (top + bottom), 0.00025, 1e-12);
  // Fingers already there (not ahead) 15 mm apart, and a fast body coming at the cloth's side:
  // the box keeps the pinch's thickness, midway.
  RigidPatch r = lattice_patch();
  for (SurfaceTouch& t : touches) {
    t.point.z() *= 2.0;
    t.ahead = false;
  }
  touches.push_back({Vec3(0.025, 0.005, 0.0), -Vec3::UnitX(), false, true});
  ASSERT_TRUE(centre_between_surfaces(r, touches, 0.0104));
  std::tie(bottom, top) = faces(r);
  EXPECT_NEAR(top - bottom, 0.0104, 1e-12);
  EXPECT_NEAR(0.5 * (top + bottom), 0.0005, 1e-12);
}
