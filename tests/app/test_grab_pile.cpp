/// Grabbing from a pile (paper Table 1): scenes/grab_pile.json, a gripper that picks the top
/// napkin off a crumpled pile of two, in both couplings.
#include <gtest/gtest.h>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

/// Lowest, highest and mean height of a recorded cloth at the first frame at or after t [m].
struct Span {
  double min{}, max{}, mean{};
};

Span span(const std::vector<ClothFrame>& frames, double t) {
  for (const ClothFrame& f : frames)
    if (f.t >= t - 1e-9) return {f.x.col(2).minCoeff(), f.x.col(2).maxCoeff(), f.x.col(2).mean()};
  ADD_FAILURE() << "no frame at " << t;
  return {};
}

struct Pile {
  nlohmann::json summary;
  std::vector<ClothFrame> bottom, top;  ///< napkins 'a' and 'b'
};

Pile run(const std::string& name, const std::string& args = "") {
  const auto out = fresh_dir(name);
  const auto scene = source_dir() / "scenes" / "grab_pile.json";
  const auto r = run_cli("run " + scene.string() + " --quiet --out " + out.string() + " " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return {read_json(out / "summary.json"), cloth_frames(out, 0), cloth_frames(out, 1)};
}

}  // namespace

TEST(GrabPile, TheGripperPicksTheTopNapkinOffThePile) {
  const Pile p = run("grab_pile");
  expect_intact(p.summary);
  // A pile before the grab: the top napkin lies crumpled on the bottom one.
  EXPECT_LT(span(p.top, 2.0).max, 0.06);
  // Lifted whole (its lowest point 10 cm up) and held from the end of the lift to the end:
  // its mean height moves less than 5 mm (measured 1 mm).
  const Span lifted = span(p.top, 3.1), end = span(p.top, 3.6);
  EXPECT_GT(end.min, 0.08);
  EXPECT_NEAR(end.mean, lifted.mean, 5e-3);
  // The bottom napkin stays on the table, flat (one layer lies at 5 mm).
  EXPECT_LT(span(p.bottom, 3.6).max, 0.03);
  EXPECT_LT(span(p.bottom, 3.6).mean, 0.01);
}

TEST(GrabPile, TheKinematicJawsCrushThePileAndLiftBothNapkins) {
  // Kinematic jaws push the cloth through itself where they squeeze the pile, so the bottom
  // napkin, caught in the top one, comes up with it.
  const Pile p = run("grab_pile_kinematic", "--coupling kinematic --duration 3.2");
  EXPECT_FALSE(p.summary["nan"].get<bool>());
  EXPECT_GT(span(p.top, 3.2).mean, 0.1);
  EXPECT_GT(span(p.bottom, 3.2).mean, 0.1);
}
