/// The 33-DOF hand lifts a ball by a thumb–index pinch (scenes/hand_grasp_ball.json).
#include <gtest/gtest.h>

#include "cli_runner.hpp"

using namespace dexcloth::test;

TEST(Hand, PinchLiftsTheBallTenCentimetresAndHoldsIt) {
  const auto s = run_scene("hand_grasp_ball");
  const auto& ball = s["probes"]["ball"];
  const double z0 = ball.front()[3].get<double>();
  const double z_end = ball.back()[3].get<double>();
  // The wrist rises 10 cm; the ball follows within 1 cm (grip settling).
  EXPECT_GT(z_end - z0, 0.09);
  // Held still from 2.0 s to the end (2.5 s): it moves less than 2 mm.
  double z_hold = 0.0;
  for (const auto& p : ball)
    if (p[0].get<double>() <= 2.0 + 1e-9) z_hold = p[3].get<double>();
  EXPECT_LT(std::abs(z_end - z_hold), 2e-3);
  EXPECT_EQ(s["nan"], false);
}
