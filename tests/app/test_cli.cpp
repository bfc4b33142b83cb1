#include <gtest/gtest.h>

#include <fstream>

#include "cli_runner.hpp"

using namespace dexcloth::test;
namespace fs = std::filesystem;

namespace {

/// Writes a scene file with `text` and returns its path.
fs::path write_scene(const fs::path& dir, const std::string& text) {
  fs::create_directories(dir);
  const fs::path p = dir / "scene.json";
  std::ofstream(p) << text;
  return p;
}

const char* kSmallScene = R"({
  "name": "small", "duration": 0.05,
  "cloths": [{"name": "c", "mesh": {"grid": {"size": [0.2, 0.2], "resolution": [5, 5]}},
              "handles": [{"vertices": [20, 24]}]}],
  "probes": [{"name": "corner", "cloth": "c", "near": [-0.1, -0.1, 0]}]
})";

}  // namespace

TEST(Cli, RunWritesSummaryWithTheContractFields) {
  const fs::path dir = fresh_dir("in");
  const fs::path out = fresh_dir("out");
  const auto r = run_cli("run " + write_scene(dir, kSmallScene).string() + " --quiet --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto s = read_json(out / "summary.json");
  for (const char* key : {"scene", "coupling", "dt", "steps", "cloth", "timing_s", "step_ms",
                          "warnings", "nan", "probes"})
    EXPECT_TRUE(s.contains(key)) << key;
  EXPECT_EQ(s["scene"], "small");
  EXPECT_EQ(s["steps"], 10);  // 0.05 s / 0.005 s
  EXPECT_EQ(s["cloth"]["vertices"], 25);
  EXPECT_EQ(s["cloth"]["triangles"], 32);
  EXPECT_EQ(s["nan"], false);
  // Frame 0 and every 1/50 s: t = 0, 0.02, 0.04.
  ASSERT_EQ(s["probes"]["corner"].size(), 3u);
  EXPECT_DOUBLE_EQ(s["probes"]["corner"][0][1].get<double>(), -0.1);
  EXPECT_LT(s["probes"]["corner"][2][3].get<double>(), 0.0);  // it fell
}

TEST(Cli, BadSceneIsRejectedAndWritesNothing) {
  const fs::path dir = fresh_dir("in");
  const fs::path out = fresh_dir("out");
  std::string bad = kSmallScene;
  bad.replace(bad.find("\"duration\""), 10, "\"duraton\"");
  const auto r = run_cli("run " + write_scene(dir, bad).string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("scene.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("duraton"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, SetOverridesAreAppliedAndValidated) {
  const fs::path dir = fresh_dir("in");
  const fs::path scene = write_scene(dir, kSmallScene);
  const fs::path out = fresh_dir("out");
  auto r = run_cli("run " + scene.string() + " --quiet --out " + out.string() + " --set /dt=0.01");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_json(out / "summary.json")["steps"], 5);
  r = run_cli("validate " + scene.string() + " --set /cloths/0/material/density=-1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("/cloths/0/material/density"), std::string::npos) << r.output;
}

TEST(Cli, HandleIndexPastAGridIsAnErrorWithItsPointer) {
  const fs::path dir = fresh_dir("in");
  std::string bad = kSmallScene;
  bad.replace(bad.find("[20, 24]"), 8, "[20, 99]");
  const auto r = run_cli("validate " + write_scene(dir, bad).string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("/cloths/0/handles/0/vertices/1"), std::string::npos) << r.output;
}

TEST(Cli, ValidateAcceptsAGoodScene) {
  const fs::path dir = fresh_dir("in");
  const auto r = run_cli("validate " + write_scene(dir, kSmallScene).string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}
