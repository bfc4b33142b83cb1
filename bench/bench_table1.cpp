/// The paper's Table 1 for every scene: triangles, seconds per step, and the cloth / rigid /
/// interface shares of the step. Each scene runs whole (or up to --duration), stepped by
/// coupling::step as `dexcloth run` steps it, without recording. Prints a Markdown table.
///   build/bench/bench_table1                       every scenes/*.json, 2 threads
///   build/bench/bench_table1 --threads 1 --duration 1.0 pinch_move curtain
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/heap.hpp"
#include "coupling/step.hpp"
#include "scene/compile.hpp"
#include "scene/load.hpp"

namespace {

using namespace dexcloth;

struct Options {
  int threads{2};
  double duration{0.0};             ///< 0: each scene's own
  std::vector<std::string> scenes;  ///< names; empty: every scene
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) {
      o.threads = std::atoi(argv[++i]);
    } else if (a == "--duration" && i + 1 < argc) {
      o.duration = std::atof(argv[++i]);
    } else if (!a.empty() && a[0] != '-') {
      o.scenes.push_back(a);
    } else {
      std::fprintf(stderr, "usage: bench_table1 [--threads N] [--duration S] [scene ...]\n");
      std::exit(2);
    }
  }
  if (o.threads < 1 || o.duration < 0.0) {
    std::fprintf(stderr, "bench_table1: --threads must be >= 1 and --duration >= 0\n");
    std::exit(2);
  }
  return o;
}

std::vector<std::string> all_scenes(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

void row(const std::filesystem::path& path, const Options& o) {
  const scene::SceneSpec spec = scene::load_scene(path.string());
  scene::CompiledScene scene = scene::compile_scene(spec);
  coupling::set_threads(scene.model, o.threads);
  const double end = o.duration > 0.0 ? std::min(o.duration, spec.duration) : spec.duration;
  std::vector<double> step_ms;
  while (scene.data.time < end - 1e-9 && !scene.data.lost) {
    coupling::step(scene.model, scene.data);
    step_ms.push_back(scene.data.last_step_ms);
  }
  int triangles = 0;
  for (const coupling::ClothBody& c : scene.model.cloths)
    triangles += static_cast<int>(c.model.faces.rows());
  const coupling::Timings& t = scene.data.timings;
  const double parts = t.cloth + t.rigid + t.interface;
  const double n = static_cast<double>(std::max<std::size_t>(step_ms.size(), 1));
  std::nth_element(step_ms.begin(), step_ms.begin() + static_cast<long>(step_ms.size() / 2),
                   step_ms.end());
  const double median = step_ms.empty() ? 0.0 : step_ms[step_ms.size() / 2];
  const auto pct = [&](double x) { return parts > 0.0 ? 100.0 * x / parts : 0.0; };
  std::printf("| %s | %d | %.3f | %.4f | %.4f | %.0f %% | %.0f %% | %.0f %% |%s\n",
              path.stem().string().c_str(), triangles, scene.data.time, t.total / n, 1e-3 * median,
              pct(t.cloth), pct(t.rigid), pct(t.interface), scene.data.lost ? " state lost" : "");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  dexcloth::keep_heap_top();  // as `dexcloth run` does
  const Options o = parse(argc, argv);
  const std::filesystem::path dir = std::filesystem::path(DEXCLOTH_SOURCE_DIR) / "scenes";
  const std::vector<std::string> names = o.scenes.empty() ? all_scenes(dir) : o.scenes;
  std::printf("Table 1 (each scene's own coupling, %d thread%s%s)\n\n", o.threads,
              o.threads == 1 ? "" : "s",
              o.duration > 0.0 ? (", first " + std::to_string(o.duration) + " s").c_str() : "");
  std::printf(
      "| scene | triangles | simulated s | s/step (mean) | s/step (median) | cloth | rigid "
      "| interface |\n|---|---|---|---|---|---|---|---|\n");
  int failures = 0;
  for (const std::string& name : names) {
    const std::filesystem::path path = dir / (name + ".json");
    try {
      row(path, o);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_table1: %s: %s\n", path.string().c_str(), e.what());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}
