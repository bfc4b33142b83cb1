/// Per-step cost of cloth collision handling (the coupling step's order: proximity + repulsion,
/// strain limiting, impact zones) for a sheet over a tessellated sphere at about 2k, 8k and 32k
/// triangles, in two states where little happens: falling freely 2 cm above the sphere, and
/// resting on it within the repulsion thickness. Every iteration restarts from the same state.
/// Run: build/bench/bench_collision  (Release). Counters: ms per step of each phase. The searches
/// run on one thread or, with threads:2, on a pool of two (as a scene's step does).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include "cloth/collision/cloth_contacts.hpp"
#include "cloth/collision/impact_zones.hpp"
#include "cloth/collision/strain_limit.hpp"
#include "core/worker_pool.hpp"

namespace {

using namespace dexcloth;
using namespace dexcloth::collision;

constexpr double kDt = 5e-3;         // step [s]
constexpr double kThickness = 5e-3;  // repulsion thickness [m]
constexpr double kRadius = 0.25;     // sphere radius [m]

// Sheet of n × n quads over size × size [m] centred on the z axis at height z, 0.1 g per vertex,
// its rest shape flat as given (so the candidates leave out its rest neighbours, as in a scene).
CollisionMesh make_sheet(int n, double z, double size) {
  CollisionMesh m;
  const int nv = (n + 1) * (n + 1);
  m.x0.resize(nv, 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.x0.row(j * (n + 1) + i) << size * (-0.5 + static_cast<double>(i) / n),
          size * (-0.5 + static_cast<double>(j) / n), z;
  m.faces.resize(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int v00 = j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
      m.faces.row(f++) << v00, v10, v11;
      m.faces.row(f++) << v00, v11, v01;
    }
  }
  m.x1 = m.x0;
  m.rest = m.x0;
  m.mass = Eigen::VectorXd::Constant(nv, 1e-4);
  m.frozen.assign(static_cast<std::size_t>(nv), 0);
  m.friction = 0.4;
  return m;
}

// The sphere as the rigid side exports it: 16 slices × 8 stacks, poles on the z axis.
CollisionMesh make_sphere(int slices, int stacks) {
  CollisionMesh m;
  m.obstacle = true;
  const int rings = stacks - 1;
  m.x0.resize(2 + rings * slices, 3);
  m.x0.row(0) << 0.0, 0.0, -kRadius;
  for (int k = 0; k < rings; ++k) {
    const double phi = std::numbers::pi * (k + 1) / stacks;
    for (int s = 0; s < slices; ++s) {
      const double a = 2.0 * std::numbers::pi * s / slices;
      m.x0.row(1 + k * slices + s) << kRadius * std::sin(phi) * std::cos(a),
          kRadius * std::sin(phi) * std::sin(a), -kRadius * std::cos(phi);
    }
  }
  const int top = 1 + rings * slices;
  m.x0.row(top) << 0.0, 0.0, kRadius;
  m.faces.resize(2 * slices * rings, 3);
  int f = 0;
  auto ring = [slices](int k, int s) { return 1 + k * slices + (s % slices); };
  for (int s = 0; s < slices; ++s) m.faces.row(f++) << 0, ring(0, s + 1), ring(0, s);
  for (int k = 0; k + 1 < rings; ++k) {
    for (int s = 0; s < slices; ++s) {
      m.faces.row(f++) << ring(k, s), ring(k, s + 1), ring(k + 1, s + 1);
      m.faces.row(f++) << ring(k, s), ring(k + 1, s + 1), ring(k + 1, s);
    }
  }
  for (int s = 0; s < slices; ++s) m.faces.row(f++) << top, ring(rings - 1, s), ring(rings - 1, s + 1);
  m.x1 = m.x0;
  m.friction = 0.4;
  return m;
}

// Inverse rest-shape matrices that make the current shape of `sheet` its rest shape.
std::vector<Mat2> rest_shapes(const CollisionMesh& sheet) {
  std::vector<Mat2> dm_inv;
  for (int f = 0; f < sheet.faces.rows(); ++f) {
    const Vec3 a = sheet.x0.row(sheet.faces(f, 0)).transpose();
    const Vec3 e1 = sheet.x0.row(sheet.faces(f, 1)).transpose() - a;
    const Vec3 e2 = sheet.x0.row(sheet.faces(f, 2)).transpose() - a;
    const Vec3 u = e1.normalized();
    const Vec3 w = (e2 - e2.dot(u) * u).normalized();
    Mat2 dm;
    dm << e1.dot(u), e2.dot(u), 0.0, e2.dot(w);
    dm_inv.push_back(dm.inverse());
  }
  return dm_inv;
}

// Sheet draped over the sphere: each vertex 4 mm outside the sphere's faceted surface above
// it (inside the 5 mm thickness), the rim hanging on at the cap's slope.
void drape(CollisionMesh& sheet) {
  const double lift = kRadius + 4e-3;
  for (int v = 0; v < sheet.x0.rows(); ++v) {
    const double r = std::hypot(sheet.x0(v, 0), sheet.x0(v, 1));
    const double rim = 0.6 * lift;
    const double z = r <= rim ? std::sqrt(lift * lift - r * r)
                              : std::sqrt(lift * lift - rim * rim) - (r - rim) * rim /
                                                                          std::sqrt(lift * lift - rim * rim);
    sheet.x0(v, 2) = z;
  }
  sheet.x1 = sheet.x0;
}

void BM_SheetOnSphere(benchmark::State& bench) {
  const int n = static_cast<int>(bench.range(0));
  const bool resting = bench.range(1) != 0;
  const double size = 1e-3 * static_cast<double>(bench.range(2));
  const int threads = static_cast<int>(bench.range(3));
  CollisionMesh sheet = make_sheet(n, kRadius + 0.02, size);
  if (resting) drape(sheet);
  CollisionMesh sphere = make_sphere(16, 8);
  const std::vector<Mat2> dm_inv = rest_shapes(sheet);
  const std::vector<CollisionMesh*> meshes{&sheet, &sphere};
  // Step motion: free fall at 1 m/s, or one step of gravity from rest.
  const Points x0 = sheet.x0;
  Points x1 = x0;
  x1.col(2).array() -= resting ? kDt * kDt * 9.81 : kDt * 1.0;

  RepulsionOptions repulsion;
  repulsion.thickness = kThickness;
  repulsion.dt = kDt;
  repulsion.friction = false;
  StrainLimitOptions strain;
  ImpactZoneOptions zones;
  zones.offset = 0.03 * kThickness;
  ClothContacts contacts;
  ImpactZoneSolver solver;
  WorkerPool pool(threads);
  contacts.candidates.set_pool(threads > 1 ? &pool : nullptr);
  solver.set_pool(threads > 1 ? &pool : nullptr);
  double t_contacts = 0.0, t_strain = 0.0, t_zones = 0.0;
  int warnings = 0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : bench) {
    sheet.x0 = x0;
    sheet.x1 = x1;
    const auto t0 = Clock::now();
    detect_cloth_contacts(meshes, repulsion, contacts);
    const auto t1 = Clock::now();
    const StrainLimitReport limited =
        limit_strain(sheet.x1, sheet.faces, dm_inv, sheet.mass, sheet.frozen, strain);
    const auto t2 = Clock::now();
    const ImpactZoneReport report = solver.resolve(meshes, zones);
    const auto t3 = Clock::now();
    t_contacts += std::chrono::duration<double, std::milli>(t1 - t0).count();
    t_strain += std::chrono::duration<double, std::milli>(t2 - t1).count();
    t_zones += std::chrono::duration<double, std::milli>(t3 - t2).count();
    warnings += static_cast<int>(report.warnings.size()) + (limited.converged ? 0 : 1);
    benchmark::DoNotOptimize(sheet.x1.data());
  }
  const auto per_step = benchmark::Counter::kAvgIterations;
  bench.counters["triangles"] = static_cast<double>(sheet.faces.rows());
  bench.counters["contacts"] = static_cast<double>(contacts.contacts.size());
  bench.counters["vf_pairs"] = static_cast<double>(contacts.candidates.vertex_face().size());
  bench.counters["ee_pairs"] = static_cast<double>(contacts.candidates.edge_edge().size());
  bench.counters["proximity_ms"] = benchmark::Counter(t_contacts, per_step);
  bench.counters["strain_ms"] = benchmark::Counter(t_strain, per_step);
  bench.counters["zones_ms"] = benchmark::Counter(t_zones, per_step);
  bench.counters["warnings"] = benchmark::Counter(warnings, per_step);
}

}  // namespace

// Args: quads per side (2·n² triangles), resting (1) or falling (0), sheet size [mm]: 1 m
// (edges of 31–7.8 mm, longer than the 5 mm thickness), or 0.3 m at n = 64, pinch_move's sheet
// (4.8 mm edges, under the thickness: every face has dozens of rest neighbours in reach);
// threads.
BENCHMARK(BM_SheetOnSphere)
    ->ArgsProduct({{32, 64, 128}, {0, 1}, {1000}, {1}})
    ->ArgsProduct({{64}, {0, 1}, {300}, {1, 2}})
    ->ArgNames({"n", "resting", "size_mm", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

BENCHMARK_MAIN();
