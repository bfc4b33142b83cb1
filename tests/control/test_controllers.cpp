#include <gtest/gtest.h>

#include "control/controllers.hpp"

namespace dexcloth::control {
namespace {

const std::string kHand = std::string(DEXCLOTH_SOURCE_DIR) + "/assets/hands/human_hand.urdf";

TEST(Controllers, JointPdReachesKeyframedPoseAndLimitsHold) {
  // Fixed palm, gravity compensated fingers; PD toward a pose reached at t = 0.5 s. After 1 s
  // every joint of every finger is within 0.02 rad of its target; targets beyond the limits
  // (index PIP above, middle DIP below) are clamped by the controller and stop at the limit
  // (0.01 rad). A joint torque pushing past
  // a limit (ring PIP, 0.2 N·m, no PD on it) is held by the limit constraint, and its
  // neighbours stay on their targets: the limit reaction cancels the torque at the joint, so at
  // rest nothing is left to move them. No joint ever passes a limit by more than 0.01 rad.
  rigid::RigidWorld world;
  rigid::UrdfOptions options;
  options.fixed_root = true;
  const rigid::SkeletonId hand = world.add_urdf("hand", kHand, options);
  const int n = world.num_dofs(hand);
  ASSERT_EQ(n, 27);
  const Eigen::VectorXd lo = world.position_lower_limits(hand), hi = world.position_upper_limits(hand);
  Eigen::VectorXd target = lo + 0.6 * (hi - lo);
  const int pip = world.dof_index(hand, "index_pip");
  const int dip = world.dof_index(hand, "middle_dip");
  target[pip] = hi[pip] + 0.5;  // beyond the upper limit
  target[dip] = lo[dip] - 0.5;  // beyond the lower limit
  ControllerSet controllers;
  controllers.add(std::make_unique<GravityCompensation>(hand, false));
  const int ring_pip = world.dof_index(hand, "ring_pip");
  controllers.add(std::make_unique<JointForceController>(hand, std::vector<int>{ring_pip},
      std::vector<VectorKeyframe>{{0.0, Eigen::VectorXd::Constant(1, 0.2)}}, true));
  std::vector<int> pd_dofs;
  for (int i = 0; i < n; ++i) {
    if (i != ring_pip) pd_dofs.push_back(i);
  }
  Eigen::VectorXd pd_target(static_cast<Eigen::Index>(pd_dofs.size()));
  for (std::size_t k = 0; k < pd_dofs.size(); ++k) pd_target[static_cast<Eigen::Index>(k)] = target[pd_dofs[k]];
  world.set_joint_pd(hand, ring_pip, 0.0, 0.02, 0.0);
  controllers.add(std::make_unique<JointPdController>(hand, pd_dofs,
      std::vector<VectorKeyframe>{{0.0, Eigen::VectorXd::Zero(n - 1)}, {0.5, pd_target}},
      Eigen::VectorXd::Constant(n - 1, 2.0), Eigen::VectorXd::Constant(n - 1, 0.02)));
  double worst_violation = 0.0;
  for (int i = 0; i < 200; ++i) {
    controllers.apply(world, world.time());
    world.step();
    const Eigen::VectorXd q = world.positions(hand);
    worst_violation = std::max({worst_violation, (q - hi).maxCoeff(), (lo - q).maxCoeff()});
  }
  const Eigen::VectorXd q = world.positions(hand);
  EXPECT_NEAR(q[ring_pip], hi[ring_pip], 0.01);
  int ring_joints = 0;
  for (int i : pd_dofs) {
    ring_joints += world.dof_joint(hand, i).rfind("ring_", 0) == 0 ? 1 : 0;
    const double expected = std::clamp(target[i], lo[i], hi[i]);
    EXPECT_NEAR(q[i], expected, i == pip || i == dip ? 0.01 : 0.02) << world.dof_name(hand, i) << " target " << target[i];
  }
  EXPECT_EQ(ring_joints, 5);  // ring CMC (2), MCP (2), DIP are checked
  EXPECT_LT(worst_violation, 0.01);
}

TEST(Controllers, JacobianTransposePressMatchesCommandedForce) {
  // A free hand lies on its back (palm up) on a table; τ = Jᵀ F (paper eq. 13) with F = 3 N down
  // at the centre of the back of the palm box, gravity fully compensated, fingers held by PD. At
  // rest the summed normal force on the table equals |F| (5 %).
  rigid::RigidWorld world;
  rigid::PropSpec table;
  table.name = "table";
  table.shape = rigid::PropSpec::Shape::plane;
  table.size = Vec3(1, 1, 0);
  world.add_prop(table);
  rigid::UrdfOptions options;
  options.X_WR.linear() = Eigen::AngleAxisd(3.14159265358979, Vec3::UnitX()).toRotationMatrix();
  options.X_WR.translation() = Vec3(0, 0, 0.0135);
  const rigid::SkeletonId hand = world.add_urdf("hand", kHand, options);
  const rigid::BodyId palm = world.root_body(hand);
  const double F = 3.0;
  ControllerSet controllers;
  controllers.add(std::make_unique<GravityCompensation>(hand, false));
  controllers.add(std::make_unique<PointForceController>(palm, Vec3(0.052, 0.010, 0.013),
      std::vector<VectorKeyframe>{{0.0, Eigen::Vector3d(0, 0, 0)}, {0.3, Eigen::Vector3d(0, 0, -F)}}));
  for (int i = 6; i < world.num_dofs(hand); ++i) world.set_joint_pd(hand, i, 2.0, 0.02, 0.0);
  double f_n = 0.0;
  int samples = 0;
  for (int i = 0; i < 300; ++i) {
    controllers.apply(world, world.time());
    world.step();
    if (world.time() > 1.0) {
      f_n += world.normal_force_sum(world.body("table/body"));
      ++samples;
    }
  }
  EXPECT_NEAR(f_n / samples, F, 0.05 * F);
}

TEST(Controllers, WristFollowsKeyframedPose) {
  // Free hand, full gravity compensation, wrist PD toward a pose 10 cm up and 30° about z,
  // reached at 0.5 s: after 1 s within 2 mm and 0.02 rad.
  rigid::RigidWorld world;
  const rigid::SkeletonId hand = world.add_urdf("hand", kHand);
  const rigid::BodyId palm = world.root_body(hand);
  Eigen::Isometry3d goal = Eigen::Isometry3d::Identity();
  goal.linear() = Eigen::AngleAxisd(0.5236, Vec3::UnitZ()).toRotationMatrix();
  goal.translation() = Vec3(0.0, 0.0, 0.1);
  ControllerSet controllers;
  controllers.add(std::make_unique<GravityCompensation>(hand, false));
  controllers.add(std::make_unique<WristController>(palm, Vec3::Zero(),
      std::vector<rigid::PoseKeyframe>{{0.0, Eigen::Isometry3d::Identity()}, {0.5, goal}}, CartesianGains{}));
  for (int i = 0; i < world.num_dofs(hand); ++i) {
    if (i >= 6) world.set_joint_pd(hand, i, 2.0, 0.02, 0.0);
  }
  for (int i = 0; i < 200; ++i) {
    controllers.apply(world, world.time());
    world.step();
  }
  const Eigen::Isometry3d X = world.pose_W(palm);
  EXPECT_LT((X.translation() - goal.translation()).norm(), 2e-3);
  EXPECT_LT(Eigen::AngleAxisd(X.linear() * goal.linear().transpose()).angle(), 0.02);
}

}  // namespace
}  // namespace dexcloth::control
