#include <gtest/gtest.h>

#include "rigid/ik.hpp"
#include "test_helpers.hpp"

namespace dexcloth::rigid {
namespace {

TEST(Ik, ThumbAndIndexTipsMeetAtAPinchPoint) {
  // Targets reachable by construction: positions of the tips at a known joint configuration.
  RigidWorld world;
  const SkeletonId hand = world.add_urdf("hand", test::asset("human_hand.urdf"));
  const BodyId index = world.body("hand/index_distal");
  const BodyId thumb = world.body("hand/thumb_distal");
  const Vec3 index_tip(0.013, 0.0, -0.006);
  const Vec3 thumb_tip(0.017, 0.0, -0.007);
  Eigen::VectorXd q = world.positions(hand);
  const Eigen::VectorXd q_open = q;
  const Eigen::VectorXd lo = world.position_lower_limits(hand), hi = world.position_upper_limits(hand);
  for (int i = 6; i < q.size(); ++i) q[i] = lo[i] + 0.3 * (hi[i] - lo[i]);
  world.set_positions(hand, q);
  const Vec3 a = world.point_W(index, index_tip), b = world.point_W(thumb, thumb_tip);
  world.set_positions(hand, q_open);
  const IkResult r = solve_ik(world, hand, {{index, index_tip, a}, {thumb, thumb_tip, b}});
  EXPECT_TRUE(r.converged) << r.max_error;
  EXPECT_LT(r.max_error, 1e-4);
  // The world's state is restored; the solution respects the limits and reaches the targets.
  EXPECT_TRUE(world.positions(hand).isApprox(q_open));
  EXPECT_TRUE(((r.q - lo).array() >= -1e-12).all() && ((hi - r.q).array() >= -1e-12).all());
  world.set_positions(hand, r.q);
  EXPECT_LT((world.point_W(index, index_tip) - a).norm(), 1e-4);
  EXPECT_LT((world.point_W(thumb, thumb_tip) - b).norm(), 1e-4);
  // The root did not move.
  EXPECT_TRUE(r.q.head<6>().isApprox(q_open.head<6>()));
}

}  // namespace
}  // namespace dexcloth::rigid
