/// Cost of one coupled world step (Algorithm 1: cloth, interface, DART) on a pinch scene, with
/// the paper's Table-1 split. Each scene is stepped by coupling::step, as `dexcloth run` steps it,
/// up to a time where the cloth is held, then single steps are timed:
///   BM_Coupled/gripper_pinch  scenes/gripper_pinch.json from 1.2 s (strip held, gripper still).
///   BM_Coupled/pinch_napkin   scenes/pinch_napkin.json from 2.2 s (the hand carrying the napkin).
///   BM_Coupled/pinch_move     scenes/pinch_move.json from 2.2 s (the hand carrying a 0.3 m sheet).
///   BM_Coupled/gripper_layers scenes/gripper_layers.json from 1.8 s (three strips held, still).
///   BM_Coupled/three_layers   scenes/three_layers.json from 2.6 s (the hand carrying three napkins).
///   BM_Coupled/curtain        scenes/curtain.json from 1.2 s (the gripper pulling 16k triangles).
/// Counters (per timed step): cloth_ms, interface_ms, rigid_ms (the Table-1 parts),
/// interface_pct (interface share of the step), patches, vr (rigid-contact vertices),
/// triangles. The argument is the step's threads (1, 2). Run (Release):
///   build/bench/bench_coupling
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "core/heap.hpp"
#include "coupling/step.hpp"
#include "scene/compile.hpp"
#include "scene/load.hpp"

namespace {

using namespace dexcloth;

const std::string kScenes = std::string(DEXCLOTH_SOURCE_DIR) + "/scenes";

void BM_Coupled(benchmark::State& bench, const std::string& name, double t_start) {
  const std::string path = kScenes + "/" + name + ".json";
  if (!std::filesystem::exists(path)) {
    bench.SkipWithError(("no " + path).c_str());
    return;
  }
  scene::CompiledScene scene = scene::compile_scene(scene::load_scene(path));
  coupling::set_threads(scene.model, static_cast<int>(bench.range(0)));
  while (scene.data.time < t_start - 1e-9 && !scene.data.lost) coupling::step(scene.model, scene.data);
  const coupling::Timings before = scene.data.timings;
  double patches = 0.0, vr = 0.0;
  for (auto _ : bench) {
    coupling::step(scene.model, scene.data);
    patches += scene.data.stats.patches;
    vr += scene.data.stats.vr;
  }
  if (scene.data.lost) bench.SkipWithError("state lost (NaN)");
  const double n = static_cast<double>(bench.iterations());
  const coupling::Timings& after = scene.data.timings;
  const double cloth = after.cloth - before.cloth;
  const double interface = after.interface - before.interface;
  const double rigid = after.rigid - before.rigid;
  bench.counters["cloth_ms"] = 1e3 * cloth / n;
  bench.counters["interface_ms"] = 1e3 * interface / n;
  bench.counters["rigid_ms"] = 1e3 * rigid / n;
  bench.counters["interface_pct"] = 100.0 * interface / (cloth + interface + rigid);
  bench.counters["patches"] = patches / n;
  bench.counters["vr"] = vr / n;
  int triangles = 0;
  for (const coupling::ClothBody& c : scene.model.cloths) triangles += static_cast<int>(c.model.faces.rows());
  bench.counters["triangles"] = triangles;
}

BENCHMARK_CAPTURE(BM_Coupled, gripper_pinch, std::string("gripper_pinch"), 1.2)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(100);
BENCHMARK_CAPTURE(BM_Coupled, pinch_napkin, std::string("pinch_napkin"), 2.2)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(100);
BENCHMARK_CAPTURE(BM_Coupled, gripper_layers, std::string("gripper_layers"), 1.8)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(100);
BENCHMARK_CAPTURE(BM_Coupled, three_layers, std::string("three_layers"), 2.6)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(100);
BENCHMARK_CAPTURE(BM_Coupled, pinch_move, std::string("pinch_move"), 2.2)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(40);
BENCHMARK_CAPTURE(BM_Coupled, curtain, std::string("curtain"), 1.2)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(40);

}  // namespace

int main(int argc, char** argv) {
  dexcloth::keep_heap_top();  // as `dexcloth run` does
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
