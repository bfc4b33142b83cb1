/// The proximity search runs a step ahead, at the end of the last step beside the rigid step,
/// or beside the solve, whichever took less time (coupling/step.cpp): a step takes the
/// proximities found ahead only when it starts with the very meshes they were found among.
/// Stepping with the lookahead must be bitwise stepping without it, also when the cloth is moved
/// between steps (then the step searches anew).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "cli_runner.hpp"
#include "coupling/step.hpp"
#include "scene/compile.hpp"
#include "scene/load.hpp"

using namespace dexcloth;

namespace {

// Three napkins stacked on a table: cloth–cloth and cloth–table proximities from the start.
const std::filesystem::path kScene = test::source_dir() / "scenes" / "three_layers.json";
constexpr int kSteps = 40;
constexpr int kMovedAt = 20;  // the step before which the top napkin is lifted
constexpr double kLift = 1.5e-3;

struct Outcome {
  std::vector<Points> x, v;
  std::size_t most_proximities{};
  int lookaheads_taken{};
  bool lookahead_at_lift{};  // whether the search had run ahead of the lifted step
};

/// kSteps steps of the scene, the last napkin lifted by kLift before step kMovedAt. With
/// `drop_lookahead`, every step's lookahead is dropped before it, so that each step searches
/// beside its solve; else the search is made to run ahead (the other placement, beside the
/// solve, made to look costly: it is still tried every few steps).
Outcome run(bool drop_lookahead) {
  const scene::SceneSpec spec = scene::load_scene(kScene.string());
  scene::CompiledScene scene = scene::compile_scene(spec);
  coupling::WorldData& data = scene.data;
  Outcome out;
  for (int k = 0; k < kSteps; ++k) {
    if (k == kMovedAt) {
      data.cloths.back().x.col(2).array() += kLift;
      out.lookahead_at_lift = data.lookahead.ready;
    }
    if (drop_lookahead) data.lookahead.ready = false;
    data.lookahead.cost[1] = 1.0;  // seconds
    out.lookaheads_taken += data.lookahead.ready ? 1 : 0;
    coupling::step(scene.model, data);
    EXPECT_FALSE(data.lost) << "state lost at step " << k;
    out.most_proximities = std::max(out.most_proximities, data.contacts.proximities.size());
  }
  for (const cloth::ClothState& c : data.cloths) {
    out.x.push_back(c.x);
    out.v.push_back(c.v);
  }
  return out;
}

bool bitwise_equal(const Points& a, const Points& b) {
  return a.rows() == b.rows() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

}  // namespace

TEST(Lookahead, SteppingWithTheLookaheadIsBitwiseSteppingWithout) {
  const Outcome with = run(false), without = run(true);
  // The search ran ahead of most steps, the lifted one among them (whose start then differs
  // from the meshes searched), and the napkins were in contact.
  EXPECT_GE(with.lookaheads_taken, kSteps - 4);
  EXPECT_TRUE(with.lookahead_at_lift);
  EXPECT_EQ(without.lookaheads_taken, 0);
  EXPECT_GT(with.most_proximities, 100u);
  ASSERT_EQ(with.x.size(), 3u);
  ASSERT_EQ(without.x.size(), 3u);
  for (std::size_t c = 0; c < with.x.size(); ++c) {
    EXPECT_TRUE(bitwise_equal(with.x[c], without.x[c])) << "cloth " << c << " positions";
    EXPECT_TRUE(bitwise_equal(with.v[c], without.v[c])) << "cloth " << c << " velocities";
  }
}
