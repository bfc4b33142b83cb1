/// The headline (paper §4, Fig. 2): a gripper pinching a hanging strip holds it iff 2μN ≥ mg,
/// with no creep, in the bai-liu coupling; the kinematic baseline ignores the squeeze force. Runs
/// scenes/gripper_pinch.json through the CLI with the squeeze force swept around
/// N* = m g / (2 μ) = 0.15·0.05·0.30·9.81 / (2·0.5) = 0.0221 N.
///
/// The pinched vertices' friction is solved inside the implicit cloth step (they carry the load
/// of the whole strip), with the DART squeeze force low-passed over 50 ms.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "cli_runner.hpp"

using namespace dexcloth::test;
namespace fs = std::filesystem;

namespace {

constexpr double kThreshold = 0.15 * 0.05 * 0.30 * 9.81 / (2.0 * 0.5);  // N* [N]

/// Runs the pinch with squeeze force `n` [N] per jaw; `extra` adds CLI arguments.
nlohmann::json pinch(double n, const std::string& coupling, const std::string& extra = "") {
  const std::string force = std::to_string(n);
  // One output folder per force and extra arguments: tests running at once never share one.
  const fs::path out =
      fresh_dir(coupling + force + "_" + std::to_string(std::hash<std::string>{}(extra)));
  const auto r = run_cli(
      "run " + (source_dir() / "scenes" / "gripper_pinch.json").string() + " --quiet --out " +
      out.string() + " --coupling " + coupling +
      " --set /bodies/0/controller/joint_forces/keyframes/0/joints/left_finger=" + force +
      " --set /bodies/0/controller/joint_forces/keyframes/0/joints/right_finger=" + force + " " + extra);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return read_json(out / "summary.json");
}

/// How far the pinched cloth vertex moved relative to the jaw between times t0 and t1 [m].
double slip(const nlohmann::json& s, double t0, double t1) {
  return relative_motion(s, "pinched", "finger", t0, t1);
}

}  // namespace

TEST(Pinch, HeldAboveTheCoulombThresholdWithoutIntersections) {
  for (double factor : {1.1, 1.5}) {
    const auto s = pinch(factor * kThreshold, "bai-liu", "--duration 2.0");
    // Released at 0.8 s; held still from 1.0 s to 2.0 s.
    EXPECT_LT(slip(s, 1.0, 2.0), 1e-3) << factor << " N*";
    EXPECT_EQ(s["intersections_max"], 0) << factor << " N*";
    EXPECT_EQ(s["nan"], false);
  }
}

TEST(Pinch, HeldAtTheThresholdWhereverTheStripHangsBetweenTheJaws) {
  // The hold at 1.1 N* must not hinge on the strip hanging exactly midway between the jaws: a
  // strip 0.2 mm off centre slipped 1.5 mm (toward a jaw) and 9 mm (sideways) when the jaws
  // could close on the cloth past its two repulsion layers.
  for (const char* at : {"[0,0.0002,0.39]", "[0.0002,0,0.39]"}) {
    const auto s = pinch(1.1 * kThreshold, "bai-liu",
                         std::string("--duration 2.0 --set /cloths/0/transform/translation=") + at);
    EXPECT_LT(slip(s, 1.0, 2.0), 1e-3) << at;
    EXPECT_EQ(s["intersections_max"], 0) << at;
  }
}

TEST(Pinch, JawsSlammedShutOnTheStripStopOnItAndHoldItThroughTheLift) {
  // At 45 N* (1 N a jaw) the jaws reach 1.2 m/s, 6 mm a step: more than the 5 mm repulsion
  // thickness, so no patch stood between them at the start of the step they arrived in, and they
  // closed through the strip (114 intersecting pairs until 5 Dec; impact zones failing next to
  // the held top edge). The patches now also take the cloth a fast body will reach in the next
  // step (speculative_touches.hpp): the jaws stop on the strip and carry it up 10 cm.
  const auto s = pinch(1.0, "bai-liu", "--duration 2.8");
  expect_intact(s);
  EXPECT_EQ(s["warnings_total"], 0) << s["warnings"];
  EXPECT_LT(slip(s, 0.3, 2.8), 1e-3);
  EXPECT_GT(s["probes"]["pinched"].back()[3].get<double>(), 0.6);
}

TEST(Pinch, JawsKickedShutFromRestStopOnTheStripWithRigidSubsteps) {
  // Open jaws at rest, then 20 N a jaw (900 N*) from 0.5 s: from rest each jaw gains about 1 m/s
  // a step, is stopped on the strip's patch, and is kicked again from rest within the next
  // step, which the velocities of past steps do not foresee. DART finds contacts only at the
  // start of its step, so with one rigid step per cloth step a jaw resting 0.2 mm off the patch
  // moved 3.4 mm into it unopposed (at 10 N; h²F/m is 5 mm for its 51 g) and the cloth step
  // then swept it through the strip (10, 20 and 50 N: 22, 8 and 8 intersecting pairs). With four
  // rigid substeps (the hand scenes' setting, scene-format.md) the jaws stop on the strip and carry
  // it up 10 cm: 0 pairs at 10, 20 and 50 N (0.6–1.9 mm of slip; at 50 N a few impacts next to the
  // held top edge go unresolved, with warnings).
  const auto s = pinch(0.0, "bai-liu",
                       "--set /coupling_params/rigid_substeps=4 "
                       "--set /bodies/0/controller/joint_forces/keyframes/1="
                       "'{\"t\":0.5,\"joints\":{\"left_finger\":20,\"right_finger\":20}}'");
  expect_intact(s);
  EXPECT_EQ(s["warnings_total"], 0) << s["warnings"];
  EXPECT_LT(slip(s, 1.0, 3.0), 5e-3);
  EXPECT_GT(s["probes"]["pinched"].back()[3].get<double>(), 0.6);
}

TEST(Pinch, DropsBelowTheCoulombThreshold) {
  const auto s = pinch(0.9 * kThreshold, "bai-liu", "--duration 2.0");
  // At 0.9 N* the strip accelerates at ≥ 0.1 g while in the jaws: > 5 cm in the first 1 s.
  EXPECT_GT(slip(s, 0.8, 2.0), 0.02);
}

TEST(Pinch, NoCreepAtOneAndAHalfTimesTheThreshold) {
  // Lift postponed so the gripper holds still from 1.0 s to 3.0 s.
  const auto s = pinch(1.5 * kThreshold, "bai-liu",
                       "--duration 3.0 --set /bodies/0/controller/joint_pd/keyframes/1/t=3.5 "
                       "--set /bodies/0/controller/joint_pd/keyframes/2/t=4.0");
  EXPECT_LT(slip(s, 1.0, 3.0), 1e-4);
}

TEST(Pinch, KinematicBaselineIgnoresTheSqueezeForce) {
  // ARCSim-style coupling: the jaws are kinematic obstacles that close until their joint limit,
  // with the cloth inside the repulsion thickness; friction then comes from the repulsion
  // impulses, which depend on positions only. So the outcome does not depend on N (paper §7.1,
  // Fig. 4): here the strip is held at 0.9 N* as at 1.5 N*, which Coulomb forbids (a strip
  // that drops leaves the 8 cm jaws; a held one creeps by millimetres at most).
  for (double factor : {0.9, 1.5}) {
    const auto s = pinch(factor * kThreshold, "kinematic", "--duration 2.0");
    EXPECT_LT(slip(s, 0.8, 2.0), 1e-2) << factor << " N*";
    EXPECT_EQ(s["patches_max"], 0);
  }
}

TEST(Pinch, FirmSqueezeHoldsThroughTheLiftWithTheClothOffTheJaws) {
  // A squeeze of 1 N per jaw (45 N*) with jaws damped to close at 5 cm/s (0.25 mm per step, well
  // inside the 5 mm repulsion layer): the patch between the jaws takes the whole force, so the
  // cloth stays at the repulsion thickness from each jaw face (jaw centre 5 mm behind its face)
  // and is carried through the 10 cm lift without slip. The handle lets go at 1.5 s, once the
  // slow jaws have closed; the lift runs from 2.5 s to 3.1 s. (Jaws slamming shut at metres per
  // second cross the repulsion layer within one step, and the patch then forms inside them.)
  const auto s = pinch(45.0 * kThreshold, "bai-liu",
                       "--duration 3.3 --set /bodies/0/controller/joint_pd/gains/left_finger/kd=20 "
                       "--set /bodies/0/controller/joint_pd/gains/right_finger/kd=20 "
                       "--set /cloths/0/handles/0/release=1.5 "
                       "--set /bodies/0/controller/joint_pd/keyframes/1/t=2.5 "
                       "--set /bodies/0/controller/joint_pd/keyframes/2/t=3.1");
  EXPECT_LT(slip(s, 1.7, 3.3), 1e-4);
  const auto& cloth = s["probes"]["pinched"];
  const auto& jaw = s["probes"]["finger"];
  for (std::size_t k = 0; k < cloth.size(); ++k) {
    if (cloth[k][0].get<double>() < 1.5) continue;
    const double off_face = std::abs(cloth[k][2].get<double>() - jaw[k][2].get<double>()) - 0.005;
    EXPECT_GT(off_face, 0.0045) << "t = " << cloth[k][0].get<double>();
  }
  EXPECT_GT(cloth.back()[3].get<double>() - cloth.front()[3].get<double>(), 0.095);
  EXPECT_EQ(s["intersections_max"], 0);
  EXPECT_EQ(s["warnings_total"], 0);
}
