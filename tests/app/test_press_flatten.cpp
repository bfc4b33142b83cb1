/// Flattening a crumpled napkin by pressing it (paper Table 1, "Flattening"):
/// scenes/press_flatten.json, the 33-DOF hand pressing a heap flat on a table, in both couplings.
#include <gtest/gtest.h>

#include <algorithm>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

/// Highest and mean height of the cloth at the first recorded frame at or after t [m].
struct Heights {
  double max{};
  double mean{};
};

Heights heights(const std::vector<ClothFrame>& frames, double t) {
  for (const ClothFrame& f : frames)
    if (f.t >= t - 1e-9) return {f.x.col(2).maxCoeff(), f.x.col(2).mean()};
  ADD_FAILURE() << "no frame at " << t;
  return {};
}

std::vector<ClothFrame> run(const std::string& name, const std::string& args,
                            nlohmann::json& summary) {
  const auto out = fresh_dir(name);
  const auto scene = source_dir() / "scenes" / "press_flatten.json";
  const auto r = run_cli("run " + scene.string() + " --quiet --out " + out.string() + " " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  summary = read_json(out / "summary.json");
  return cloth_frames(out);
}

}  // namespace

TEST(PressFlatten, TheHandPressesTheCrumpledNapkinFlat) {
  nlohmann::json s;
  const auto frames = run("press_flatten", "", s);
  expect_intact(s);
  // Crumpled before the hand arrives: a heap 6 cm high, 2.4 cm on average (one flat layer
  // lies at 5 mm, the repulsion thickness).
  const Heights heap = heights(frames, 1.5);
  EXPECT_GT(heap.max, 0.04);
  EXPECT_GT(heap.mean, 0.015);
  // Pressed: the palm's lower face comes down to 2 cm and no point of the napkin is above
  // 3.5 cm; it never passes through the cloth (expect_intact).
  double lowest_palm = 1.0;
  for (const auto& row : s["probes"]["palm"])
    lowest_palm = std::min(lowest_palm, row[3].get<double>());
  EXPECT_LT(lowest_palm, 0.025);
  EXPECT_LT(heights(frames, 2.5).max, 0.035);
  // Flat after the hand has gone: on average little more than one layer (measured 6 mm).
  EXPECT_LT(heights(frames, 3.6).mean, 0.009);
}

TEST(PressFlatten, TheKinematicHandPushesTheHeapAsideInsteadOfFlatteningIt) {
  // A kinematic hand with capped repulsion friction squeezes the heap out from under the
  // palm: it ends 2.2 cm high on average.
  nlohmann::json s;
  const auto frames = run("press_flatten_kinematic", "--coupling kinematic", s);
  expect_intact(s);
  EXPECT_GT(heights(frames, 3.6).mean, 0.015);
}
