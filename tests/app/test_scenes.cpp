#include <gtest/gtest.h>

#include <cmath>

#include "cli_runner.hpp"

using namespace dexcloth::test;
namespace fs = std::filesystem;

/// Every scene under scenes/ validates and runs briefly without NaN or lost state, in both
/// coupling modes (DESIGN.md: every scene runs in both).
class EveryScene : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryScene, ValidatesAndRunsBrieflyInBothCouplingModes) {
  const fs::path scene = source_dir() / "scenes" / GetParam();
  auto r = run_cli("validate " + scene.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* mode : {"bai-liu", "kinematic"}) {
    const fs::path out = fresh_dir(mode);
    r = run_cli("run " + scene.string() + " --quiet --duration 0.05 --coupling " + mode +
                " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << mode << "\n" << r.output;
    const auto s = read_json(out / "summary.json");
    EXPECT_EQ(s["nan"], false);
    EXPECT_EQ(s["coupling"], mode);
    EXPECT_EQ(s["steps"].get<long>(), std::lround(0.05 / s["dt"].get<double>()));
  }
}

namespace {
std::vector<std::string> scene_files() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(source_dir() / "scenes"))
    if (entry.path().extension() == ".json") names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}
std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string s = info.param.substr(0, info.param.size() - 5);
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}
}  // namespace

INSTANTIATE_TEST_SUITE_P(Scenes, EveryScene, ::testing::ValuesIn(scene_files()), test_name);
