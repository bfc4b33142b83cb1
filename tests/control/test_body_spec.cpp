#include <gtest/gtest.h>

#include "control/body_spec.hpp"

namespace dexcloth::control {
namespace {

using nlohmann::json;

const std::string kAssets = std::string(DEXCLOTH_SOURCE_DIR) + "/assets/hands";

bool has(const ErrorList& e, const std::string& pointer, const std::string& text) {
  for (const auto& err : e.errors()) {
    if (err.file == "scene.json" && err.pointer == pointer && err.message.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(BodySpec, ParsesAFullEntry) {
  const json j = json::parse(R"({
    "name": "hand", "urdf": "human_hand.urdf", "poses": "human_hand.poses.json",
    "root": {"translation": [0.1, 0.2, 0.3], "rotation_deg": [0, 0, 90]}, "fixed_root": false, "friction": 0.8,
    "controller": {
      "gravity_compensation": "joints",
      "joint_pd": {"kp": 3, "kd": 0.03, "gains": {"thumb_ip": {"kp": 1}},
                   "keyframes": [{"t": 0, "pose": "open"}, {"t": 1, "pose": "pinch", "joints": {"index_dip": 0.5}}]},
      "wrist": {"kp": 1000, "keyframes": [{"t": 0, "translation": [0.1, 0.2, 0.3]}]},
      "forces": [{"body": "index_distal", "point": [0.013, 0, -0.008], "keyframes": [{"t": 0, "force": [0, 0, -2]}]}]
    }})");
  ErrorList errors;
  const BodySpec s = parse_body_spec(j, "scene.json", "/bodies/0", kAssets, errors);
  ASSERT_TRUE(errors.empty()) << errors.to_string();
  EXPECT_EQ(s.urdf, kAssets + "/human_hand.urdf");
  EXPECT_EQ(s.root_rotation_deg, Vec3(0, 0, 90));
  EXPECT_EQ(s.controller.gravity_compensation, GravityCompensationMode::joints);
  ASSERT_TRUE(s.controller.joint_pd);
  EXPECT_EQ(s.controller.joint_pd->joint_gains.at("thumb_ip").kp, 1.0);
  EXPECT_EQ(s.controller.joint_pd->joint_gains.at("thumb_ip").kd, 0.03);
  EXPECT_EQ(s.controller.wrist->gains.kp, 1000.0);
  // Building it resolves every name and places the root.
  rigid::RigidWorld world;
  BuiltBody b = build_body(world, s, "scene.json");
  EXPECT_EQ(b.controllers.size(), 4u);
  EXPECT_TRUE(probe(world, "hand/palm").isApprox(Vec3(0.1, 0.2, 0.3)));
  EXPECT_TRUE(probe(world, "hand/palm", Vec3(1, 0, 0)).isApprox(Vec3(0.1, 1.2, 0.3), 1e-9));
}

TEST(BodySpec, ReportsEveryProblemWithItsPointer) {
  const json j = json::parse(R"({
    "name": "hand", "urdf": "human_hand.urdf", "colour": "red", "fixed_root": 1,
    "controller": {
      "gravity_compensation": "some",
      "joint_pd": {"kp": -1, "keyframes": [{"t": 1}, {"t": 0.5, "jionts": {}}]},
      "forces": [{"point": [0, 0], "keyframes": [{"t": 0}]}]
    }})");
  ErrorList errors;
  parse_body_spec(j, "scene.json", "/bodies/0", kAssets, errors);
  EXPECT_TRUE(has(errors, "/bodies/0/colour", "unknown key")) << errors.to_string();
  EXPECT_TRUE(has(errors, "/bodies/0/fixed_root", "true or false"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/gravity_compensation", "\"none\""));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/joint_pd/kp", "must be ≥ 0, got -1"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/joint_pd/keyframes/1/t", "must be > the previous"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/joint_pd/keyframes/1/jionts", "unknown key"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/forces/0/body", "is required"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/forces/0/point", "3 finite numbers"));
  EXPECT_TRUE(has(errors, "/bodies/0/controller/forces/0/keyframes/0/force", "is required"));
  EXPECT_EQ(errors.size(), 9u) << errors.to_string();
}

TEST(BodySpec, UnknownNamesAndFilesAreReportedAtBuild) {
  const json j = json::parse(R"({
    "name": "hand", "urdf": "human_hand.urdf", "poses": "human_hand.poses.json",
    "controller": {"joint_pd": {"keyframes": [{"t": 0, "pose": "wave", "joints": {"index_pip3": 1}}]},
                   "forces": [{"body": "sixth_finger", "keyframes": [{"t": 0, "force": [0, 0, 1]}]}]}})");
  ErrorList errors;
  const BodySpec s = parse_body_spec(j, "scene.json", "/bodies/0", kAssets, errors);
  ASSERT_TRUE(errors.empty()) << errors.to_string();
  rigid::RigidWorld world;
  try {
    build_body(world, s, "scene.json");
    FAIL() << "bad names accepted";
  } catch (const InputRejected& e) {
    EXPECT_TRUE(has(e.errors(), "/bodies/0/controller/joint_pd/keyframes/0/pose", "no pose 'wave'")) << e.what();
    EXPECT_TRUE(has(e.errors(), "/bodies/0/controller/joint_pd/keyframes/0/joints/index_pip3", "no joint 'index_pip3'"));
    EXPECT_TRUE(has(e.errors(), "/bodies/0/controller/forces/0/body", "no body 'sixth_finger'"));
    EXPECT_EQ(e.errors().size(), 3u) << e.what();
  }
  // A missing URDF names the scene entry and the URDF path.
  BodySpec missing = s;
  missing.name = "other";
  missing.urdf = kAssets + "/nothing.urdf";
  rigid::RigidWorld world2;
  try {
    build_body(world2, missing, "scene.json");
    FAIL() << "missing URDF accepted";
  } catch (const InputRejected& e) {
    EXPECT_TRUE(has(e.errors(), "/bodies/0/urdf", "nothing.urdf: URDF file not found")) << e.what();
  }
}

}  // namespace
}  // namespace dexcloth::control
