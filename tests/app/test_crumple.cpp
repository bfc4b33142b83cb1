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

/// Expects the centroid's horizontal velocity over 1.6–2.3 s and over 2.3–3.0 s to agree within
/// 2 mm/s, and to stay under 0.2 m/s.
void expect_constant_velocity(const std::vector<std::array<double, 4>>& c,
                              const std::string& what) {
  const auto a = at(c, 1.6), b = at(c, 2.3), e = at(c, 3.0);
  for (int axis : {1, 2}) {
    const auto i = static_cast<std::size_t>(axis);
    const double v1 = (b[i] - a[i]) / (b[0] - a[0]), v2 = (e[i] - b[i]) / (e[0] - b[0]);
    EXPECT_NEAR(v1, v2, 2e-3) << what << " axis " << axis;
    EXPECT_LT(std::abs(v2), 0.2) << what << " axis " << axis;
  }
}

/// The starts each crumple test asserts together (the heap is chaotic): the scene's, the
/// napkin shifted 0.1 mm, and turned 0.5°.
const std::vector<std::string> kStarts = {
    "", "--set '/cloths/0/transform/translation=[0.0001,0,0.004]'",
    "--set '/cloths/0/transform/rotation_deg=[0,0,0.5]'"};

}  // namespace

TEST(Crumple, OnAFrictionlessTableTheHeapsCentreOfMassKeepsItsVelocity) {
  // After the release (1.1 s) only gravity and the table's normal force act: the horizontal
  // momentum is constant. One-sided cloth–cloth friction had sent the heap off the table
  // (40 cm by 2.4 s); pairs ending on the table's diagonal (a flat edge) then pushed it along
  // the other diagonal, changing its velocity by up to 75 mm/s in 0.7 s. The heap is let go at
  // up to 0.25 m/s (the handle holds its centre while the rest slides), so the table is made
  // 1.2 m wide here, out of reach of its edges. Cloth–cloth friction is solved per pair, with
  // equal and opposite impulses (6 Dec): over eight starts (shifts of 0.1–0.5 mm, turns of
  // 0.5–1°) the velocity changed by 0.00 mm/s in seven and 0.59 in the one let go at 0.25 m/s
  // (0.0–1.4 mm/s with three OpenBLAS kernels before, and 54 mm/s with AVX-512's, when each
  // vertex solved its own friction). Three of them are asserted.
  for (std::size_t k = 0; k < kStarts.size(); ++k) {
    const auto c = centroids(run_crumple("crumple_frictionless_" + std::to_string(k),
                                         "--set /obstacles/0/friction=0 --set "
                                         "'/obstacles/0/shape/box/size=[1.2,1.2,0.04]' " +
                                             kStarts[k]));
    expect_constant_velocity(c, "start " + std::to_string(k));
  }
}

TEST(Crumple, OnAFrictionlessTableMadeOfManyTrianglesTheHeapsCentreKeepsItsVelocity) {
  // The same on a table given as an OBJ mesh (tests/app/data/grid_table.obj) whose top is split
  // into 12 × 12 squares: its inner vertices, like its diagonals, are no features of the
  // surface, and pairs ending on them are left out (a cloth vertex beside one leans toward it).
  // With the scene's start the velocity changed by 0.00 mm/s (0.06 mm/s before such vertices
  // were left out; 0.31 with the napkin turned 0.5°).
  const auto c = centroids(
      run_crumple("crumple_grid_table",
                  "--set '/obstacles/0/shape={\"obj\":\"grid_table.obj\"}' --set "
                  "'/obstacles/0/transform/translation=[0,0,0]' --set /obstacles/0/friction=0"));
  expect_constant_velocity(c, "grid table");
}

TEST(Crumple, OnATableWithFrictionTheHeapDoesNotCrawlAway) {
  // It had crawled 22 cm across the table from 2.2 s to 3.0 s, risen, and fallen off. The heap
  // is chaotic: any change of rounding gives another heap. So three starts (the scene's, the
  // napkin shifted 0.1 mm, turned 0.5°) are asserted together. It does not come to rest,
  // either. The 8 mm mesh is mangled where the hanging napkin lands (edges at 0.14–2.2 of their
  // rest length), and every step the repulsion pushes vertices against the stretched membrane
  // (README); its creases open and close, flaps rise and fall, and the table's friction turns
  // that jitter into some drift. Over eight starts (shifts of 0.1–0.5 mm, turns of 0.5–1°, three
  // OpenBLAS kernels) the centroid moved 2.0–48 mm, median 16 mm, its height changed by −12 to
  // +7.9 mm and ended 9.6–29.9 mm up. (Before pairs ending on the table's flat diagonal were left
  // out, whose sideways push also held the heap: 1.4–25 mm, median 5, and it only sank.) With
  // cloth–cloth friction per pair (6 Dec; loftier heaps, whose standing flaps may topple in
  // the window), over another eight starts: 3.0–59 mm, median 10.5 (0.8–48, median 7.7, before
  // on those eight; run on to 4.5 s, one of them then crawled 23 cm and fell off the table).
  // With the impact zones holding cloth that skims the table along its normal (6 Dec), over
  // the same eight: 5.5–55 mm, median 13, ending 10.8–36.5 mm up (the scene's start 36.5).
  std::vector<double> drifts;
  for (std::size_t k = 0; k < kStarts.size(); ++k) {
    const auto c = centroids(run_crumple("crumple_friction_" + std::to_string(k), kStarts[k]));
    const auto a = at(c, 2.2), b = at(c, 3.0);
    drifts.push_back(std::hypot(b[1] - a[1], b[2] - a[2]));
    EXPECT_LT(drifts.back(), 0.06) << "start " << k;
    EXPECT_LT(b[3], a[3] + 0.01) << "start " << k << ": the heap rose";
    EXPECT_LT(b[3], 0.04) << "start " << k;  // a heap a few layers high, not risen
  }
  std::sort(drifts.begin(), drifts.end());
  EXPECT_LT(drifts[1], 0.025);  // the median
}
