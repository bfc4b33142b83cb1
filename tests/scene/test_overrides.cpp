/// --set overrides: values land where the pointer says, are parsed as JSON when possible, and
/// are validated like the file.
#include <gtest/gtest.h>

#include "scene/load.hpp"
#include "scene/overrides.hpp"
#include "scene_test_util.hpp"

namespace dexcloth::scene::test {
namespace {

using nlohmann::json;

TEST(LoadSceneOverrides, ChangeTheValues) {
  const SceneSpec s =
      load_scene(data_path("full.json"), {"/dt=0.001", "/cloths/0/material/friction=0.8"});
  EXPECT_DOUBLE_EQ(s.dt, 0.001);
  EXPECT_DOUBLE_EQ(s.cloths[0].material.friction, 0.8);
  // Untouched values stay as in the file.
  EXPECT_DOUBLE_EQ(s.duration, 2.5);
  EXPECT_DOUBLE_EQ(s.cloths[0].material.density, 0.2);
}

TEST(LoadSceneOverrides, ASlideDirectionIsNormalised) {
  const SceneSpec s = load_scene(data_path("full.json"), {"/cloths/0/handles/0/slide=[3,0,4]"});
  ASSERT_TRUE(s.cloths[0].handles[0].slide);
  EXPECT_TRUE(s.cloths[0].handles[0].slide->isApprox(Vec3(0.6, 0.0, 0.8), 1e-15));
}

TEST(LoadSceneOverrides, LaterOverrideWins) {
  const SceneSpec s = load_scene(data_path("full.json"), {"/dt=0.001", "/dt=0.003"});
  EXPECT_DOUBLE_EQ(s.dt, 0.003);
}

TEST(LoadSceneOverrides, TypoIsAnUnknownKey) {
  const std::string path = data_path("full.json");
  try {
    load_scene(path, {"/cloths/0/material/densty=1"});
    FAIL() << "typo accepted";
  } catch (const InputRejected& rejected) {
    expect_errors(rejected.errors(),
                  {{path, "/cloths/0/material/densty", "unknown key \"densty\"; did you mean"}});
  }
}

TEST(ApplyOverrides, ParsesValuesAsJsonElseString) {
  ErrorList errors;
  const json doc = apply_overrides(
      json::object(),
      {"/a=1.5", "/b=[1,2,3]", "/c=true", "/d=\"quoted\"", "/e=plain text", "/f=", "/g=a=b"},
      errors);
  EXPECT_TRUE(errors.empty()) << errors.to_string();
  EXPECT_EQ(doc["a"], 1.5);
  EXPECT_EQ(doc["b"], json::array({1, 2, 3}));
  EXPECT_EQ(doc["c"], true);
  EXPECT_EQ(doc["d"], "quoted");
  EXPECT_EQ(doc["e"], "plain text");
  EXPECT_EQ(doc["f"], "");
  EXPECT_EQ(doc["g"], "a=b");
}

TEST(ApplyOverrides, CreatesMissingObjectsAndAppendsToArrays) {
  ErrorList errors;
  const json in = {{"cloths", json::array({{{"name", "a"}}})}};
  const json doc =
      apply_overrides(in,
                      {"/collision/thickness=0.01", "/cloths/1={\"name\":\"b\"}",
                       "/cloths/-={\"name\":\"c\"}", "/cloths/0/name=z", "/odd~1key~0=1"},
                      errors);
  EXPECT_TRUE(errors.empty()) << errors.to_string();
  EXPECT_EQ(doc["collision"]["thickness"], 0.01);
  ASSERT_EQ(doc["cloths"].size(), 3u);
  EXPECT_EQ(doc["cloths"][0]["name"], "z");
  EXPECT_EQ(doc["cloths"][1]["name"], "b");
  EXPECT_EQ(doc["cloths"][2]["name"], "c");
  EXPECT_EQ(doc["odd/key~"], 1);
  // The input is taken by value: the caller's document is unchanged.
  EXPECT_EQ(in["cloths"].size(), 1u);
}

TEST(ApplyOverrides, ReportsEveryMalformedOverrideAndAppliesTheRest) {
  ErrorList errors;
  const json doc = apply_overrides(
      {{"dt", 0.005}, {"list", {1, 2}}},
      {"/dt", "dt=1", "/list/5=1", "/list/01=1", "/dt/x=1", "/duration=2", "/n=1e999"}, errors);
  expect_errors(errors, {{"--set /dt", "", "no '='"},
                         {"--set dt=1", "", "invalid JSON pointer"},
                         {"--set /list/5=1", "", "/list/5 does not exist: /list has 2 entries"},
                         {"--set /list/01=1", "", "\"01\" is not an index"},
                         {"--set /dt/x=1", "", "cannot set inside /dt: it is a number"},
                         {"--set /n=1e999", "", "number out of range"}});
  EXPECT_EQ(doc["duration"], 2);
  EXPECT_EQ(doc["dt"], 0.005);
  EXPECT_EQ(doc["list"], json::array({1, 2}));
}

}  // namespace
}  // namespace dexcloth::scene::test
