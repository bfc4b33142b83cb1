#pragma once
/// Scene files -> validated SceneSpec. The format is documented in docs/scene-format.md.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/spec.hpp"

namespace dexcloth::scene {

/// Reads the scene file at `path`, applies `overrides` ("/json/pointer=value", the CLI's
/// repeatable `--set`) and validates everything. Relative paths in the file are resolved against
/// the file's folder. Throws dexcloth::InputRejected carrying every problem found, each naming the
/// file and JSON pointer (`x.json: /cloths/0/material/density: must be > 0, got -1`), or
/// "line L, column C" for syntax errors, or `--set <argument>` for a malformed override.
SceneSpec load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Validates an in-memory scene document; `file` names it in messages and `base_dir` resolves
/// relative paths. Throws dexcloth::InputRejected as load_scene does.
SceneSpec parse_scene(const nlohmann::json& doc, const std::string& file,
                      const std::string& base_dir);

}  // namespace dexcloth::scene
