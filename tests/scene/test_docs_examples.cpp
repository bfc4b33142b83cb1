/// Every ```json example in docs/scene-format.md is a valid scene, or a valid piece of one
/// (a cloth, an obstacle, a probe, or top-level keys), so the documentation cannot drift from
/// the validator. OBJ paths resolve against tests/scene/data/.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "scene/load.hpp"
#include "scene_test_util.hpp"

namespace dexcloth::scene::test {
namespace {

using nlohmann::json;

// The bodies of the ```json fenced blocks of a Markdown file.
std::vector<std::string> json_blocks(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> blocks;
  std::string line;
  std::string current;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line.rfind("```json", 0) == 0) {
      inside = true;
      current.clear();
    } else if (inside && line.rfind("```", 0) == 0) {
      inside = false;
      blocks.push_back(current);
    } else if (inside) {
      current += line + "\n";
    }
  }
  return blocks;
}

// Wraps a fragment into a whole scene, judging what it is by its keys.
json as_scene(const json& block) {
  json scene = {{"name", "doc"}, {"cloths", json::array()}};
  const json sheet = {{"name", "sheet"},
                      {"mesh", {{"grid", {{"size", {1, 1}}, {"resolution", {10, 10}}}}}}};
  if (block.contains("cloths")) return block;
  if (block.contains("mesh")) {
    scene["cloths"].push_back(block);
  } else if (block.contains("shape")) {
    scene["obstacles"] = json::array({block});
  } else if (block.contains("cloth") || block.contains("body")) {
    scene["cloths"].push_back(sheet);
    scene["probes"] = json::array({block});
  } else {
    scene.update(block);
  }
  return scene;
}

TEST(DocsExamples, EveryJsonBlockIsValid) {
  const std::string doc = std::string(DEXCLOTH_SOURCE_DIR) + "/docs/scene-format.md";
  const auto blocks = json_blocks(doc);
  ASSERT_GE(blocks.size(), 10u) << "no examples found in " << doc;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    SCOPED_TRACE("example " + std::to_string(i + 1) + ":\n" + blocks[i]);
    json block;
    ASSERT_NO_THROW(block = json::parse(blocks[i], nullptr, true, true));
    try {
      parse_scene(as_scene(block), "example", data_path(""));
    } catch (const InputRejected& rejected) {
      ADD_FAILURE() << rejected.what();
    }
  }
}

}  // namespace
}  // namespace dexcloth::scene::test
