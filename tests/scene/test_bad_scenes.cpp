/// Bad scene files and bad --set arguments: each is rejected with every problem, at the exact
/// JSON pointer (or line/column, or --set argument) and naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "scene/load.hpp"
#include "scene_test_util.hpp"

namespace dexcloth::scene::test {
namespace {

// A problem in the scene file itself: file left empty, filled in with the scene's path.
Expected at(std::string pointer, std::string fragment) {
  return {"", std::move(pointer), std::move(fragment)};
}

// A malformed --set argument: located by the argument, not by the file.
Expected in_set(const std::string& arg, std::string fragment) {
  return {"--set " + arg, "", std::move(fragment)};
}

struct BadCase {
  std::string label;                   ///< test name
  std::string file;                    ///< under tests/scene/data/
  std::vector<std::string> overrides;  ///< --set arguments
  std::vector<Expected> errors;        ///< exactly the problems expected
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.label; }

class BadScene : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadScene, RejectedWithEveryProblemLocated) {
  const BadCase& c = GetParam();
  const std::string path = data_path(c.file);
  std::vector<Expected> expected = c.errors;
  for (auto& e : expected) {
    if (e.file.empty()) e.file = path;
  }
  try {
    load_scene(path, c.overrides);
    FAIL() << c.file << " was accepted";
  } catch (const InputRejected& rejected) {
    expect_errors(rejected.errors(), expected);
  }
}

const std::vector<BadCase> bad_cases = {
    {"syntax", "bad_syntax.json", {}, {at("line 4, column 10", "expected '}'")}},
    {"inf_literal", "bad_inf.json", {}, {at("line 4, column 15", "number overflow")}},
    {"duplicate_key",
     "bad_duplicate_key.json",
     {},
     {at("/dt", "duplicate key \"dt\""),
      at("/cloths/0/material/density", "duplicate key \"density\"")}},
    {"not_object", "bad_not_object.json", {}, {at("", "must be an object, got array of 3")}},
    {"missing_required",
     "bad_missing_required.json",
     {},
     {at("/name", "required key is missing"), at("/cloths", "required key is missing")}},
    {"types",
     "bad_types.json",
     {},
     {at("/dt", "must be a number, got string \"fast\""),
      at("/gravity", "must be an array of 3 numbers, got array of 2"),
      at("/collision/self_collision", "must be true or false, got 1"),
      at("/cloths/0/name", "must be a string, got 7"),
      at("/cloths/0/material/density", "must be a number, got string \"heavy\""),
      at("/cloths/0/handles", "must be an array, got object")}},
    {"negative_density",
     "bad_negative_density.json",
     {},
     {at("/cloths/0/material/density", "must be > 0, got -1")}},
    {"poisson_half",
     "bad_poisson.json",
     {},
     {at("/cloths/0/material/poisson", "must be in [0, 0.5), got 0.5")}},
    {"resolution_below_2",
     "bad_resolution.json",
     {},
     {at("/cloths/0/mesh/grid/resolution/0", "must be >= 2, got 1"),
      at("/cloths/0/mesh/grid/size/1", "must be > 0, got 0")}},
    {"resolution_not_integer",
     "bad_resolution_float.json",
     {},
     {at("/cloths/0/mesh/grid/resolution/0", "must be an integer, got 10.5")}},
    {"missing_mesh_file",
     "bad_missing_mesh_file.json",
     {},
     {at("/cloths/0/mesh/obj", "file not found: \"" + data_path("meshes/nope.obj") + "\"")}},
    {"grid_and_obj",
     "bad_grid_and_obj.json",
     {},
     {at("/cloths/0/mesh", "exactly one of \"grid\", \"obj\", got \"grid\" and \"obj\""),
      at("/cloths/1/mesh", "exactly one of \"grid\", \"obj\", got none")}},
    {"unknown_top_key",
     "bad_unknown_top_key.json",
     {},
     {at("/gravty", "unknown key \"gravty\"; did you mean \"gravity\"?"),
      at("/foo_bar", "unknown key \"foo_bar\"")}},
    {"unknown_nested_key",
     "bad_unknown_nested_key.json",
     {},
     {at("/cloths/0/material/densty", "unknown key \"densty\"; did you mean \"density\"?"),
      at("/cloths/0/transform/translaton", "did you mean \"translation\"?")}},
    {"duplicate_names",
     "bad_duplicate_cloth.json",
     {},
     {at("/cloths/1/name", "duplicate cloth name \"sheet\" (first used at /cloths/0)"),
      at("/obstacles/1/name", "duplicate obstacle name \"o\"")}},
    {"probe_unknown_cloth",
     "bad_probe_cloth.json",
     {},
     {at("/probes/0/cloth", "no cloth named \"shet\"; did you mean \"sheet\"?")}},
    {"probes",
     "bad_probes.json",
     {},
     {at("/probes/0", "exactly one of \"cloth\", \"body\", got \"cloth\" and \"body\""),
      at("/probes/1/body", "must be \"skeleton/body_node\", got \"hand\""),
      at("/probes/2/near", "required key is missing"),
      at("/probes/3/point", "belongs to body probes")}},
    {"handle_vertex_range",
     "bad_handle_vertex.json",
     {},
     {at("/cloths/0/handles/0/vertices/2", "vertex index 9 out of range: the grid has 9"),
      at("/cloths/0/handles/0/vertices/3", "must be >= 0, got -1"),
      at("/cloths/0/handles/1/vertices", "must list at least one vertex")}},
    {"motion_times",
     "bad_motion_times.json",
     {},
     {at("/cloths/0/handles/0/motion/2/t", "must be > the previous keyframe's t (1.0), got 1.0"),
      at("/obstacles/0/motion/1/t", "must be > the previous keyframe's t (0.5), got 0.2"),
      at("/obstacles/0/motion/2/t", "must be >= 0, got -1")}},
    {"coupling_mode",
     "bad_coupling.json",
     {},
     {at("/coupling", "got \"bai_liu\"; did you mean \"bai-liu\"?")}},
    {"collision_and_coupling_params",
     "bad_collision_coupling_params.json",
     {},
     {at("/collision/thickness", "must be > 0, got 0"),
      at("/collision/selfcollision", "did you mean \"self_collision\"?"),
      at("/coupling_params/cluster_normal_deg", "must be in (0, 180], got 200"),
      at("/coupling_params/cluster_offset", "must be > 0, got -0.001"),
      at("/coupling_params/rigid_substeps", "must be an integer, got 2.5"),
      at("/solver/factor_precision", "must be \"double\" or \"single\", got \"half\""),
      at("/solver/refine_tolerance", "must be in (0, 1e-05], got 0.0001")}},
    {"box_min_above_max",
     "bad_box_handle.json",
     {},
     {at("/cloths/0/handles/0/box", "min[2] = 1.0 > max[2] = 0.0")}},
    {"strain_limits",
     "bad_strain_limits.json",
     {},
     {at("/cloths/0/material/strain_limits", "0 < min <= 1 <= max, got [1.1,1.5]"),
      at("/cloths/1/material/strain_limits", "array of 2 numbers, got array of 1")}},
    {"dt_zero",
     "bad_dt.json",
     {},
     {at("/dt", "must be in (0, 0.05], got 0"), at("/duration", "must be > 0, got -1"),
      at("/frame_rate", "must be > 0, got 0")}},
    {"dt_too_large", "bad_dt_large.json", {}, {at("/dt", "must be in (0, 0.05], got 0.1")}},
    {"shapes",
     "bad_shapes.json",
     {},
     {at("/obstacles/0/shape/sphere/radius", "must be > 0, got -1"),
      at("/obstacles/1/shape/capsule/length", "required key is missing"),
      at("/obstacles/2/shape/box/size", "array of 3 numbers, got array of 2"),
      at("/obstacles/3/shape", "got \"box\" and \"sphere\""),
      at("/obstacles/4/shape/cylindr", "unknown key \"cylindr\""),
      at("/obstacles/4/shape", "got none"),
      at("/obstacles/5/shape/plane/normal", "unknown key \"normal\""),
      at("/obstacles/5/friction", "must be >= 0, got -0.1")}},
    {"bodies",
     "bad_bodies.json",
     {},
     {at("/bodies/0/name", "required key is missing"),
      at("/bodies/1", "must be an object, got 3")}},
    // --set: values are validated like the file and blamed on the argument.
    {"set_nan",
     "full.json",
     {"/dt=nan"},
     {at("/dt", "must be a number, got string \"nan\" (from --set /dt=nan)")}},
    {"set_inf",
     "full.json",
     {"/cloths/0/material/density=inf", "/duration=-Infinity"},
     {at("/cloths/0/material/density", "must be a number, got string \"inf\""),
      at("/duration", "must be a number, got string \"-Infinity\"")}},
    {"set_overflow", "full.json", {"/dt=1e999"}, {in_set("/dt=1e999", "number out of range")}},
    {"set_slide",
     "full.json",
     {"/cloths/0/handles/0/slide=[0,0,0]", "/cloths/0/handles/1/slide=[1,0]"},
     {at("/cloths/0/handles/0/slide", "must be a non-zero direction, got [0, 0, 0]"),
      at("/cloths/0/handles/1/slide", "array of 3 numbers, got array of 2")}},
    {"set_unknown_key",
     "full.json",
     {"/cloths/0/material/densty=1"},
     {at("/cloths/0/material/densty", "did you mean \"density\"? (from --set")}},
    {"set_malformed",
     "full.json",
     {"/dt", "dt=0.1", "/a~2=1", "=1"},
     {in_set("/dt", "no '=' found"), in_set("dt=0.1", "invalid JSON pointer"),
      in_set("/a~2=1", "invalid JSON pointer"), in_set("=1", "must name a key")}},
    {"set_unreachable",
     "full.json",
     {"/cloths/7/name=x", "/dt/x=1", "/cloths/x/name=y"},
     {in_set("/cloths/7/name=x", "/cloths/7 does not exist: /cloths has 2 entries"),
      in_set("/dt/x=1", "cannot set inside /dt: it is a number"),
      in_set("/cloths/x/name=y", "\"x\" is not an index")}},
    {"set_and_file_errors_together",
     "bad_negative_density.json",
     {"/dt", "/frame_rate=-1"},
     {in_set("/dt", "no '=' found"), at("/frame_rate", "must be > 0, got -1 (from --set"),
      at("/cloths/0/material/density", "must be > 0, got -1")}},
    {"set_on_unparsable_file",
     "bad_syntax.json",
     {"/dt"},
     {at("line 4, column 10", "syntax error"), in_set("/dt", "no '=' found")}},
};

INSTANTIATE_TEST_SUITE_P(Scene, BadScene, ::testing::ValuesIn(bad_cases),
                         [](const auto& info) { return info.param.label; });

TEST(BadSceneFiles, EveryDataFileIsCovered) {
  // A bad_*.json added without a case in the table would test nothing.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(data_path(""))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("bad_", 0) != 0) continue;
    ++files;
    bool covered = false;
    for (const auto& c : bad_cases) covered = covered || c.file == name;
    EXPECT_TRUE(covered) << name << " has no case";
  }
  EXPECT_GE(files, 20u);
}

TEST(BadSceneFiles, MissingSceneFileIsReported) {
  const std::string path = data_path("no_such_scene.json");
  try {
    load_scene(path);
    FAIL() << "missing file accepted";
  } catch (const InputRejected& rejected) {
    expect_errors(rejected.errors(), {{path, "", "file not found"}});
  }
}

}  // namespace
}  // namespace dexcloth::scene::test
