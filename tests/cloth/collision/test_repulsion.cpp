#include <gtest/gtest.h>

#include "cloth/collision/cloth_contacts.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

constexpr double kThickness = 5e-3;
constexpr double kDt = 5e-3;

// A static obstacle triangle in z = 0 and a small cloth triangle above it at height `height`,
// moving with velocity `velocity` over the step.
struct Scene {
  CollisionMesh obstacle;
  CollisionMesh cloth;
  std::vector<CollisionMesh*> meshes() { return {&cloth, &obstacle}; }
};

Scene make_scene(double height, const Vec3& velocity) {
  Scene s;
  s.obstacle.obstacle = true;
  s.obstacle.x0.resize(3, 3);
  s.obstacle.x0 << -1, -1, 0, 2, -1, 0, -1, 2, 0;
  s.obstacle.x1 = s.obstacle.x0;
  s.obstacle.faces.resize(1, 3);
  s.obstacle.faces << 0, 1, 2;
  s.cloth = make_sheet(1, 1, 0.02, 0.02, Vec3(0.1, 0.1, height), 1e-3);
  s.cloth.faces.conservativeResize(1, 3);  // one triangle, vertices 0, 1, 3 (vertex 2 unused)
  for (int v = 0; v < 4; ++v) s.cloth.x1.row(v) = s.cloth.x0.row(v) + kDt * velocity.transpose();
  return s;
}

RepulsionOptions options(bool friction) {
  RepulsionOptions o;
  o.thickness = kThickness;
  o.dt = kDt;
  o.friction = friction;
  return o;
}

}  // namespace

TEST(Repulsion, ApproachInsideThicknessEndsAtLeastNinetyPercentApart) {
  Scene s = make_scene(0.95 * kThickness, Vec3(0, 0, -1.0));  // 1 m/s toward the face
  ClothContacts data;
  detect_cloth_contacts(s.meshes(), options(false), data);
  for (const int v : {0, 1, 3}) EXPECT_GE(s.cloth.x1(v, 2), 0.9 * kThickness) << v;
  // Without repulsion the vertices would have ended at 0.95·5 mm − 5 mm < 0.
  const ContactVertexSets sets = contact_vertex_sets(data.contacts, 0);
  EXPECT_EQ(sets.obstacle, (std::vector<int>{0, 1, 3}));
  EXPECT_TRUE(sets.cloth.empty());
  for (const VertexContact& c : data.contacts) {
    EXPECT_TRUE(c.with_obstacle);
    EXPECT_NEAR(c.normal.z(), 1.0, 1e-12);
    EXPECT_NEAR(c.distance, 0.95 * kThickness, 1e-12);
    EXPECT_GT(c.normal_impulse, 0.0);
    // Impulse stops 1 m/s of a 1 g vertex and adds at most 0.1·d/h.
    EXPECT_GE(c.normal_impulse, 1e-3 * 1.0);
    EXPECT_LE(c.normal_impulse, 1e-3 * (1.0 + 0.1 * 0.05 * kThickness / kDt) + 1e-12);
  }
}

TEST(Repulsion, DeepOverlapIsPushedBackTowardThickness) {
  Scene s = make_scene(0.5 * kThickness, Vec3(0, 0, -0.2));
  ClothContacts data;
  detect_cloth_contacts(s.meshes(), options(false), data);
  for (const int v : {0, 1, 3}) {
    // Approach stopped and the gap grows by 0.1·d per step (Bridson's cap on the spring).
    EXPECT_NEAR(s.cloth.x1(v, 2), 0.5 * kThickness + 0.1 * 0.5 * kThickness, 1e-12);
  }
}

TEST(Repulsion, AnObstaclePairBeyondTheThicknessClosesToItAndNoFurther) {
  // 8 mm over the face at 2 m/s: the step would take the vertices 2 mm into it. Searched to
  // 10 mm from the obstacle, they stop at the 5 mm thickness (impulse 1 g · (2 − 0.6) m/s).
  Scene s = make_scene(1.6 * kThickness, Vec3(0, 0, -2.0));
  s.obstacle.beyond_thickness = true;
  CollisionCandidates candidates;
  std::vector<Proximity> found;
  std::vector<std::vector<Proximity>> scratch;
  const std::vector<CollisionMesh*> meshes = s.meshes();
  const std::vector<const CollisionMesh*> view(meshes.begin(), meshes.end());
  find_proximities(view, kThickness, 2.0 * kThickness, candidates, found, scratch);
  ASSERT_EQ(found.size(), 3u);
  std::vector<VertexContact> contacts;
  std::vector<double> impulses;
  apply_repulsion(meshes, found, options(false), contacts, impulses);
  for (const int v : {0, 1, 3}) EXPECT_NEAR(s.cloth.x1(v, 2), kThickness, 1e-12) << v;
  ASSERT_EQ(contacts.size(), 3u);
  for (const VertexContact& c : contacts) {
    EXPECT_TRUE(c.with_obstacle);
    EXPECT_NEAR(c.distance, 1.6 * kThickness, 1e-12);
    EXPECT_NEAR(c.normal_impulse, 1e-3 * (2.0 - 0.6 * kThickness / kDt), 1e-12);
  }
  // At 0.5 m/s they end 2.5 mm lower, 5.5 mm over the face: left alone, and no contact.
  s = make_scene(1.6 * kThickness, Vec3(0, 0, -0.5));
  s.obstacle.beyond_thickness = true;
  const Points before = s.cloth.x1;
  find_proximities(view, kThickness, 2.0 * kThickness, candidates, found, scratch);
  ASSERT_EQ(found.size(), 3u);
  apply_repulsion(meshes, found, options(false), contacts, impulses);
  EXPECT_EQ(s.cloth.x1, before);
  EXPECT_TRUE(contacts.empty());
}

TEST(Repulsion, SeparatingPairIsLeftAlone) {
  Scene s = make_scene(0.5 * kThickness, Vec3(0, 0, 1.0));
  const Points before = s.cloth.x1;
  ClothContacts data;
  detect_cloth_contacts(s.meshes(), options(true), data);
  EXPECT_EQ(s.cloth.x1, before);
  for (const VertexContact& c : data.contacts) EXPECT_EQ(c.normal_impulse, 0.0);
}

TEST(Repulsion, FrictionBoundedByMuTimesNormalAndNeverReverses) {
  for (const double slide : {0.2, 3.0}) {  // stuck within one step, and sliding
    Scene s = make_scene(0.9 * kThickness, Vec3(slide, 0, -1.0));
    s.cloth.friction = 0.4;
    s.obstacle.friction = 0.9;  // pair μ = √(0.4·0.9) = 0.6
    ClothContacts data;
    detect_cloth_contacts(s.meshes(), options(true), data);
    ASSERT_EQ(data.contacts.size(), 3u);
    for (const VertexContact& c : data.contacts) {
      EXPECT_GT(c.friction_impulse, 0.0);
      EXPECT_LE(c.friction_impulse, 0.6 * c.normal_impulse + 1e-15);
      const double vx = (s.cloth.x1(c.vertex, 0) - s.cloth.x0(c.vertex, 0)) / kDt;
      EXPECT_GE(vx, 0.0) << "friction reversed the tangential velocity";
      EXPECT_LE(vx, slide);
      // Kinematic baseline: v_T ← max(|v_T| − μ·Δv_N, 0), Δv_N = impulse / m.
      const double dvn = c.normal_impulse / 1e-3;
      EXPECT_NEAR(vx, std::max(slide - 0.6 * dvn, 0.0), 1e-9);
    }
  }
}

TEST(Repulsion, FrozenVerticesAndObstaclesNeverMove) {
  Scene s = make_scene(0.5 * kThickness, Vec3(0.3, 0, -1.0));
  s.cloth.frozen[1] = 1;
  const Points frozen_before = s.cloth.x1;
  const Points obstacle_before = s.obstacle.x1;
  ClothContacts data;
  detect_cloth_contacts(s.meshes(), options(true), data);
  EXPECT_EQ(s.cloth.x1.row(1), frozen_before.row(1));
  EXPECT_EQ(s.obstacle.x1, obstacle_before);
  EXPECT_GE(s.cloth.x1(0, 2), s.cloth.x0(0, 2));  // the free vertices did stop
  // The frozen vertex is still reported in Vr for the coupling.
  const ContactVertexSets sets = contact_vertex_sets(data.contacts, 0);
  EXPECT_TRUE(std::find(sets.obstacle.begin(), sets.obstacle.end(), 1) != sets.obstacle.end());
}

TEST(Repulsion, ClothClothContactsGoToVcOnBothSides) {
  // Two parallel sheets 2 mm apart approaching each other: every vertex lands in Vc.
  CollisionMesh a = make_sheet(4, 4, 0.1, 0.1, Vec3(0, 0, 0), 1e-3);
  CollisionMesh b = make_sheet(4, 4, 0.1, 0.1, Vec3(0.01, 0.012, 2e-3), 1e-3);
  a.x1.col(2).array() += kDt * 0.5;
  b.x1.col(2).array() -= kDt * 0.5;
  ClothContacts data;
  detect_cloth_contacts({&a, &b}, options(true), data);
  for (int m = 0; m < 2; ++m) {
    const ContactVertexSets sets = contact_vertex_sets(data.contacts, m);
    EXPECT_TRUE(sets.obstacle.empty());
    EXPECT_GE(sets.cloth.size(), 16u);
  }
  // Momentum along z is conserved by the pairwise impulses.
  const double pz = (a.x1 - a.x0).col(2).sum() + (b.x1 - b.x0).col(2).sum();
  EXPECT_NEAR(pz, 0.0, 1e-12);
  // Every pair's approach (1 m/s before) is stopped.
  for (const Proximity& p : data.proximities) {
    Vec3 vr = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      const CollisionMesh& m = p.corner_mesh(k) == 0 ? a : b;
      vr += p.w[k] * (m.x1.row(p.corner[static_cast<std::size_t>(k)]) - m.x0.row(p.corner[static_cast<std::size_t>(k)])).transpose() / kDt;
    }
    EXPECT_GE(p.normal.dot(vr), -1e-3);
  }
}
