/// Valid scenes parse to the expected values: explicit values kept, defaults applied, paths
/// resolved against the scene file's folder.
#include <gtest/gtest.h>

#include <filesystem>

#include "scene/load.hpp"
#include "scene_test_util.hpp"

namespace dexcloth::scene::test {
namespace {

TEST(LoadScene, FullSceneHasEveryValue) {
  const std::string path = data_path("full.json");
  const SceneSpec s = load_scene(path);
  const std::string obj = data_path("meshes/square.obj");

  // Top level.
  EXPECT_EQ(s.file, path);
  EXPECT_EQ(s.name, "full");
  EXPECT_EQ(s.description, "pinch a grid cloth, drape an OBJ cloth");
  EXPECT_DOUBLE_EQ(s.dt, 0.002);
  EXPECT_DOUBLE_EQ(s.duration, 2.5);
  EXPECT_DOUBLE_EQ(s.frame_rate, 25.0);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.8));
  EXPECT_EQ(s.coupling.mode, "kinematic");
  EXPECT_DOUBLE_EQ(s.coupling.cluster_distance, 0.05);
  EXPECT_DOUBLE_EQ(s.coupling.cluster_normal_deg, 15.0);
  EXPECT_DOUBLE_EQ(s.coupling.cluster_offset, 0.002);
  EXPECT_EQ(s.coupling.rigid_substeps, 3);
  EXPECT_DOUBLE_EQ(s.collision.thickness, 0.004);
  EXPECT_FALSE(s.collision.self_collision);
  EXPECT_EQ(s.solver.factor_precision, "single");
  EXPECT_DOUBLE_EQ(s.solver.refine_tolerance, 1e-6);

  // Grid cloth with material, transform and two handles.
  ASSERT_EQ(s.cloths.size(), 2u);
  const ClothSpec& sheet = s.cloths[0];
  EXPECT_EQ(sheet.name, "sheet");
  ASSERT_TRUE(sheet.mesh.grid_size && sheet.mesh.grid_resolution);
  EXPECT_EQ(*sheet.mesh.grid_size, (std::array<double, 2>{0.5, 0.4}));
  EXPECT_EQ(*sheet.mesh.grid_resolution, (std::array<int, 2>{11, 9}));
  EXPECT_FALSE(sheet.mesh.obj_path);
  EXPECT_EQ(sheet.transform.translation, Vec3(0, 0, 0.3));
  EXPECT_EQ(sheet.transform.rotation_deg, Vec3(90, 0, 45));
  const MaterialSpec& m = sheet.material;
  EXPECT_DOUBLE_EQ(m.density, 0.2);
  EXPECT_DOUBLE_EQ(m.youngs_modulus, 1e6);
  EXPECT_DOUBLE_EQ(m.poisson, 0.25);
  EXPECT_DOUBLE_EQ(m.thickness, 0.0005);
  EXPECT_DOUBLE_EQ(m.bending_stiffness, 2e-6);
  EXPECT_DOUBLE_EQ(m.damping, 0.01);
  EXPECT_DOUBLE_EQ(m.friction, 0.7);
  ASSERT_TRUE(m.strain_limits);
  EXPECT_EQ(*m.strain_limits, (std::array<double, 2>{0.9, 1.1}));
  ASSERT_EQ(sheet.handles.size(), 2u);
  EXPECT_EQ(sheet.handles[0].vertices, (std::vector<int>{0, 10}));
  EXPECT_FALSE(sheet.handles[0].box);
  ASSERT_EQ(sheet.handles[0].motion.size(), 2u);
  EXPECT_DOUBLE_EQ(sheet.handles[0].motion[1].t, 1.5);
  EXPECT_EQ(sheet.handles[0].motion[1].translation, Vec3(0, 0, 0.1));
  ASSERT_TRUE(sheet.handles[1].box);
  EXPECT_EQ((*sheet.handles[1].box)[0], Vec3(-1, -1, -1));
  EXPECT_EQ((*sheet.handles[1].box)[1], Vec3(1, 1, 0.3));
  EXPECT_TRUE(sheet.handles[1].vertices.empty());
  EXPECT_FALSE(sheet.handles[0].slide);

  // OBJ cloth: path resolved, every material value defaulted.
  const ClothSpec& shirt = s.cloths[1];
  ASSERT_TRUE(shirt.mesh.obj_path);
  EXPECT_TRUE(std::filesystem::equivalent(*shirt.mesh.obj_path, obj));
  EXPECT_EQ(*shirt.mesh.obj_path, std::filesystem::path(obj).lexically_normal().string());
  EXPECT_FALSE(shirt.mesh.grid_size);
  EXPECT_DOUBLE_EQ(shirt.material.density, MaterialSpec{}.density);
  EXPECT_DOUBLE_EQ(shirt.material.youngs_modulus, MaterialSpec{}.youngs_modulus);
  EXPECT_FALSE(shirt.material.strain_limits);
  EXPECT_EQ(shirt.transform.translation, Vec3::Zero());

  // Obstacles: every shape kind, motion with rotation, friction default.
  ASSERT_EQ(s.obstacles.size(), 5u);
  using Kind = ShapeSpec::Kind;
  EXPECT_EQ(s.obstacles[0].shape.kind, Kind::box);
  EXPECT_EQ(s.obstacles[0].shape.box_size, Vec3(1, 1, 0.05));
  EXPECT_DOUBLE_EQ(s.obstacles[0].friction, 0.3);
  ASSERT_EQ(s.obstacles[0].motion.size(), 2u);
  EXPECT_EQ(s.obstacles[0].motion[1].translation, Vec3(0.1, 0, 0));
  EXPECT_EQ(s.obstacles[0].motion[1].rotation_deg, Vec3(0, 0, 30));
  EXPECT_EQ(s.obstacles[1].shape.kind, Kind::sphere);
  EXPECT_DOUBLE_EQ(s.obstacles[1].shape.radius, 0.1);
  EXPECT_EQ(s.obstacles[1].transform.translation, Vec3(0, 0, 1));
  EXPECT_DOUBLE_EQ(s.obstacles[1].friction, 0.5);
  EXPECT_EQ(s.obstacles[2].shape.kind, Kind::capsule);
  EXPECT_DOUBLE_EQ(s.obstacles[2].shape.radius, 0.02);
  EXPECT_DOUBLE_EQ(s.obstacles[2].shape.length, 0.3);
  EXPECT_EQ(s.obstacles[3].shape.kind, Kind::plane);
  EXPECT_EQ(s.obstacles[4].shape.kind, Kind::obj);
  EXPECT_TRUE(std::filesystem::equivalent(s.obstacles[4].shape.obj_path, obj));

  // Probes: cloth and body, point defaulting to the body origin.
  ASSERT_EQ(s.probes.size(), 3u);
  EXPECT_EQ(s.probes[0].cloth, "sheet");
  EXPECT_EQ(s.probes[0].near, Vec3(0.25, 0.2, 0.3));
  EXPECT_TRUE(s.probes[0].body.empty());
  EXPECT_EQ(s.probes[1].body, "hand/index_tip");
  EXPECT_EQ(s.probes[1].point, Vec3(0, 0, 0.01));
  EXPECT_EQ(s.probes[2].point, Vec3::Zero());

  // Bodies are kept verbatim for the rigid module.
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0]["urdf"], "hands/hand.urdf");
}

TEST(LoadScene, MinimalSceneGetsDefaults) {
  const SceneSpec s =
      parse_scene({{"name", "m"}, {"cloths", nlohmann::json::array()}}, "m.json", "");
  const SceneSpec d;
  EXPECT_EQ(s.file, "m.json");
  EXPECT_EQ(s.name, "m");
  EXPECT_DOUBLE_EQ(s.dt, 0.005);
  EXPECT_DOUBLE_EQ(s.duration, 1.0);
  EXPECT_DOUBLE_EQ(s.frame_rate, 50.0);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.coupling.mode, "bai-liu");
  EXPECT_DOUBLE_EQ(s.coupling.cluster_distance, 0.04);
  EXPECT_DOUBLE_EQ(s.coupling.cluster_normal_deg, 20.0);
  EXPECT_DOUBLE_EQ(s.coupling.cluster_offset, 0.003);
  EXPECT_DOUBLE_EQ(s.collision.thickness, 0.005);
  EXPECT_TRUE(s.collision.self_collision);
  EXPECT_EQ(s.solver.factor_precision, "double");
  EXPECT_DOUBLE_EQ(s.solver.refine_tolerance, 1e-10);
  EXPECT_TRUE(s.cloths.empty() && s.obstacles.empty() && s.probes.empty());
  EXPECT_TRUE(s.bodies.is_array() && s.bodies.empty());
}

TEST(ParseScene, ResolvesPathsAgainstBaseDir) {
  const nlohmann::json doc = {
      {"name", "in-memory"},
      {"cloths", {{{"name", "c"}, {"mesh", {{"obj", "meshes/square.obj"}}}}}}};
  const SceneSpec s = parse_scene(doc, "memory", data_path(""));
  ASSERT_TRUE(s.cloths.at(0).mesh.obj_path);
  EXPECT_TRUE(
      std::filesystem::equivalent(*s.cloths[0].mesh.obj_path, data_path("meshes/square.obj")));
  // The same document with another base folder cannot find the mesh.
  EXPECT_THROW(parse_scene(doc, "memory", "/nonexistent"), InputRejected);
}

TEST(ParseScene, RejectsNonFiniteNumbersInMemory) {
  // JSON text cannot hold NaN or Inf, but an in-memory document can.
  nlohmann::json doc = {{"name", "x"}, {"cloths", nlohmann::json::array()}};
  doc["dt"] = std::numeric_limits<double>::quiet_NaN();
  doc["gravity"] = {0.0, std::numeric_limits<double>::infinity(), 0.0};
  try {
    parse_scene(doc, "memory", "");
    FAIL() << "NaN accepted";
  } catch (const InputRejected& rejected) {
    expect_errors(rejected.errors(), {{"memory", "/dt", "must be finite"},
                                      {"memory", "/gravity/1", "must be finite"}});
  }
}

TEST(ParseScene, AcceptsIntegralFloatsAsIntegers) {
  const nlohmann::json doc = nlohmann::json::parse(R"({"name": "x", "cloths": [
      {"name": "c", "mesh": {"grid": {"size": [1, 1], "resolution": [4.0, 3]}},
       "handles": [{"vertices": [11.0]}]}]})");
  const SceneSpec s = parse_scene(doc, "memory", "");
  EXPECT_EQ(*s.cloths[0].mesh.grid_resolution, (std::array<int, 2>{4, 3}));
  EXPECT_EQ(s.cloths[0].handles[0].vertices, std::vector<int>{11});
}

TEST(LoadScene, EveryShippedSceneIsValid) {
  // The scenes under scenes/ are what users run first; each must pass validation.
  std::size_t count = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(DEXCLOTH_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    try {
      load_scene(entry.path().string());
    } catch (const InputRejected& rejected) {
      ADD_FAILURE() << rejected.what();
    }
  }
  EXPECT_GT(count, 0u);
}

}  // namespace
}  // namespace dexcloth::scene::test
