#include <gtest/gtest.h>

#include "rigid/world.hpp"
#include "test_helpers.hpp"

namespace dexcloth::rigid {
namespace {

using test::add_box;

/// A 50 g "fingertip" box resting on patch 0 (2 cm × 2 cm × 1 mm) that lies on a static block.
struct PatchScene {
  RigidWorld world{RigidWorldOptions{0.005, Vec3(0, 0, -9.81), 4000, 8}};
  BodyId finger;
  PatchState patch;
  PatchScene() {
    PropSpec block;
    block.name = "block";
    block.size = Vec3(0.1, 0.1, 0.1);
    block.X_WP.translation() = Vec3(0, 0, -0.05);  // top face at z = 0
    world.add_prop(block);
    finger = world.root_body(add_box(world, "finger", Vec3(0.015, 0.015, 0.015), 0.05, Vec3(0, 0, 0.001 + 0.0075)));
    patch.active = true;
    patch.extents = Vec2(0.02, 0.02);
    patch.thickness = 0.001;
    patch.X_WP.translation() = Vec3(0, 0, 0.0005);
    patch.mass = 1.0e-3;
  }
};

TEST(PatchPool, FingerOnActivePatchPushesIt) {
  PatchScene s;
  for (int i = 0; i < 100; ++i) {
    // The coupling resets the patch every step from the cloth.
    s.world.patches().set(0, s.patch);
    s.world.step();
  }
  // The finger's weight goes through the patch: the patch feels m g down from the finger (3 %).
  const double w = 0.05 * 9.81;
  Vec3 from_finger = Vec3::Zero();
  for (const auto& c : s.world.patches().contacts(0)) {
    if (c.other == s.finger) from_finger += c.f_W;
  }
  EXPECT_NEAR(from_finger.z(), -w, 0.03 * w);
  // The finger rests on the patch top (z = 1 mm), not on the block.
  EXPECT_NEAR(s.world.pose_W(s.finger).translation().z(), 0.001 + 0.0075, 5e-4);
  for (const auto& c : s.world.contacts(s.finger)) EXPECT_EQ(c.other, s.world.patches().body(0));
}

TEST(PatchPool, InactivePatchFeelsNothingAndPatchesIgnoreEachOther) {
  PatchScene s;
  PatchState off = s.patch;
  off.active = false;
  // Patch 1 overlaps patch 0 exactly: patch–patch pairs must be filtered out.
  PatchState twin = s.patch;
  for (int i = 0; i < 100; ++i) {
    s.world.patches().set(0, off);
    s.world.patches().set(1, twin);
    s.world.step();
  }
  EXPECT_TRUE(s.world.patches().contacts(0).empty());
  for (const auto& c : s.world.patches().contacts(1)) EXPECT_NE(c.other, s.world.patches().body(0));
  EXPECT_FALSE(s.world.patches().contacts(1).empty());
  // With patch 1 switched off too, the finger falls onto the block (top at z = 0).
  s.world.patches().deactivate_all();
  for (int i = 0; i < 100; ++i) s.world.step();
  EXPECT_TRUE(s.world.patches().contacts(1).empty());
  EXPECT_NEAR(s.world.pose_W(s.finger).translation().z(), 0.0075, 5e-4);
}

TEST(PatchPool, PatchesOfDifferentLayersStack) {
  // Patch 1 (layer 1) lies on patch 0 (layer 0): the finger rests on top of both (z = 2 mm), and
  // patch 0 carries the finger's weight down to the block through patch 1.
  PatchScene s;
  PatchState upper = s.patch;
  upper.layer = 1;
  upper.X_WP.translation() = Vec3(0, 0, 0.0015);
  s.world.set_free_body_state(s.finger, Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 0.002 + 0.0075)),
                              Vec3::Zero(), Vec3::Zero());
  for (int i = 0; i < 100; ++i) {
    s.world.patches().set(0, s.patch);
    s.world.patches().set(1, upper);
    s.world.step();
  }
  EXPECT_NEAR(s.world.pose_W(s.finger).translation().z(), 0.002 + 0.0075, 5e-4);
  Vec3 from_upper = Vec3::Zero();
  for (const auto& c : s.world.patches().contacts(0))
    if (c.other == s.world.patches().body(1)) from_upper += c.f_W;
  EXPECT_NEAR(from_upper.z(), -0.05 * 9.81, 0.05 * 0.05 * 9.81);
}

/// Where a 15 g fingertip pushed down with 2 N onto a 1 mm patch lying on a block ends after
/// `steps` steps of 5 ms: the height of its bottom face [m] and the mean force it puts on the
/// patch in the last step [N]. The finger starts 1 mm above the patch, at rest.
std::pair<double, double> push_onto_patch(int substeps, int steps) {
  RigidWorld world{RigidWorldOptions{0.005, Vec3(0, 0, -9.81), 4000, 8, substeps}};
  PropSpec block;
  block.name = "block";
  block.size = Vec3(0.1, 0.1, 0.1);
  block.X_WP.translation() = Vec3(0, 0, -0.05);  // top face at z = 0
  world.add_prop(block);
  const BodyId finger = world.root_body(
      add_box(world, "finger", Vec3(0.015, 0.015, 0.015), 0.015, Vec3(0, 0, 0.002 + 0.0075)));
  PatchState patch;
  patch.active = true;
  patch.extents = Vec2(0.04, 0.04);
  patch.thickness = 0.001;
  patch.X_WP.translation() = Vec3(0, 0, 0.0005);
  patch.mass = 1.0e-4;
  for (int i = 0; i < steps; ++i) {
    world.patches().set(0, patch);  // rebuilt every step, as the coupling does
    world.add_force_at(finger, Vec3::Zero(), Vec3(0, 0, -2.0));
    world.step();
  }
  Vec3 f = Vec3::Zero();
  for (const auto& c : world.patches().contacts(0))
    if (c.other == finger) f += c.f_W;
  return {world.pose_W(finger).translation().z() - 0.0075, -f.z()};
}

TEST(PatchPool, SubstepsStopAFingerDrivenOntoAThinPatch) {
  // Contacts are found once per DART step: a light finger under a large force that starts a step
  // off the patch moves h² a = 3.6 mm in it (a = F/m + g = 143 m/s²), through the 1 mm patch
  // into the block. With four substeps (h_s² a = 0.22 mm) it has covered 0.22, 0.67 and 1.34 mm
  // after the first three, so it is found at most one substep's travel (0.67 mm) deep in the patch.
  EXPECT_LT(push_onto_patch(1, 1).first, 0.0);
  const double bottom = push_onto_patch(4, 1).first;
  EXPECT_GT(bottom, 0.0005);
  EXPECT_LT(bottom, 0.002);
  // At rest it sits the contact allowance deep, and the contact force over the substeps
  // averages to the push and the finger's weight.
  const auto [rest, force] = push_onto_patch(4, 40);
  EXPECT_NEAR(rest, 0.001 - RigidWorld{}.contact_allowance(), 5e-5);
  EXPECT_NEAR(force, 2.0 + 0.015 * 9.81, 0.02 * 2.15);
}

TEST(PatchPool, ResizedPatchCollidesWithItsNewSize) {
  // A patch made wider after creation must support a finger resting off its old extent.
  PatchScene s;
  s.world.patches().set(0, s.patch);
  s.world.step();
  s.patch.extents = Vec2(0.08, 0.08);
  const BodyId finger = s.finger;
  s.world.set_free_body_state(finger, Eigen::Isometry3d(Eigen::Translation3d(0.03, 0.0, 0.0085)), Vec3::Zero(), Vec3::Zero());
  for (int i = 0; i < 100; ++i) {
    s.world.patches().set(0, s.patch);
    s.world.step();
  }
  EXPECT_NEAR(s.world.pose_W(finger).translation().z(), 0.0085, 5e-4);
  // The patch carries the finger's weight (0.49 N) down onto the block: Σ contacts ≈ patch weight.
  Vec3 from_finger = Vec3::Zero();
  for (const auto& c : s.world.patches().contacts(0)) {
    if (c.other == finger) from_finger += c.f_W;
  }
  EXPECT_NEAR(from_finger.z(), -0.05 * 9.81, 0.03 * 0.05 * 9.81);
  EXPECT_NEAR(s.world.patches().contact_force_W(0).z(), 1.0e-3 * 9.81, 1.0e-3);
}

}  // namespace
}  // namespace dexcloth::rigid
