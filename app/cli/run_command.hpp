#pragma once
/// `dexcloth run` and `dexcloth validate`.
#include <string>
#include <vector>

namespace dexcloth::app {

struct RunOptions {
  std::string scene;                   ///< scene file path
  std::string out_dir;                 ///< output folder
  std::vector<std::string> overrides;  ///< --set /pointer=value
  double duration{-1.0};               ///< [s], < 0: the scene's
  std::string coupling;                ///< "" : the scene's
  int threads{1};                      ///< threads of the step's parallel parts
  bool quiet{false};
  bool export_obj{false};
};

/// Runs a scene; returns the process exit code (0 ok, 1 bad input, 2 simulation failed).
int run_scene(const RunOptions& options);

/// Validates a scene; prints every problem; returns 0 or 1.
int validate_scene(const std::string& scene, const std::vector<std::string>& overrides);

}  // namespace dexcloth::app
