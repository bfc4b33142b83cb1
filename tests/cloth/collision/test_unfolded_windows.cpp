#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/unfolded_subtrees.hpp"
#include "cloth/collision/unfolded_windows.hpp"
#include "mesh_builders.hpp"
#include "self_contact_checks.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

constexpr double kStride = 16e-3;  // about what CollisionCandidates takes on this 5 mm grid

/// A cloth's tree, subtrees and windows at its x0 (proximity search).
struct Culling {
  Bvh bvh;
  UnfoldedSubtrees subtrees;
  UnfoldedWindows windows;

  explicit Culling(const CollisionMesh& m) {
    bvh.build(m.faces, m.x0, m.x0, 0.5 * kReach);
    subtrees.build(m.rest, m.faces, bvh);
    subtrees.update(bvh, m.x0, kRestDistance, kReach);
    windows.build(subtrees.rest_plane(), m.faces,
                  build_topology(m.faces, static_cast<int>(m.x0.rows())), subtrees.rest_boxes(),
                  kStride);
    windows.update(m.x0, kRestDistance - 2.0 * subtrees.flatness(), kReach);
  }
  /// The face pairs of the self query, leaving out what `skip` says.
  std::vector<FacePair> pairs(const QuerySkip& skip, int pieces = 1) const {
    std::vector<BvhQuery> queries;
    split_query(bvh, bvh, true, pieces, queries, &skip);
    std::vector<FacePair> out;
    for (const BvhQuery& q : queries) run_query(bvh, bvh, q, nullptr, out, &skip);
    return out;
  }
};

/// How many windows are covered once (of every level, or of one), and how many flagged.
int covered(const UnfoldedWindows& w) {
  int n = 0;
  for (std::size_t k = 0; k < w.num_windows(); ++k) n += w.covered(k);
  return n;
}

int covered(const UnfoldedWindows& w, int level) {
  int n = 0;
  const std::size_t first = w.first_window(level);
  for (std::size_t k = first; k < first + w.level_windows(level); ++k) n += w.covered(k);
  return n;
}

int flagged(const UnfoldedWindows& w) {
  int n = 0;
  for (std::size_t k = 0; k < w.num_windows(); ++k) n += w.flagged(k);
  return n;
}

/// The n × n sheet of 5 mm quads waved along x: z = A·sin(2π·x/λ).
CollisionMesh wavy_sheet(int n, double amplitude, double length) {
  CollisionMesh m = sheet(n);
  for (int v = 0; v < m.x0.rows(); ++v)
    m.x0(v, 2) = amplitude * std::sin(2.0 * M_PI * m.x0(v, 0) / length);
  m.x1 = m.x0;
  return m;
}

/// Slides the vertices `upper` of `m`, a mesh whose rest shape covers its rest plane twice, by
/// 10 mm and lifts them by 3 mm: every face keeps its shape and turn, but points of the two
/// layers 10 mm apart at rest meet. No window may count, and every close pair is found.
template <typename Upper>
void expect_layers_found_without_windows(CollisionMesh& m, Upper upper) {
  for (int v = 0; v < m.x0.rows(); ++v)
    if (upper(v)) m.x0.row(v) += Vec3(10e-3, 0.0, 3e-3).transpose();
  m.x1 = m.x0;
  EXPECT_EQ(covered(Culling(m).windows), 0);
  EXPECT_GT(expect_every_close_pair_found(m), 100);
}

}  // namespace

TEST(UnfoldedWindows, AWavySheetIsUnfoldedInEveryWindowThoughNotInItsBiggerSubtrees) {
  // Waves 5 cm long and 4 mm high (radius of curvature down to 1.6 cm, faces turned up to 27°):
  // no patch wider than a centimetre lies within 1.4 mm of a plane, but within a window of
  // 32 mm no face turns by more than 54° from another, and κ ≥ cos 27°·0.99.
  const CollisionMesh m = wavy_sheet(40, 4e-3, 50e-3);
  const Culling c(m);
  EXPECT_EQ(covered(c.windows), static_cast<int>(c.windows.num_windows()));
  EXPECT_EQ(flagged(c.windows), static_cast<int>(c.windows.num_windows()));
  int big_flagged = 0;
  for (int i = 0; i < c.bvh.num_nodes(); ++i)
    big_flagged += c.bvh.subtree_faces(i) > 32 && c.subtrees.flags()[static_cast<std::size_t>(i)];
  EXPECT_EQ(big_flagged, 0);
  // The windows leave out most of the face pairs the subtrees leave in.
  const std::size_t subtrees_only =
      c.pairs({&c.subtrees.flags(), nullptr, nullptr, nullptr}).size();
  const std::size_t both = c.pairs({&c.subtrees.flags(), &c.windows, nullptr, nullptr}).size();
  EXPECT_GT(subtrees_only, 10000u);
  EXPECT_LT(both, subtrees_only / 4);
  // Folded to a U within a window (its right part laid back 3 mm above the left), the windows
  // over the fold are not flagged, the others still are.
  CollisionMesh folded = sheet(40);
  for (int v = 0; v < folded.x0.rows(); ++v) {
    const double u = folded.rest(v, 0);
    if (u > 0.0) {  // a half circle of radius 1.5 mm, then flat
      const double a = std::min(u / 1.5e-3, M_PI);
      const double beyond = u - 1.5e-3 * a;
      folded.x0.row(v) << 1.5e-3 * std::sin(a) - beyond, folded.rest(v, 1),
          1.5e-3 * (1.0 - std::cos(a));
    }
  }
  folded.x1 = folded.x0;
  const Culling f(folded);
  const int some = flagged(f.windows);
  EXPECT_GT(some, 0);
  EXPECT_LT(some, static_cast<int>(f.windows.num_windows()));
  EXPECT_GT(expect_every_close_pair_found(folded), 1000);
}

TEST(UnfoldedWindows, TheCandidatesOfAWavySheetUseItsWindowsInBothSearches) {
  // The wavy sheet through CollisionCandidates: the proximity and the swept search both leave
  // pairs out by its windows, every one of them flagged (the candidate tests elsewhere only show
  // that nothing within reach is lost, which holds without any culling).
  const CollisionMesh m = wavy_sheet(40, 4e-3, 50e-3);
  CollisionCandidates candidates;
  candidates.set_rest_neighbour_distance(kRestDistance);
  for (const bool swept : {false, true}) {
    candidates.update({&m}, swept, swept ? 0.5e-3 : 0.5 * kReach);
    const UnfoldedWindows* w = candidates.windows(0);
    ASSERT_NE(w, nullptr) << swept;
    EXPECT_EQ(flagged(*w), static_cast<int>(w->num_windows())) << swept;
  }
  // A flat sheet is left out whole by its subtrees: no windows are asked.
  const CollisionMesh flat = sheet(40);
  candidates.update({&flat}, false, 0.5 * kReach);
  EXPECT_EQ(candidates.windows(0), nullptr);
}

TEST(UnfoldedWindows, NoPairWithinTheReachIsLeftOutOfWrinkledAndFoldedSheets) {
  // Seeded wrinkles (waves 2 to 6 cm long, 1 to 5 mm high) and, every other run, a fold of
  // radius 1.5 to 4 mm along a tilted line: every pair within the reach that is not a rest
  // neighbour is still a candidate (tested against every pair of the mesh).
  Uniform uniform{99u};
  int flagged_runs = 0, close_pairs = 0;
  for (int run = 0; run < 8; ++run) {
    CollisionMesh m = sheet(24);
    std::vector<std::array<double, 4>> waves;  // kx, ky, phase, amplitude
    for (int k = 0; k < 3; ++k) {
      const double length = 0.02 + 0.04 * uniform(), angle = 2.0 * M_PI * uniform();
      waves.push_back({2.0 * M_PI / length * std::cos(angle), 2.0 * M_PI / length * std::sin(angle),
                       2.0 * M_PI * uniform(), 1e-3 + 4e-3 * uniform()});
    }
    const double radius = 1.5e-3 + 2.5e-3 * uniform(), tilt = 0.5 * (uniform() - 0.5);
    const Vec3 across(std::cos(tilt), std::sin(tilt), 0.0);
    for (int v = 0; v < m.x0.rows(); ++v) {
      Vec3 p = m.rest.row(v).transpose();
      for (const auto& [kx, ky, phase, a] : waves)
        p.z() += a * std::sin(kx * m.rest(v, 0) + ky * m.rest(v, 1) + phase);
      const double u = p.dot(across) - 0.01 * (run % 3);
      if (run % 2 == 1 && u > 0.0) {  // folded back over the sheet around a half cylinder
        const double a = std::min(u / radius, M_PI), beyond = u - radius * a;
        p += (radius * std::sin(a) - beyond - u) * across +
             Vec3(0.0, 0.0, radius * (1.0 - std::cos(a)));
      }
      m.x0.row(v) = p.transpose();
    }
    m.x1 = m.x0;
    flagged_runs += flagged(Culling(m).windows) > 0;
    close_pairs += expect_every_close_pair_found(m);
  }
  EXPECT_GE(flagged_runs, 6);
  EXPECT_GT(close_pairs, 1000);
}

TEST(UnfoldedWindows, TheBoundHoldsOnASheetSqueezedJustPastIt) {
  // A sheet with its rest vertices jittered by up to 1 mm (so rest distances take every value)
  // squeezed uniformly in its plane to c along a direction: every face's κ is c, so points
  // d ≥ 7.85 mm apart at rest stay c·d apart. Below c = 5/7.85 = 0.637 pairs 7.85 to 5/c mm
  // apart at rest come within the reach, and no window may be flagged; above it, every window
  // is.
  Uniform uniform{7u};
  int close_pairs = 0;
  for (const double c : {0.56, 0.6, 0.63, 0.645}) {
    CollisionMesh m = sheet(16);
    for (int v = 0; v < m.rest.rows(); ++v) {
      m.rest(v, 0) += 1e-3 * (2.0 * uniform() - 1.0);
      m.rest(v, 1) += 1e-3 * (2.0 * uniform() - 1.0);
    }
    const double angle = 2.0 * M_PI * uniform();
    const Vec3 n(std::cos(angle), std::sin(angle), 0.0);
    for (int v = 0; v < m.x0.rows(); ++v) {
      const Vec3 u = m.rest.row(v).transpose();
      m.x0.row(v) = (u - (1.0 - c) * u.dot(n) * n).transpose();
    }
    m.x1 = m.x0;
    const Culling culling(m);
    const int once = covered(culling.windows);
    EXPECT_GT(once, 0);
    EXPECT_EQ(flagged(culling.windows), c < 0.637 ? 0 : once) << c;
    close_pairs += expect_every_close_pair_found(m);
  }
  EXPECT_GT(close_pairs, 50);
}

TEST(UnfoldedWindows, TwoSheetsAtOneRestPlaceAreNotCovered) {
  // One mesh of two equal sheets with the same rest shape: covered twice with one orientation,
  // no boundary inside.
  const CollisionMesh one = sheet(12);
  const auto nv = static_cast<int>(one.x0.rows());
  CollisionMesh m = one;
  m.x0.resize(2 * nv, 3);
  m.x0 << one.x0, one.x0;
  m.rest = m.x0;
  m.faces.resize(2 * one.faces.rows(), 3);
  m.faces << one.faces, one.faces.array() + nv;
  m.mass = Eigen::VectorXd::Constant(2 * nv, 1e-4);
  expect_layers_found_without_windows(m, [&](int v) { return v >= nv; });
}

TEST(UnfoldedWindows, AWindowOverASlitIsNotCovered) {
  // The sheet cut along x = 0 (the right half's vertices there doubled), then its right half
  // slid 12 mm left and lifted 3 mm over the left one: every face keeps its rest shape and
  // turn (κ = 1 everywhere), but the halves' faces 12 mm apart at rest are 3 mm apart.
  CollisionMesh m = sheet(20);
  const int row = 21;
  const auto nv = static_cast<int>(m.x0.rows());
  Points x(nv + row, 3);
  x.topRows(nv) = m.x0;
  for (int j = 0; j < row; ++j) x.row(nv + j) = m.x0.row(j * row + 10);
  for (int f = 0; f < m.faces.rows(); ++f) {
    const double cx = (x(m.faces(f, 0), 0) + x(m.faces(f, 1), 0) + x(m.faces(f, 2), 0)) / 3.0;
    if (cx < 0.0) continue;
    for (int k = 0; k < 3; ++k)
      if (m.faces(f, k) % row == 10) m.faces(f, k) = nv + m.faces(f, k) / row;
  }
  m.rest = x;
  m.x0 = x;
  for (int v = 0; v < m.x0.rows(); ++v)
    if (v >= nv || (v % row) > 10) m.x0.row(v) += Vec3(-12e-3, 0.0, 3e-3).transpose();
  m.x1 = m.x0;
  m.mass = Eigen::VectorXd::Constant(m.x0.rows(), 1e-4);
  const Culling c(m);
  // 7 × 7 windows of 32 mm at 16 mm steps from −50 mm (along the rest plane's axes, which lie
  // along x and y in some order): two rows or columns of them span the cut at 0. Of the second
  // level's 4 × 4, of 64 mm at 32 mm steps, two (from −50 and −18 mm) do.
  ASSERT_EQ(c.windows.num_levels(), 2);
  ASSERT_EQ(c.windows.level_windows(0), 49u);
  ASSERT_EQ(c.windows.level_windows(1), 16u);
  EXPECT_EQ(covered(c.windows, 0), 49 - 14);
  EXPECT_EQ(covered(c.windows, 1), 16 - 8);
  EXPECT_GT(expect_every_close_pair_found(m), 100);
}

TEST(UnfoldedWindows, ARestShapeFoldedFlatOnItselfIsNotCovered) {
  // A 40 × 10 strip whose rest shape is folded flat in half: its right half laid back onto the
  // left in the rest plane, covered twice.
  CollisionMesh m = make_sheet(40, 10, 0.2, 0.05, Vec3(-0.1, 0.0, 0.0), 1e-4);
  for (int v = 0; v < m.x0.rows(); ++v)
    if (m.x0(v, 0) > 0.0) m.x0(v, 0) = -m.x0(v, 0);
  m.rest = m.x0;
  expect_layers_found_without_windows(m, [](int v) { return v % 41 > 20; });
}

TEST(UnfoldedWindows, AHoleUncoversTheWindowsAroundItOnly) {
  // The faces of four quads at the sheet's centre taken out: the windows reaching into the hole
  // are not covered once, every other one is.
  CollisionMesh m = sheet(20);
  Triangles kept(m.faces.rows(), 3);
  int k = 0;
  for (int f = 0; f < m.faces.rows(); ++f) {
    const Vec3 c =
        (m.x0.row(m.faces(f, 0)) + m.x0.row(m.faces(f, 1)) + m.x0.row(m.faces(f, 2))).transpose() /
        3.0;
    if (std::abs(c.x()) < 5e-3 && std::abs(c.y()) < 5e-3) continue;
    kept.row(k++) = m.faces.row(f);
  }
  ASSERT_EQ(k, m.faces.rows() - 8);
  m.faces = kept.topRows(k);
  const Culling c(m);
  // 7 × 7 windows of 32 mm at 16 mm steps from −50 mm: three rows and three columns of them
  // reach into the hole (−5 to 5 mm), the rest are covered once; of the second level's 4 × 4,
  // of 64 mm at 32 mm steps, two rows and two columns.
  ASSERT_EQ(c.windows.level_windows(0), 49u);
  EXPECT_EQ(covered(c.windows, 0), 49 - 9);
  EXPECT_EQ(covered(c.windows, 1), 16 - 4);
}

TEST(Bvh, AFlaggedWindowLeavesOutThePairsOfNodesWithinItOnly) {
  // A wavy sheet's self query with every window flagged: the pairs left out are those whose two
  // faces' rest boxes fit in a window, split into pieces or not. (With some windows unflagged
  // a node pair may fit in a flagged window that its faces' pairs, one cell up, do not.)
  const CollisionMesh m = wavy_sheet(20, 2e-3, 40e-3);
  const Culling c(m);
  const std::vector<FacePair> all = c.pairs({});
  ASSERT_EQ(flagged(c.windows), static_cast<int>(c.windows.num_windows()));
  std::vector<int> leaf(static_cast<std::size_t>(m.faces.rows()));
  for (int i = 0; i < c.bvh.num_nodes(); ++i)
    if (c.bvh.leaf_face(i) >= 0) leaf[static_cast<std::size_t>(c.bvh.leaf_face(i))] = i;
  std::vector<FacePair> expected;
  for (const FacePair& p : all)
    if (!c.windows.skips(leaf[static_cast<std::size_t>(p.a)], leaf[static_cast<std::size_t>(p.b)]))
      expected.push_back(p);
  ASSERT_LT(expected.size(), all.size() / 2);
  for (const int pieces : {1, 7, 64}) {
    const std::vector<FacePair> found = c.pairs({nullptr, &c.windows, nullptr, nullptr}, pieces);
    ASSERT_EQ(found.size(), expected.size()) << pieces << " pieces";
    for (std::size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].a, expected[k].a);
      EXPECT_EQ(found[k].b, expected[k].b);
    }
  }
}

TEST(UnfoldedWindows, APairTooWideForTheFirstLevelIsAskedOfTheSecond) {
  // A wavy sheet, every window of both levels flagged: a pair of nodes is left out exactly when
  // its rest boxes together span at most two cells of the first level (16 mm) or, failing that,
  // of the second (32 mm) on each axis, the cells counted from the sheet's rest corner.
  const CollisionMesh m = wavy_sheet(40, 4e-3, 50e-3);
  const Culling c(m);
  ASSERT_EQ(c.windows.num_levels(), 2);
  ASSERT_EQ(flagged(c.windows), static_cast<int>(c.windows.num_windows()));
  const std::vector<double>& box = c.subtrees.rest_boxes();
  const auto cells = [&](int i, int j, int level, int axis) {
    const auto cell = [&](double u) {
      return static_cast<int>(std::floor((u - box[static_cast<std::size_t>(axis)]) / kStride)) >>
             level;
    };
    const auto at = [&](int node, int k) { return box[4 * static_cast<std::size_t>(node) + k]; };
    const auto a = static_cast<std::size_t>(axis);
    return cell(std::max(at(i, 2 + a), at(j, 2 + a))) - cell(std::min(at(i, a), at(j, a))) + 1;
  };
  int first = 0, second = 0, neither = 0;
  for (int i = 0; i < c.bvh.num_nodes(); ++i) {
    if (c.bvh.subtree_faces(i) < 8 || c.bvh.subtree_faces(i) > 256) continue;
    for (int j = i; j < c.bvh.num_nodes(); j += 7) {
      if (c.bvh.subtree_faces(j) < 8 || c.bvh.subtree_faces(j) > 256) continue;
      const bool fits_first = cells(i, j, 0, 0) <= 2 && cells(i, j, 0, 1) <= 2;
      const bool fits_second = cells(i, j, 1, 0) <= 2 && cells(i, j, 1, 1) <= 2;
      first += fits_first;
      second += !fits_first && fits_second;
      neither += !fits_first && !fits_second;
      EXPECT_EQ(c.windows.skips(i, j), fits_first || fits_second) << i << " " << j;
    }
  }
  EXPECT_GT(first, 100);
  EXPECT_GT(second, 100);
  EXPECT_GT(neither, 100);
}
