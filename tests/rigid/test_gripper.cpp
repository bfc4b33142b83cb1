#include <gtest/gtest.h>

#include "rigid/world.hpp"
#include "test_helpers.hpp"

namespace dexcloth::rigid {
namespace {

using test::add_box;
using test::add_table;
using test::asset;

/// Gripper squeezes a box with joint force N on each jaw, then lifts 10 cm over 1 s and holds
/// 0.5 s. Returns how far the box rose [m].
double squeeze_and_lift(double jaw_force, double mu, double box_mass) {
  RigidWorld world;
  add_table(world, mu);
  const SkeletonId box = add_box(world, "box", Vec3(0.05, 0.06, 0.05), box_mass, Vec3(0, 0, 0.025), mu);
  UrdfOptions options;
  options.fixed_root = true;
  options.X_WR.translation() = Vec3(0, 0, 0.1);
  options.friction = mu;
  const SkeletonId g = world.add_urdf("gripper", asset("gripper.urdf"), options);
  const int lift = world.dof_index(g, "lift");
  const int left = world.dof_index(g, "left_finger");
  const int right = world.dof_index(g, "right_finger");
  const BodyId box_body = world.root_body(box);
  const double z0 = world.com_W(box_body).z();
  const double h = world.time_step();
  for (int i = 0; i < 400; ++i) {
    const double t = i * h;
    // Lift: stiff implicit PD (supports the gripper's weight with < 1 mm sag).
    const double lift_target = t < 0.3 ? 0.0 : std::min(0.1, 0.1 * (t - 0.3) / 1.0);
    world.set_joint_pd(g, lift, 5.0e4, 2.0e3, lift_target);
    // Jaws: constant closing force.
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(world.num_dofs(g));
    tau[left] = jaw_force;
    tau[right] = jaw_force;
    world.add_forces(g, tau);
    world.step();
  }
  return world.com_W(box_body).z() - z0;
}

TEST(Gripper, LiftsIffTwoMuNExceedsWeight) {
  // Coulomb: the box is held iff 2 μ N ≥ m g. Sweep N at 0.9 and 1.1 of the threshold (5 %
  // accuracy needed to separate them); lifted means it rose ≥ 8 of the 10 cm, not lifted < 1 cm.
  const double mu = 0.5;
  const double m = 0.2;
  const double threshold = m * 9.81 / (2.0 * mu);
  EXPECT_GT(squeeze_and_lift(1.1 * threshold, mu, m), 0.08);
  EXPECT_LT(squeeze_and_lift(0.9 * threshold, mu, m), 0.01);
  // A different μ moves the threshold accordingly.
  const double mu2 = 0.8;
  const double threshold2 = m * 9.81 / (2.0 * mu2);
  EXPECT_GT(squeeze_and_lift(1.05 * threshold2, mu2, m), 0.08);
  EXPECT_LT(squeeze_and_lift(0.95 * threshold2, mu2, m), 0.01);
}

TEST(Gripper, JawContactForceEqualsCommandedJointForce) {
  // At rest (before lifting) each jaw's contact normal force equals its joint force (2 %).
  RigidWorld world;
  add_table(world);
  add_box(world, "box", Vec3(0.05, 0.06, 0.05), 0.2, Vec3(0, 0, 0.025));
  UrdfOptions options;
  options.fixed_root = true;
  options.X_WR.translation() = Vec3(0, 0, 0.1);
  const SkeletonId g = world.add_urdf("gripper", asset("gripper.urdf"), options);
  const double N = 7.0;
  for (int i = 0; i < 200; ++i) {
    world.set_joint_pd(g, world.dof_index(g, "lift"), 5.0e4, 2.0e3, 0.0);
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(world.num_dofs(g));
    tau[world.dof_index(g, "left_finger")] = N;
    tau[world.dof_index(g, "right_finger")] = N;
    world.add_forces(g, tau);
    world.step();
  }
  EXPECT_NEAR(world.normal_force_sum(world.body("gripper/left_jaw")), N, 0.02 * N);
  EXPECT_NEAR(world.normal_force_sum(world.body("gripper/right_jaw")), N, 0.02 * N);
  EXPECT_NEAR(world.contact_force_W(world.body("gripper/left_jaw")).y(), N, 0.02 * N);
}

}  // namespace
}  // namespace dexcloth::rigid
