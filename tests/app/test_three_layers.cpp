/// The 33-DOF hand pinches three stacked napkins, lifts them, carries them and turns them
/// (scenes/three_layers.json, paper Fig. 5).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "cli_runner.hpp"

using namespace dexcloth::test;

TEST(ThreeLayers, TheHandCarriesAllThreeNapkinsWithoutIntersections) {
  const auto s = run_scene("three_layers");
  // From the handles' release (1.7 s) on, the outer napkins hang from the pads and the middle
  // one from the layers around it, while the wrist lifts them 15 cm, carries them 20 cm and
  // turns them 60°: each napkin's pinched vertex stays between the pads and rises with the hand.
  // A napkin that slides out falls below where it was let go. Measured over six runs with the
  // middle napkin shifted ≤ 0.3 mm: all three held, within 7.0–11.9 mm of the pad centres,
  // rising 14.2–15.0 cm. Before squeezed vertices moved with the pads along the normal, the
  // stack was lost within a second after the lift.
  for (const char* layer : {"pinched_bottom", "pinched_middle", "pinched_top"}) {
    const Carry c = carry(s, layer, 1.7);
    EXPECT_LT(c.farthest, 0.02) << layer;
    EXPECT_GT(c.rise, 0.12) << layer;
  }
  // No cloth–cloth or cloth–hand intersection at any recorded frame, no lost state.
  EXPECT_EQ(s["intersections_max"], 0);
  EXPECT_EQ(s["nan"], false);
  for (const auto& w : s["warnings"])
    EXPECT_EQ(w["message"].get<std::string>().find("lost"), std::string::npos) << w;
}
