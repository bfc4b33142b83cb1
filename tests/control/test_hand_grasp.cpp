#include <gtest/gtest.h>

#include <algorithm>

#include "control/body_spec.hpp"

namespace dexcloth::control {
namespace {

using nlohmann::json;

const std::string kAssets = std::string(DEXCLOTH_SOURCE_DIR) + "/assets/hands";

/// Outcome of a pinch-and-lift run of the human hand on a dynamic sphere.
struct GraspRun {
  double rise{};            ///< sphere centre rise from its rest height to the end of the hold [m]
  double slip{};            ///< sphere displacement in the palm frame over the hold [m]
  Vec3 f_mean_W{Vec3::Zero()};  ///< contact force on the sphere averaged over the hold [N]
  double n_min{1e9};        ///< smallest summed normal force on the sphere during the hold [N]
  double max_depth{};       ///< deepest contact of any hand body, whole run [m]
  int table_contacts{};     ///< sphere–table contacts during the hold
  int hand_contacts{};      ///< hand–sphere contacts at the end
};

/// Thumb–index pinch of a sphere (radius r, mass m) on a table: fingers open until 0.3 s, close
/// to the "pinch" pose by 0.8 s, the wrist lifts 10 cm from 1.0 s to 1.5 s, then holds still;
/// the hold is measured from 1.6 s to 2.6 s.
GraspRun pinch_and_lift(double r, double m) {
  rigid::RigidWorld world;
  rigid::PropSpec table;
  table.name = "table";
  table.shape = rigid::PropSpec::Shape::plane;
  table.size = Vec3(1, 1, 0);
  world.add_prop(table);
  rigid::PropSpec ball;
  ball.name = "ball";
  ball.shape = rigid::PropSpec::Shape::sphere;
  ball.radius = r;
  ball.mass = m;
  ball.X_WP.translation() = Vec3(0, 0, r);
  world.add_prop(ball);
  // The pinch pose's pads meet at c = (0.09, 0.03, -0.06) in the palm frame; the wrist is placed
  // so that c is the sphere's centre: the pads close on its equator, and the PD, whose targets
  // lie r inside the surface, squeezes.
  const Vec3 c_P(0.09, 0.03, -0.06);
  const Vec3 wrist0 = Vec3(0.0, 0.0, r) - c_P;
  const json body = {
      {"name", "hand"},
      {"urdf", "human_hand.urdf"},
      {"poses", "human_hand.poses.json"},
      {"root", {{"translation", {wrist0.x(), wrist0.y(), wrist0.z()}}}},
      {"controller",
       {{"gravity_compensation", "full"},
        {"joint_pd", {{"kp", 2.0}, {"kd", 0.02},
                      {"keyframes", {{{"t", 0.0}, {"pose", "open"}}, {{"t", 0.3}, {"pose", "open"}}, {{"t", 0.8}, {"pose", "pinch"}}}}}},
        {"wrist", {{"keyframes", {{{"t", 0.0}, {"translation", {wrist0.x(), wrist0.y(), wrist0.z()}}},
                                  {{"t", 1.0}, {"translation", {wrist0.x(), wrist0.y(), wrist0.z()}}},
                                  {{"t", 1.5}, {"translation", {wrist0.x(), wrist0.y(), wrist0.z() + 0.1}}}}}}}}}};
  ErrorList errors;
  const BodySpec spec = parse_body_spec(body, "scene.json", "/bodies/0", kAssets, errors);
  EXPECT_TRUE(errors.empty()) << errors.to_string();
  BuiltBody hand = build_body(world, spec, "scene.json");
  const rigid::BodyId b = world.body("ball/body");
  const rigid::BodyId palm = world.root_body(hand.skeleton);
  const std::vector<rigid::BodyId> hand_bodies = world.skeleton_bodies(hand.skeleton);
  GraspRun run;
  const double z0 = world.com_W(b).z();
  Vec3 p_hold_start = Vec3::Zero();
  int samples = 0;
  const int steps = static_cast<int>(2.6 / world.time_step() + 0.5);
  for (int i = 0; i < steps; ++i) {
    hand.controllers.apply(world, world.time());
    world.step();
    for (const rigid::BodyId hb : hand_bodies) {
      for (const auto& c : world.contacts(hb)) run.max_depth = std::max(run.max_depth, c.depth);
    }
    const double t = world.time();
    const Vec3 p_P = world.pose_W(palm).inverse() * world.com_W(b);
    if (std::abs(t - 1.6) < 0.5 * world.time_step()) p_hold_start = p_P;
    if (t > 1.6 + 0.5 * world.time_step()) {
      run.f_mean_W += world.contact_force_W(b);
      run.n_min = std::min(run.n_min, world.normal_force_sum(b));
      for (const auto& c : world.contacts(b)) run.table_contacts += world.body_name(c.other) == "table/body" ? 1 : 0;
      ++samples;
    }
    if (i + 1 == steps) run.slip = (p_P - p_hold_start).norm();
  }
  run.f_mean_W /= samples;
  run.rise = world.com_W(b).z() - z0;
  for (const auto& c : world.contacts(b)) run.hand_contacts += world.body_skeleton(c.other) == hand.skeleton ? 1 : 0;
  return run;
}

TEST(HandGrasp, PinchLiftsASphereAndContactsCarryItsWeight) {
  // A 20 g sphere (r = 12 mm) and a 40 g one (r = 16 mm). Lifted: the centre rises ≥ 5 cm of the
  // wrist's 10 cm. Held: it moves < 2 mm in the palm frame over the 1 s hold. Newton on the
  // sphere at rest: the mean contact force equals its weight; the 2 % band allows a mean
  // acceleration of 0.02 g, far above what a held sphere shows, and the horizontal part is
  // below 2 % of the weight. Fingers stay out of the sphere and table: no contact deeper than
  // 2 mm (DART resolves penetration at ≤ 1 mm/s, so a deeper one would be a tunnelling pad).
  for (const auto& [r, m] : {std::pair{0.012, 0.02}, std::pair{0.016, 0.04}}) {
    SCOPED_TRACE("sphere r = " + std::to_string(r) + " m, m = " + std::to_string(m) + " kg");
    const GraspRun run = pinch_and_lift(r, m);
    const double w = m * 9.81;
    EXPECT_GT(run.rise, 0.05) << "sphere not lifted";
    EXPECT_LT(run.slip, 0.002);
    EXPECT_EQ(run.table_contacts, 0);
    EXPECT_GE(run.hand_contacts, 2);
    EXPECT_NEAR(run.f_mean_W.z(), w, 0.02 * w);
    EXPECT_LT(run.f_mean_W.head<2>().norm(), 0.02 * w);
    // The grasp is a squeeze: the normal forces exceed the weight throughout the hold.
    EXPECT_GT(run.n_min, w);
    EXPECT_LT(run.max_depth, 0.002);
  }
}

}  // namespace
}  // namespace dexcloth::control
