#include <gtest/gtest.h>

#include <cmath>

#include "control/poses.hpp"
#include "rigid/world.hpp"

namespace dexcloth::control {
namespace {

const std::string kAssets = std::string(DEXCLOTH_SOURCE_DIR) + "/assets/hands";

/// A flat skin pad of the hand: its face centre and outward normal, in the world.
struct Pad {
  Vec3 centre;
  Vec3 normal;
};

/// Thumb pulp and index radial pads (make_human_hand.py: the face lies 0.5 mm outside the
/// capsule; centres at the pad boxes' outer faces) with the hand fixed at the identity, in `pose`.
std::pair<Pad, Pad> key_pads(const std::string& pose) {
  rigid::RigidWorld world;
  rigid::UrdfOptions options;
  options.fixed_root = true;
  const rigid::SkeletonId s = world.add_urdf("hand", kAssets + "/human_hand.urdf", options);
  ErrorList errors;
  const PoseLibrary poses = load_poses(kAssets + "/human_hand.poses.json", errors);
  EXPECT_TRUE(errors.empty()) << errors.to_string();
  Eigen::VectorXd q = world.positions(s);
  for (const auto& [joint, value] : poses.at(pose)) q[world.dof_index(s, joint)] = value;
  world.set_positions(s, q);
  const Eigen::Isometry3d thumb = world.pose_W(world.body(s, "thumb_distal"));
  const Eigen::Isometry3d index = world.pose_W(world.body(s, "index_middle"));
  return {{thumb * Vec3(0.0105, 0.0, -0.0097), thumb.linear() * Vec3(0, 0, -1)},
          {index * Vec3(0.014, 0.009, 0.0), index.linear() * Vec3(0, 1, 0)}};
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(HandPoses, KeyPinchHoldsTheThumbPadParallelToTheIndexRadialPad) {
  // 'key': pads face each other within 0.5°, 7.7 mm apart (a cloth's 10 mm patch between them
  // leaves the thumb PD a 2.3 mm overshoot to squeeze with), centres aligned within 1.5 mm.
  const auto [thumb, index] = key_pads("key");
  EXPECT_LT(angle_deg(thumb.normal, -index.normal), 0.5);
  const Vec3 d = thumb.centre - index.centre;
  EXPECT_NEAR(d.dot(index.normal), 0.0077, 5e-4);
  EXPECT_LT((d - d.dot(index.normal) * index.normal).norm(), 1.5e-3);
}

TEST(HandPoses, KeyOpenLeavesRoomForACurtainOfCloth) {
  // 'key_open': the same pads at least 15 mm apart and within 5° of parallel, so a cloth with
  // a 5 mm repulsion layer on each side fits between them.
  const auto [thumb, index] = key_pads("key_open");
  EXPECT_LT(angle_deg(thumb.normal, -index.normal), 5.0);
  EXPECT_GT((thumb.centre - index.centre).dot(index.normal), 0.015);
}

}  // namespace
}  // namespace dexcloth::control
