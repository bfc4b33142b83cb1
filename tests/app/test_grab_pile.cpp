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
  // A pile before the grab: both napkins crumpled on the table, the top one on the bottom one.
  for (const auto* napkin : {&p.bottom, &p.top}) {
    EXPECT_LT(heights_at(*napkin, 2.0).min, 0.005);
    EXPECT_LT(heights_at(*napkin, 2.0).max, 0.1);
  }
  // The top napkin comes up whole with the jaws: lowest point above 5 cm, mean above 10 cm at
  // the top of the lift (3.1 s). The pile's shape is chaotic (a last-bit change of the
  // arithmetic, such as another CPU's BLAS kernels, makes another pile): over five piles on one
  // machine (the top napkin turned 19.5, 20 or 20.5° or shifted 0.5 mm) it came up every time
  // and stayed to the end (lowest point 5.6–15 cm, mean 13–17 cm at 3.6 s), in three leaving
  // the bottom one on the table (or most of it) and in two with the bottom one caught in its
  // folds. On another (3 Dec evening) this pile's top napkin came up (lowest point 10.8 cm at
  // 3.1 s), slid 3 cm in the jaws from 3.3 s and fell out at 3.52 s, and of six other piles four
  // came up with the top napkin and two with the bottom one, all held to the end (README).
  // Which comes along, and the hold, are therefore not asserted.
  const Heights lifted = heights_at(p.top, 3.1);
  EXPECT_GT(lifted.min, 0.05);
  EXPECT_GT(lifted.mean, 0.1);
}

TEST(GrabPile, TheKinematicJawsCrushThePileAndLiftTheBottomNapkin) {
  // Kinematic jaws push the cloth through itself where they squeeze the pile, so the bottom
  // napkin, caught in the top one, comes up too. Over eight piles (5 Dec: this one with this
  // machine's BLAS kernels and with OPENBLAS_CORETYPE=Cooperlake, SkylakeX, Sandybridge; the
  // top napkin turned 19.5 or 20.5° or shifted 0.5 mm in x or y): 163–405 intersecting pairs,
  // the bottom napkin's mean height at 3.2 s 14.9–16.8 cm, the top one's 11.3–17.4 cm in seven
  // and 2.5 cm in one (turned 20.5°: left on the table). So the top napkin's lift is not
  // asserted. The bottom one's is chance too, only less often: a build whose hinge assembly
  // rounded differently (not merged, 5 Dec) lifted neither napkin (2.0–2.5 cm).
  const Pile p = run("grab_pile_kinematic", "--coupling kinematic --duration 3.2");
  EXPECT_FALSE(p.summary["nan"].get<bool>());
  EXPECT_GT(p.summary["intersections_max"].get<int>(), 0);
  EXPECT_GT(heights_at(p.bottom, 3.2).mean, 0.1);
}
