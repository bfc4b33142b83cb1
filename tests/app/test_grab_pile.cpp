/// Grabbing from a pile (paper Table 1): scenes/grab_pile.json, a gripper that picks the top
/// napkin off a crumpled pile of two, in both couplings.
#include <gtest/gtest.h>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

struct Pile {
  nlohmann::json summary;
  std::vector<ClothFrame> bottom, top;  ///< napkins 'a' and 'b'
};

Pile run(const std::string& name, const std::string& args = "") {
  const CliRun r = run_file(source_dir() / "scenes" / "grab_pile.json", name, args);
  return {r.summary, cloth_frames(r.out, 0), cloth_frames(r.out, 1)};
}

}  // namespace

TEST(GrabPile, TheGripperPicksTheTopNapkinOffThePile) {
  const Pile p = run("grab_pile");
  expect_intact(p.summary);
  // A pile before the grab: the top napkin lies crumpled on the bottom one.
  EXPECT_LT(heights_at(p.top, 2.0).max, 0.06);
  // Lifted whole (its lowest point 10 cm up) and held from the end of the lift to the end:
  // its mean height moves less than 5 mm (measured 1 mm).
  const Heights lifted = heights_at(p.top, 3.1), end = heights_at(p.top, 3.6);
  EXPECT_GT(end.min, 0.08);
  EXPECT_NEAR(end.mean, lifted.mean, 5e-3);
  // The bottom napkin stays on the table (one layer lies at 5 mm). The top one drags part of it
  // up a few centimetres as it leaves, and it falls back rumpled, more or less at random:
  // measured max 1.3–3.7 cm, mean 5–11 mm.
  EXPECT_LT(heights_at(p.bottom, 3.6).max, 0.05);
  EXPECT_LT(heights_at(p.bottom, 3.6).mean, 0.015);
}

TEST(GrabPile, TheKinematicJawsCrushThePileAndLiftBothNapkins) {
  // Kinematic jaws push the cloth through itself where they squeeze the pile, so the bottom
  // napkin, caught in the top one, comes up with it.
  const Pile p = run("grab_pile_kinematic", "--coupling kinematic --duration 3.2");
  EXPECT_FALSE(p.summary["nan"].get<bool>());
  EXPECT_GT(heights_at(p.top, 3.2).mean, 0.1);
  EXPECT_GT(heights_at(p.bottom, 3.2).mean, 0.1);
}
