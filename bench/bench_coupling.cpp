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
/// triangles. The argument is the step's threads (1, 2).
///   BM_PinchMoveSearches: the two broad phases of a step alone, on the states of pinch_move's
///   20 steps from 2.2 s (the sheet hanging in wrinkles from the pinch, its self query the
///   step's largest search), taken in turn without stepping: the proximity search
///   (find_proximities, at x0) and the impact zones' swept candidates (x0 → x1), each step's
///   x0 the last one's x1 as in a run (so that what the searches keep from one step to the next,
///   and share as the step has them share it, counts as it does there). Counters: proximity_ms,
///   swept_ms, and the candidates and proximities found (means over the steps). Argument: threads
///   of the searches (1, 2).
/// Run (Release):
///   build/bench/bench_coupling
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cloth/collision/impact_zones.hpp"
#include "cloth/collision/proximity.hpp"
#include "core/heap.hpp"
#include "core/worker_pool.hpp"
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

// The collision meshes of pinch_move's 20 steps from 2.2 s (x0 each step's start, x1 its end),
// stepped once for every run of BM_PinchMoveSearches (none: state lost).
struct SearchStates {
  double thickness{};
  std::vector<std::vector<collision::CollisionMesh>> steps;
};

const SearchStates& pinch_move_states() {
  static const SearchStates states = [] {
    scene::CompiledScene s = scene::compile_scene(scene::load_scene(kScenes + "/pinch_move.json"));
    while (s.data.time < 2.2 - 1e-9 && !s.data.lost) coupling::step(s.model, s.data);
    SearchStates out{s.model.thickness, {}};
    for (int k = 0; k < 20 && !s.data.lost; ++k) {
      coupling::step(s.model, s.data);
      out.steps.push_back(s.data.meshes);
    }
    if (s.data.lost) out.steps.clear();
    return out;
  }();
  return states;
}

void BM_PinchMoveSearches(benchmark::State& bench) {
  const SearchStates& states = pinch_move_states();
  if (states.steps.empty()) {
    bench.SkipWithError("state lost (NaN)");
    return;
  }
  std::vector<std::vector<const collision::CollisionMesh*>> views;
  for (const std::vector<collision::CollisionMesh>& step : states.steps) {
    views.emplace_back();
    for (const collision::CollisionMesh& m : step) views.back().push_back(&m);
  }
  const int threads = static_cast<int>(bench.range(0));
  WorkerPool pool(threads);
  collision::CollisionCandidates proximity, swept;
  proximity.set_pool(threads > 1 ? &pool : nullptr);
  swept.set_pool(threads > 1 ? &pool : nullptr);
  swept.share_fits(proximity);  // as the step has them
  std::vector<collision::Proximity> found;
  std::vector<std::vector<collision::Proximity>> scratch;
  const double ccd_tolerance = collision::ImpactZoneOptions{}.ccd_tolerance;
  // Untimed first searches build what the step keeps between steps (trees, topology, rest
  // neighbours, the unfolded subtrees' and windows' rest data), on the step before the first.
  collision::find_proximities(views.back(), states.thickness, proximity, found, scratch);
  swept.update(views.back(), true, ccd_tolerance);
  using Clock = std::chrono::steady_clock;
  double t_proximity = 0.0, t_swept = 0.0, vf = 0.0, ee = 0.0, proximities = 0.0, candidates = 0.0;
  std::size_t k = 0;
  for (auto _ : bench) {
    const std::vector<const collision::CollisionMesh*>& meshes = views[k];
    k = (k + 1) % views.size();
    const auto t0 = Clock::now();
    collision::find_proximities(meshes, states.thickness, proximity, found, scratch);
    const auto t1 = Clock::now();
    swept.update(meshes, true, ccd_tolerance);
    const auto t2 = Clock::now();
    t_proximity += std::chrono::duration<double, std::milli>(t1 - t0).count();
    t_swept += std::chrono::duration<double, std::milli>(t2 - t1).count();
    vf += static_cast<double>(proximity.vertex_face().size());
    ee += static_cast<double>(proximity.edge_edge().size());
    proximities += static_cast<double>(found.size());
    candidates += static_cast<double>(swept.vertex_face().size() + swept.edge_edge().size());
  }
  const auto per_run = benchmark::Counter::kAvgIterations;
  bench.counters["proximity_ms"] = benchmark::Counter(t_proximity, per_run);
  bench.counters["swept_ms"] = benchmark::Counter(t_swept, per_run);
  bench.counters["vf_candidates"] = benchmark::Counter(vf, per_run);
  bench.counters["ee_candidates"] = benchmark::Counter(ee, per_run);
  bench.counters["proximities"] = benchmark::Counter(proximities, per_run);
  bench.counters["swept_candidates"] = benchmark::Counter(candidates, per_run);
}
BENCHMARK(BM_PinchMoveSearches)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  dexcloth::keep_heap_top();  // as `dexcloth run` does
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
