/// The 33-DOF hand picks a napkin off a table by a key pinch, lifts it and carries it around
/// (scenes/pinch_napkin.json, paper Fig. 2 "Moving" at napkin size).
#include <gtest/gtest.h>

#include "cli_runner.hpp"

using namespace dexcloth::test;

TEST(PinchNapkin, TheHandCarriesTheNapkinByFrictionAloneWithoutIntersections) {
  const auto s = run_scene("pinch_napkin");
  // From the handle's release (1.4 s) to the end the napkin hangs from the pads alone while the
  // wrist lifts it 15 cm and carries it 20 cm, turning 60°: the pinched vertex rises with the
  // hand and stays between the pads. A dropped napkin falls below where it was let go. The
  // outcome is chaotic (the scene path's spelling changes it): over 16 runs with the napkin
  // shifted ≤ 0.3 mm and two path spellings, all carried it, the pinched vertex rose 14.7–15.0 cm
  // and stayed within 5.9–8.3 mm of the pad centres (without rigid substeps: 8.9–14.1 cm and
  // 13–62 mm, the thumb crossing the patch in single steps). Since normal forces are shares of
  // each body's resultant (no longer counted twice near a patch): 8 of 8 runs carried it,
  // 14.0–14.9 cm, 5.9–14.2 mm. Since squeezed vertices move with the pads along the normal in
  // the implicit solve: 8 of 8, 14.9–15.0 cm, 5.8–7.1 mm; with reweighted least-squares steps
  // in the friction solve: 8 of 8, 15.0 cm, 6.2–6.8 mm.
  const Carry c = carry(s, "pinched", 1.4);
  EXPECT_LT(c.farthest, 0.03);
  EXPECT_GT(c.rise, 0.12);
  expect_intact(s);
}
