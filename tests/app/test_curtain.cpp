/// A curtain on its rod (paper Table 1, "Curtain"): sliding handles keep cloth vertices on a line
/// and leave them free along it, checked against the analytic motion of a strip on a tilted-
/// gravity rod; then scenes/curtain.json, a gripper pulling a 16k-triangle curtain along its rod
/// by friction alone, in both couplings.
#include <gtest/gtest.h>

#include <cmath>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

/// Coordinate i (1: x, 2: y, 3: z) of probe `p`'s sample k.
double at(const nlohmann::json& s, const std::string& p, std::size_t k, int i) {
  return s["probes"][p][k][static_cast<std::size_t>(i)].get<double>();
}

}  // namespace

TEST(RodSlide, AStripOnAFrictionlessRodTranslatesAlongItAtGSinTheta) {
  // Gravity tilted 30° toward +x: every vertex gets a = g sin 30° along the rod, which holds
  // the rest, so the strip translates rigidly along x. Implicit Euler from rest gives
  // v_n = n·h·a and x_n = h²·a·n(n+1)/2 exactly (internal forces of a translation vanish).
  const auto s = run_file(source_dir() / "tests" / "app" / "data" / "rod_slide.json", "rod").summary;
  const double a = 9.81 * 0.5, h = s["dt"].get<double>();
  const auto& top = s["probes"]["top"];
  ASSERT_GE(top.size(), 10u);
  double x_end = 0.0;
  for (std::size_t k = 0; k < top.size(); ++k) {
    const double n = std::round(top[k][0].get<double>() / h);
    const double expected = a * h * h * n * (n + 1.0) / 2.0;
    // On the rod: free along x, held across it.
    EXPECT_NEAR(at(s, "top", k, 1) - at(s, "top", 0, 1), expected, 1e-9) << "t " << n * h;
    EXPECT_NEAR(at(s, "top", k, 2), at(s, "top", 0, 2), 1e-12);
    EXPECT_NEAR(at(s, "top", k, 3), at(s, "top", 0, 3), 1e-12);
    // So does the middle of the bottom edge (no shear from a uniform acceleration; by symmetry
    // no sideways sag either).
    EXPECT_NEAR(at(s, "bottom", k, 1) - at(s, "bottom", 0, 1), expected, 1e-9);
    x_end = expected;
  }
  EXPECT_GT(x_end, 0.2);  // 0.3 s at 4.9 m/s²: 22 cm
  expect_intact(s);
}

TEST(Curtain, AGripperPullsTheCurtainAlongItsRodByFrictionAlone) {
  const auto s = run_file(source_dir() / "scenes" / "curtain.json", "curtain_bai_liu").summary;
  expect_intact(s);
  const std::size_t last = s["probes"]["jaw"].size() - 1;
  // The wrist pulls 25 cm along the rod (x) from 0.8 s to 2.0 s.
  const double pulled = at(s, "jaw", last, 1) - at(s, "jaw", 0, 1);
  EXPECT_NEAR(pulled, 0.25, 0.01);
  // The cloth between the jaws moves with them: < 2 mm relative to the jaw from the squeeze
  // (0.7 s) to the end, while the jaw travels 25 cm.
  EXPECT_LT(relative_motion(s, "gripped", "jaw", 0.72, 2.3), 2e-3);
  // The whole curtain slides on its rod: its middle ring and trailing edge follow the pull
  // (within 10 %: the trailing cloth lags and swings back after the stop).
  for (const char* p : {"ring", "far_edge"})
    EXPECT_NEAR(at(s, p, last, 1) - at(s, p, 0, 1), pulled, 0.1 * pulled) << p;
  // The rings stay on the rod: 0.9 m high, in the curtain's plane.
  for (std::size_t k = 0; k <= last; ++k) {
    EXPECT_NEAR(at(s, "ring", k, 3), 0.9, 1e-9);
    EXPECT_NEAR(at(s, "ring", k, 2), 0.0, 1e-9);
  }
}

TEST(Curtain, TheKinematicBaselineLetsTheCurtainSlipThroughTheJaws) {
  // ARCSim-style coupling: the jaws are kinematic obstacles and friction comes from the
  // repulsion with its per-step cap, so the squeeze does not hold the cloth: it slips through
  // the jaws during the pull (13 mm by 1.6 s) and, on a frictionless rod, runs on ahead.
  const auto s = run_file(source_dir() / "scenes" / "curtain.json", "curtain_kinematic",
                          "--coupling kinematic --duration 1.6").summary;
  expect_intact(s);
  EXPECT_GT(relative_motion(s, "gripped", "jaw", 0.72, 1.6), 5e-3);
}
