/// Per-step time of a hanging sheet (cloth dynamics only) at about 2k, 8k and 32k triangles.
/// Run: build/bench/bench_cloth_step  (Release). One benchmark iteration = one 5 ms step.
#include <benchmark/benchmark.h>

#include <vector>

#include "cloth/dynamics.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"
#include "cloth/state.hpp"

namespace {

using namespace dexcloth;

void BM_HangingSheetStep(benchmark::State& bench) {
  const int n = static_cast<int>(bench.range(0));
  cloth::ClothMesh mesh = cloth::make_grid(1.0, 1.0, n, n);
  const cloth::ClothModel model = cloth::build_model(mesh, cloth::Material{});
  cloth::ClothState state = cloth::make_state(model, mesh.x);
  // Pinned top corners (hard constraints), gravity along −y in the sheet's plane.
  const std::vector<cloth::VelocityConstraint> pins{{n * (n - 1), Vec3::Zero()},
                                                    {n * n - 1, Vec3::Zero()}};
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 0.005;
  for (int warm = 0; warm < 5; ++warm) cloth::step_dynamics(model, state, h, gravity, pins);
  for (auto _ : bench) {
    const cloth::DynamicsReport report = cloth::step_dynamics(model, state, h, gravity, pins);
    benchmark::DoNotOptimize(report.residual);
  }
  bench.counters["triangles"] = static_cast<double>(model.faces.rows());
  bench.counters["vertices"] = static_cast<double>(n * n);
}

}  // namespace

BENCHMARK(BM_HangingSheetStep)->Arg(33)->Arg(65)->Arg(129)->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

BENCHMARK_MAIN();
