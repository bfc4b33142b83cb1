/// The paper's "Curtain" as the paper does it: the 33-DOF hand grabs a 16k-triangle curtain's
/// leading edge by a key pinch and slides it along its rod (scenes/curtain_hand.json).
#include <gtest/gtest.h>

#include <cmath>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

constexpr double kClosed = 0.8;  // the hand is in 'key' from here on [s]
constexpr double kPull = 0.25;   // the wrist's travel along the rod (x) [m]

/// How far probe `p` moved along the rod (x) from the first sample to the last [m].
double slid(const nlohmann::json& s, const std::string& p) {
  const auto& samples = s["probes"][p];
  return samples.back()[1].get<double>() - samples.front()[1].get<double>();
}

}  // namespace

TEST(CurtainHand, TheHandSlidesTheCurtainAlongItsRodByAKeyPinch) {
  const auto s = run_scene("curtain_hand");
  expect_intact(s);
  // Only the pads' friction moves the curtain: the pinched vertex stays between them while the
  // wrist pulls 25 cm (measured: at most 6.0 mm from either pad centre, 6.0–9.7 mm with the
  // curtain shifted up to 8 mm along the rod and 4 mm across it; the pads are 7.7 mm apart).
  // The curtain's edge lies stepped between the pads in this start; counted as two layers, it
  // held the pads a thickness apart until the pull flattened the step, and with other rounding
  // the curtain slipped 8 mm while they closed (16.9 mm from a pad).
  EXPECT_LT(carry(s, "pinched", kClosed).farthest, 0.015);
  EXPECT_NEAR(slid(s, "pinched"), kPull, 0.02);
  // The whole curtain follows on its frictionless rod (measured: 27 cm; it runs a little on
  // after the hand stops and bunches toward it).
  for (const char* p : {"ring", "far_edge"}) EXPECT_NEAR(slid(s, p), kPull, 0.2 * kPull) << p;
  // The rings stay on the rod: 0.9 m high, in the curtain's plane.
  for (const auto& sample : s["probes"]["ring"]) {
    EXPECT_NEAR(sample[3].get<double>(), 0.9, 1e-9);
    EXPECT_NEAR(sample[2].get<double>(), 0.0, 1e-9);
  }
}

TEST(CurtainHand, WithoutFrictionThePadsSlideOffTheEdge) {
  // μ = 0 on the hand: the pull is along the cloth's plane, so nothing but friction can carry
  // it. The pads slide off the leading edge and the curtain stays (measured: 17 cm from the pads
  // by 1.8 s, the rings moved 4 mm).
  const auto s = run_scene("curtain_hand", "--duration 1.8 --set /bodies/0/friction=0");
  expect_intact(s);
  EXPECT_GT(carry(s, "pinched", kClosed).farthest, 0.1);
  EXPECT_LT(std::abs(slid(s, "ring")), 0.02);
}

TEST(CurtainHand, TheKinematicBaselineLetsTheCurtainSlipInThePinch) {
  // ARCSim-style coupling: the hand is a kinematic obstacle and friction comes from the
  // repulsion, capped per step; the pinched edge slips between the pads during the pull while
  // the repulsion still drags the curtain along. How far it slips before it catches again
  // depends on rounding alone: by OpenBLAS kernel (OPENBLAS_CORETYPE), at most 5.9 cm from a pad
  // with this machine's default, 11.8 cm with Cooperlake or SkylakeX, 14.8 cm with Sandybridge
  // (the pinched vertex carried 21.6–25.1 cm along the rod); at 1.8 s, where this test once
  // stopped, 4.6–11.9 cm. With the single-precision substitution kernels (7 Dec, default
  // OpenBLAS kernels): 14.5 cm, carried 23.0 cm. Required: beyond 4 cm, against the 1.5 cm the pads
  // keep in the paper's coupling (TheHandSlidesTheCurtainAlongItsRodByAKeyPinch).
  const auto s = run_scene("curtain_hand", "--coupling kinematic");
  EXPECT_EQ(s["nan"], false);
  EXPECT_EQ(s["patches_max"], 0);
  EXPECT_GT(carry(s, "pinched", kClosed).farthest, 0.04);
}
