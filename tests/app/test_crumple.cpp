/// A crumpled cloth on a table (tests/app/data/crumple.json): its many self-contacts must not
/// move it. Cloth–cloth friction acts in equal and opposite pairs, so on a frictionless table
/// the centre of mass keeps its velocity, and on a table with friction the heap comes to rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

/// Centre of mass of the recorded cloth at each frame, with vertex masses from the triangles
/// around each vertex (a uniform grid: the same weights as the lumped masses): {t, x, y, z}.
std::vector<std::array<double, 4>> centroids(const std::filesystem::path& out) {
  dexcloth::Triangles faces;
  const std::vector<ClothFrame> frames = cloth_frames(out, 0, &faces);
  std::vector<double> weight(frames.empty() ? 0 : static_cast<std::size_t>(frames[0].x.rows()),
                             0.0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) weight[static_cast<std::size_t>(faces(f, k))] += 1.0;
  double total = 0.0;
  for (double w : weight) total += w;
  std::vector<std::array<double, 4>> rows;
  for (const ClothFrame& frame : frames) {
    std::array<double, 4> row{frame.t, 0.0, 0.0, 0.0};
    for (Eigen::Index i = 0; i < frame.x.rows(); ++i)
      for (int a = 0; a < 3; ++a)
        row[static_cast<std::size_t>(a + 1)] +=
            weight[static_cast<std::size_t>(i)] * frame.x(i, a) / total;
    rows.push_back(row);
  }
  return rows;
}

/// The row at the first frame at or after t.
std::array<double, 4> at(const std::vector<std::array<double, 4>>& rows, double t) {
  for (const auto& r : rows)
    if (r[0] >= t - 1e-9) return r;
  return rows.back();
}

std::filesystem::path run_crumple(const std::string& name, const std::string& args = "") {
  const CliRun run = run_file(source_dir() / "tests" / "app" / "data" / "crumple.json", name, args);
  expect_intact(run.summary);
  return run.out;
}

}  // namespace

TEST(Crumple, OnAFrictionlessTableTheHeapsCentreOfMassKeepsItsVelocity) {
  // After the release (1.1 s) only gravity and the table's normal force act: the horizontal
  // momentum is constant. One-sided cloth–cloth friction had sent the heap off the table
  // (40 cm by 2.4 s); now it drifts at the 2–3 cm/s it was let go with. Only the scene's own
  // start holds this to 2 mm/s, though. Over eight starts (shifts of 0.1–0.5 mm, turns of
  // 0.5–1°, three OpenBLAS kernels) the velocity held to 0.4 mm/s in four, changed by 7 mm/s in
  // one, and in three the heap, let go at 0.1–0.2 m/s, went over the table's edge. On a 1.2 m
  // table the eight gave 0.1–1.5 mm/s in six and 18 and 75 mm/s in two: the per-vertex
  // cloth–cloth friction is not pairwise, so the two sides' impulses cancel only approximately
  // (README, "What it does not do yet").
  const auto c = centroids(run_crumple("crumple_frictionless", "--set /obstacles/0/friction=0"));
  const auto a = at(c, 1.6), b = at(c, 2.3), e = at(c, 3.0);
  for (int axis : {1, 2}) {
    const double v1 =
        (b[static_cast<std::size_t>(axis)] - a[static_cast<std::size_t>(axis)]) / (b[0] - a[0]);
    const double v2 =
        (e[static_cast<std::size_t>(axis)] - b[static_cast<std::size_t>(axis)]) / (e[0] - b[0]);
    EXPECT_NEAR(v1, v2, 2e-3) << "axis " << axis;
    EXPECT_LT(std::abs(v2), 0.1) << "axis " << axis;
  }
}

TEST(Crumple, OnATableWithFrictionTheHeapDoesNotCrawlAway) {
  // It had crawled 22 cm across the table from 2.2 s to 3.0 s, risen, and fallen off. The heap
  // is chaotic: any change of rounding gives another heap. So three starts (the scene's, the
  // napkin shifted 0.1 mm, turned 0.5°) are asserted together. It does not come to rest, either:
  // its creases keep opening against the friction and flaps fall, so the heap sinks (by up to
  // 22 mm in eight starts) and its centroid moves as it spreads. Over those eight starts (shifts
  // of 0.1–0.5 mm, turns of 0.5–1°, three OpenBLAS kernels) the centroid moved 1.4–25 mm, median
  // 5 mm (README). The 8 mm mesh is mangled where the hanging napkin lands (edges at 0.14–2.2 of
  // their rest length), and every step the repulsion pushes vertices against the stretched
  // membrane; the table's friction turns that jitter into some drift.
  const std::vector<std::string> starts = {
      "", "--set '/cloths/0/transform/translation=[0.0001,0,0.004]'",
      "--set '/cloths/0/transform/rotation_deg=[0,0,0.5]'"};
  std::vector<double> drifts;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const auto c = centroids(run_crumple("crumple_friction_" + std::to_string(k), starts[k]));
    const auto a = at(c, 2.2), b = at(c, 3.0);
    drifts.push_back(std::hypot(b[1] - a[1], b[2] - a[2]));
    EXPECT_LT(drifts.back(), 0.04) << "start " << k;
    EXPECT_LT(b[3], a[3] + 2e-3) << "start " << k << ": the heap rose";
    EXPECT_LT(b[3], 0.03) << "start " << k;  // a heap a few layers high, not risen
  }
  std::sort(drifts.begin(), drifts.end());
  EXPECT_LT(drifts[1], 0.015);  // the median
}
