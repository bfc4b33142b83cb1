#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "rigid/world.hpp"
#include "test_helpers.hpp"

namespace dexcloth::rigid {
namespace {

using test::add_box;
using test::add_table;
using test::asset;

/// A folder for this suite's input files, under the build tree.
std::filesystem::path output_dir() {
  const auto dir = std::filesystem::path(DEXCLOTH_BINARY_DIR) / "test_output" / "rigid";
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(RigidWorld, HumanHandHas33DofsAdultMassAndCapsules) {
  RigidWorld world;
  const SkeletonId hand = world.add_urdf("hand", asset("human_hand.urdf"));
  EXPECT_EQ(world.num_dofs(hand), 33);
  EXPECT_EQ(world.root_dofs(hand), 6);
  // Adult hand ≈ 0.4 kg (±15 %).
  EXPECT_NEAR(world.mass(hand), 0.4, 0.06);
  // Wrist crease to middle fingertip ≈ 19 cm in the open pose (distal capsule tip: 13 mm cylinder
  // + 8.2 mm cap beyond the DIP joint).
  const Vec3 tip = world.point_W(world.body("hand/middle_distal"), Vec3(0.013 + 0.0082, 0, 0));
  const Vec3 wrist = world.point_W(world.body("hand/palm"), Vec3::Zero());
  EXPECT_NEAR((tip - wrist).norm(), 0.19, 0.01);
  // Cylinders were loaded as capsules: the exported distal mesh reaches the tip cap.
  std::vector<ObstacleMesh> meshes;
  world.export_obstacle_meshes(meshes);
  const auto it = std::find_if(meshes.begin(), meshes.end(),
                               [](const auto& m) { return m.name == "hand/middle_distal"; });
  ASSERT_NE(it, meshes.end());
  double reach = 0.0;
  for (Eigen::Index i = 0; i < it->x.rows(); ++i)
    reach = std::max(reach, (Vec3(it->x.row(i).transpose()) - wrist).norm());
  EXPECT_NEAR(reach, 0.189, 0.002);
}

TEST(RigidWorld, MissingAndMalformedUrdfNameTheFile) {
  RigidWorld world;
  try {
    world.add_urdf("hand", "/nonexistent/hand.urdf");
    FAIL() << "missing file accepted";
  } catch (const InputRejected& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/hand.urdf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos) << e.what();
  }
  const std::string bad = (output_dir() / "bad.urdf").string();
  std::ofstream(bad) << "<robot name=\"x\"><link name=\"a\"></robot";
  try {
    world.add_urdf("bad", bad);
    FAIL() << "malformed URDF accepted";
  } catch (const InputRejected& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("malformed"), std::string::npos) << e.what();
  }
}

TEST(RigidWorld, AMeshPropWithNonFiniteOrNoTrianglesIsRejectedNamingTheFile) {
  // The mesh reader takes "nan" and "inf" for numbers; a body made of them has no surface.
  const auto dir = output_dir();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"},
      {"inf.obj", "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n"},
      {"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n"}};
  for (const auto& [name, text] : cases) {
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    RigidWorld world;
    PropSpec prop;
    prop.name = "bowl";
    prop.shape = PropSpec::Shape::mesh;
    prop.mesh_path = path;
    try {
      world.add_prop(prop);
      FAIL() << name << " accepted";
    } catch (const InputRejected& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bowl"), std::string::npos) << e.what();
    }
  }
}

TEST(RigidWorld, UnknownBodyOrJointNamesTheFile) {
  RigidWorld world;
  const SkeletonId hand = world.add_urdf("hand", asset("human_hand.urdf"));
  try {
    world.body("hand/sixth_finger");
    FAIL() << "unknown body accepted";
  } catch (const InputRejected& e) {
    EXPECT_NE(std::string(e.what()).find("human_hand.urdf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sixth_finger"), std::string::npos) << e.what();
  }
  EXPECT_THROW(world.dof_index(hand, "index_pip2"), InputRejected);
  EXPECT_THROW(world.add_urdf("hand", asset("gripper.urdf")), InputRejected);  // duplicate name
}

TEST(RigidWorld, BoxRestingOnTableFeelsItsWeight) {
  // Contact bookkeeping: Σ f_W on a resting box balances m g (1 %), normals point into the box.
  RigidWorld world;
  add_table(world);
  const double m = 0.3;
  add_box(world, "box", Vec3(0.1, 0.08, 0.06), m, Vec3(0, 0, 0.03));
  for (int i = 0; i < 200; ++i) world.step();
  const BodyId box = world.body("box/body");
  ASSERT_FALSE(world.contacts(box).empty());
  const Vec3 f = world.contact_force_W(box);
  EXPECT_NEAR(f.z(), m * 9.81, 0.01 * m * 9.81);
  EXPECT_NEAR(f.head<2>().norm(), 0.0, 1e-3);
  EXPECT_NEAR(world.normal_force_sum(box), m * 9.81, 0.01 * m * 9.81);
  for (const auto& c : world.contacts(box)) EXPECT_GT(c.n_W.z(), 0.99);
  // The table sees the opposite: normals point down into the table.
  const BodyId table = world.body("table/body");
  EXPECT_NEAR(world.contact_force_W(table).z(), -m * 9.81, 0.01 * m * 9.81);
  for (const auto& c : world.contacts(table)) EXPECT_LT(c.n_W.z(), -0.99);
}

TEST(RigidWorld, FreeBodyStateRoundTrips) {
  RigidWorld world;
  const SkeletonId s = add_box(world, "box", Vec3(0.1, 0.1, 0.1), 1.0, Vec3::Zero());
  const BodyId b = world.root_body(s);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  X.translation() = Vec3(0.1, -0.2, 0.3);
  const Vec3 v(0.5, -0.1, 0.2);
  const Vec3 w(1.0, 2.0, -0.5);
  world.set_free_body_state(b, X, v, w);
  EXPECT_TRUE(world.pose_W(b).isApprox(X, 1e-12));
  EXPECT_TRUE(world.point_velocity_W(b, Vec3::Zero()).isApprox(v, 1e-12));
  EXPECT_TRUE(world.angular_velocity_W(b).isApprox(w, 1e-12));
  // Point velocity: v + ω × r.
  const Vec3 p_B(0.05, 0.0, 0.0);
  EXPECT_TRUE(world.point_velocity_W(b, p_B).isApprox(v + w.cross(X.linear() * p_B), 1e-12));
}

TEST(RigidWorld, PointJacobianMatchesFiniteDifferences) {
  RigidWorld world;
  const SkeletonId hand = world.add_urdf("hand", asset("human_hand.urdf"));
  Eigen::VectorXd q = world.positions(hand);
  for (int i = 6; i < q.size(); ++i)
    q[i] = 0.5 * (world.position_lower_limits(hand)[i] + world.position_upper_limits(hand)[i]);
  world.set_positions(hand, q);
  const BodyId tip = world.body("hand/index_distal");
  const Vec3 p_B(0.02, 0.0, -0.005);
  const Eigen::MatrixXd J = world.point_jacobian_W(tip, p_B);
  ASSERT_EQ(J.rows(), 3);
  ASSERT_EQ(J.cols(), 33);
  // Joint DOFs (the free root's DOFs are exponential coordinates: compare those via velocity).
  const double eps = 1e-6;
  for (int i = 6; i < 33; ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += eps;
    qm[i] -= eps;
    world.set_positions(hand, qp);
    const Vec3 xp = world.point_W(tip, p_B);
    world.set_positions(hand, qm);
    const Vec3 xm = world.point_W(tip, p_B);
    EXPECT_LT(((xp - xm) / (2 * eps) - J.col(i)).norm(), 1e-6) << world.dof_name(hand, i);
  }
  world.set_positions(hand, q);
  Eigen::VectorXd qd = Eigen::VectorXd::Random(33);
  world.set_velocities(hand, qd);
  EXPECT_LT((world.point_velocity_W(tip, p_B) - J * qd).norm(), 1e-9);
}

TEST(RigidWorld, KeyframedPropMovesAndExportsItsVelocity) {
  RigidWorld world;
  PropSpec prop;
  prop.name = "slider";
  prop.shape = PropSpec::Shape::sphere;
  prop.radius = 0.05;
  Eigen::Isometry3d X1 = Eigen::Isometry3d::Identity();
  X1.translation() = Vec3(0.2, 0.0, 0.0);
  prop.motion = {{0.0, Eigen::Isometry3d::Identity()}, {1.0, X1}};
  world.add_prop(prop);
  const BodyId b = world.body("slider/body");
  for (int i = 0; i < 100; ++i) world.step();  // t = 0.5: half way, peak smoothstep speed 1.5·0.2
  EXPECT_NEAR(world.pose_W(b).translation().x(), 0.1, 1e-9);
  std::vector<ObstacleMesh> meshes;
  world.export_obstacle_meshes(meshes);
  ASSERT_EQ(meshes.size(), 1u);
  for (Eigen::Index i = 0; i < meshes[0].v.rows(); ++i) EXPECT_NEAR(meshes[0].v(i, 0), 0.3, 1e-9);
}

}  // namespace
}  // namespace dexcloth::rigid
