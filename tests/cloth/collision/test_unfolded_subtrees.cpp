#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <tuple>

#include "cloth/collision/bvh.hpp"
#include "cloth/collision/ccd.hpp"
#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/rest_neighbours.hpp"
#include "cloth/collision/unfolded_subtrees.hpp"
#include "mesh_builders.hpp"
#include "self_contact_checks.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

/// The flags of `m`'s tree at its x0.
std::vector<std::uint8_t> flags(const CollisionMesh& m, double rest_distance = kRestDistance) {
  Bvh bvh;
  bvh.build(m.faces, m.x0, m.x0, 0.5 * kReach);
  UnfoldedSubtrees unfolded;
  unfolded.build(m.rest, m.faces, bvh);
  unfolded.update(bvh, m.x0, rest_distance, kReach);
  return unfolded.flags();
}

/// Whether any subtree of `m`'s tree is flagged at its x0.
bool any_flagged(const CollisionMesh& m) {
  const std::vector<std::uint8_t> f = flags(m);
  return std::any_of(f.begin(), f.end(), [](std::uint8_t x) { return x != 0; });
}

/// A seeded family of deformed sheets: how many runs leave some subtree out, and how many
/// close pairs they hold (else a test of them shows nothing).
struct Runs {
  int flagged = 0;
  int close_pairs = 0;
  /// Checks sheet `m` at rest (x1 = x0) against every pair, and counts it.
  void check(CollisionMesh& m) {
    m.x1 = m.x0;
    flagged += any_flagged(m);
    close_pairs += expect_every_close_pair_found(m);
  }
};

/// The sheet with its tree, waving from step to step (waves that grow with t, and a growing
/// shear), and the flags of a fresh UnfoldedSubtrees updated once.
struct WavingSheet {
  static constexpr double kSweptReach = 1e-3;
  const CollisionMesh m = sheet();
  Bvh bvh;
  MeshTopology topology;

  WavingSheet() {
    bvh.build(m.faces, m.x0, m.x0, 0.5 * kReach);
    topology = build_topology(m.faces, static_cast<int>(m.x0.rows()));
  }
  /// The positions at time t.
  Points at(double t) const {
    Points x = m.rest;
    for (int v = 0; v < x.rows(); ++v) {
      const double u = m.rest(v, 0), w = m.rest(v, 1);
      x(v, 2) = (0.6e-3 + 0.5e-3 * t) * std::sin(180.0 * u + 3.0 * t) * std::cos(140.0 * w - t);
      x(v, 0) += 0.4e-3 * t * std::cos(150.0 * w);
    }
    return x;
  }
  /// An UnfoldedSubtrees of the sheet, built.
  UnfoldedSubtrees subtrees() const {
    UnfoldedSubtrees u;
    u.build(m.rest, m.faces, bvh);
    return u;
  }
  /// A fresh object's flags at x0 (proximity, `x1` null) or over x0 → x1 (swept).
  std::vector<std::uint8_t> fresh_flags(const Points& x0, const Points* x1) const {
    UnfoldedSubtrees u = subtrees();
    if (x1 == nullptr) {
      u.update(bvh, x0, kRestDistance, kReach);
    } else {
      u.update_swept(bvh, m.faces, topology, x0, *x1, kSweptReach);
    }
    return u.flags();
  }
};

}  // namespace

TEST(UnfoldedSubtrees, AFlatSheetMovedRigidlyAndStretchedIsOneSubtree) {
  // Turned about a tilted axis, moved and stretched by 5 % in one direction: an affine image
  // of its rest shape, so the root holds no contact; nor does it at rest.
  CollisionMesh m = sheet();
  EXPECT_EQ(flags(m)[0], 1);
  const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  for (int v = 0; v < m.x0.rows(); ++v)
    m.x0.row(v) =
        (turn * Vec3(1.05 * m.rest(v, 0), m.rest(v, 1), 0.0) + Vec3(0.3, -1.0, 2.0)).transpose();
  EXPECT_EQ(flags(m)[0], 1);
  // Not when the rest distance does not exceed the reach: every pair could then be a contact.
  EXPECT_EQ(flags(m, kReach)[0], 0);
  // Nor when the sheet is squeezed to 60 % in one direction, where points 7.85 mm apart at rest
  // come within 4.7 mm of each other.
  for (int v = 0; v < m.x0.rows(); ++v) m.x0.row(v) << 0.6 * m.rest(v, 0), m.rest(v, 1), 0.0;
  EXPECT_EQ(flags(m)[0], 0);
}

TEST(UnfoldedSubtrees, ASheetWithAFoldIsNotOneButItsSingleLayerIs) {
  // Its right quarter folded back over the next one, 3 mm above it: the root's fit is far from
  // the layers, while subtrees of the single layer on the left are flat.
  CollisionMesh m = sheet();
  for (int v = 0; v < m.x0.rows(); ++v)
    if (m.x0(v, 0) > 0.025) m.x0.row(v) << 0.05 - m.x0(v, 0), m.x0(v, 1), 3e-3;
  Bvh bvh;
  bvh.build(m.faces, m.x0, m.x0, 0.5 * kReach);
  const std::vector<std::uint8_t> f = flags(m);
  EXPECT_EQ(f[0], 0);
  // Faces under flagged nodes (the topmost ones): at least half the left half's.
  int covered = 0;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    if (f[static_cast<std::size_t>(i)] != 0) {
      covered += bvh.subtree_faces(i);
    } else if (bvh.leaf_face(i) < 0) {
      stack.push_back(i + 1);
      stack.push_back(bvh.right_child(i));
    }
  }
  EXPECT_GT(covered, m.faces.rows() / 4);
  // And the search still finds every pair across the layers.
  EXPECT_GT(expect_every_close_pair_found(m), 300);
}

TEST(UnfoldedSubtrees, ACurvedRestShapeFlagsNothing) {
  // The sheet's rest shape rolled into a half cylinder of radius 3 cm: no rest plane, so no
  // distances measured in it can be trusted.
  CollisionMesh m = sheet();
  for (int v = 0; v < m.rest.rows(); ++v) {
    const double a = m.rest(v, 0) / 0.03;
    m.rest.row(v) << 0.03 * std::sin(a), m.rest(v, 1), 0.03 * (1.0 - std::cos(a));
  }
  m.x0 = m.rest;
  m.x1 = m.x0;
  for (const std::uint8_t x : flags(m)) EXPECT_EQ(x, 0);
}

TEST(UnfoldedSubtrees, NoPairWithinTheReachIsLeftOutOfCrumpledSheets) {
  // Seeded smooth crumples of growing amplitude (sums of waves 1 to 5 cm long, 0.3 to 2.4 mm
  // high, with some in-plane shear), every other one with a fold: whatever subtrees are left out,
  // every pair within the reach that is not a rest neighbour is still a candidate (tested against
  // every pair of the mesh).
  Uniform uniform{2024u};
  Runs runs;
  for (int run = 0; run < 8; ++run) {
    CollisionMesh m = sheet();
    const double amplitude = 0.3e-3 * (1 + run);
    std::vector<std::tuple<double, double, double, double>> waves;  // kx, ky, phase, amplitude
    for (int k = 0; k < 4; ++k) {
      const double length = 0.01 + 0.04 * uniform(), angle = 2.0 * M_PI * uniform();
      waves.emplace_back(2.0 * M_PI / length * std::cos(angle),
                         2.0 * M_PI / length * std::sin(angle), 2.0 * M_PI * uniform(),
                         amplitude * (0.5 + uniform()));
    }
    for (int v = 0; v < m.x0.rows(); ++v) {
      double z = 0.0, dx = 0.0;
      for (const auto& [kx, ky, phase, a] : waves) {
        const double s = kx * m.rest(v, 0) + ky * m.rest(v, 1) + phase;
        z += a * std::sin(s);
        dx += 0.5 * a * std::cos(s);  // in-plane shear: squeezes some rows together
      }
      m.x0.row(v) << m.rest(v, 0) + dx, m.rest(v, 1), z;
    }
    if (run % 2 == 1) {  // fold the right third back over the sheet, 2 mm above it
      for (int v = 0; v < m.x0.rows(); ++v)
        if (m.x0(v, 0) > 0.02) m.x0.row(v) << 0.04 - m.x0(v, 0), m.x0(v, 1), 2e-3 - m.x0(v, 2);
    }
    runs.check(m);
  }
  EXPECT_GE(runs.flagged, 4);
  EXPECT_GT(runs.close_pairs, 1000);
}

TEST(UnfoldedSubtrees, NoPairWithinTheReachIsLeftOutWhereTheSheetIsSqueezedInPlane) {
  // The flat sheet squeezed and stretched in its plane by a wave along a direction n,
  // x = u − A·sin(k·(u·n) + φ)·n (1.5 to 2.8 mm, 18 to 24 mm long, never folding over): points
  // d apart at rest across a squeezed stretch come within d − 2A·sin(kd/2), 3.3 mm for 8 mm at
  // A = 2.5 mm. A subtree over whole waves keeps F ≈ 1 and misses their ends by about A either
  // way; subtrees within half a wave fit closely.
  Runs runs;
  for (int run = 0; run < 8; ++run) {
    CollisionMesh m = sheet();
    const double amplitude = 1.5e-3 + 0.18e-3 * run, length = 18e-3 + 3e-3 * (run % 3);
    const double k = 2.0 * M_PI / length, angle = 0.4 * run, phase = 0.7 * run;
    const Vec3 n(std::cos(angle), std::sin(angle), 0.0);
    ASSERT_LT(amplitude * k, 1.0);  // no fold-over
    for (int v = 0; v < m.x0.rows(); ++v) {
      const Vec3 u = m.rest.row(v).transpose();
      m.x0.row(v) = (u - amplitude * std::sin(k * u.dot(n) + phase) * n).transpose();
    }
    runs.check(m);
  }
  EXPECT_GE(runs.flagged, 4);
  EXPECT_GT(runs.close_pairs, 100);
}

TEST(UnfoldedSubtrees, TheSweptSearchKeepsEveryPairThatCollidesOverTheStep) {
  // Crumpled sheets with a fold, moving over a step: a flat region moved rigidly, the folded
  // layer driven down 5 mm through the layer under it, and seeded jitter of growing size.
  Uniform uniform{77u};
  int hits = 0, left_out = 0;
  for (int run = 0; run < 6; ++run) {
    CollisionMesh m = sheet();
    const double jitter = 0.2e-3 * run;
    for (int v = 0; v < m.x0.rows(); ++v) {
      const double u = m.rest(v, 0), w = m.rest(v, 1);
      m.x0.row(v) << u, w, 1e-3 * std::sin(90.0 * u + run) * std::cos(70.0 * w);
      if (u > 0.025) m.x0.row(v) << 0.05 - u, w, 3e-3;  // the folded layer over the next
      m.x1.row(v) = m.x0.row(v) + Vec3(2e-3, -1e-3, 0.5e-3).transpose();
      if (u > 0.025) m.x1(v, 2) -= 5e-3;
      for (int k = 0; k < 3; ++k) m.x1(v, k) += jitter * (uniform() - 0.5);
    }
    const auto [h, out] = expect_every_collision_found(m);
    hits += h;
    left_out += out;
  }
  EXPECT_EQ(left_out, 6);
  EXPECT_GT(hits, 1000);
}

TEST(UnfoldedSubtrees, TheSweptSearchKeepsAVertexPokedThroughTheNextTriangle) {
  // The flat sheet, each of nine vertices v10 of a quad (diagonal v00–v11) pushed 4 mm toward
  // v01 while dropping from 0.5 mm above the sheet to 0.02 mm below it: it meets the triangle
  // across the diagonal, 3.54 mm away at rest (the sheet's least separation), 0.96 of the way
  // through the step. Only its own residual (about 4 mm at the end) keeps its subtree in:
  // the bound must use the least separation and the end state's ρ.
  CollisionMesh m = sheet();
  for (const int i : {3, 9, 15})
    for (const int j : {3, 9, 15}) {
      const int v10 = j * 21 + i + 1;
      m.x0(v10, 2) = 0.5e-3;
      m.x1.row(v10) << m.rest(v10, 0) - 4e-3 / std::sqrt(2.0),
          m.rest(v10, 1) + 4e-3 / std::sqrt(2.0), -0.02e-3;
    }
  const auto [hits, left_out] = expect_every_collision_found(m);
  EXPECT_TRUE(left_out);
  EXPECT_GE(hits, 9);
  // Turned half a turn about a tilted axis within the step, the sheet passes through that
  // axis at mid-step (the linear motion's map shrinks to rank one there): σ at the ends is 1,
  // and only the change of F between them keeps the subtrees in.
  CollisionMesh flip = sheet(8);
  const Mat3 half_turn =
      Eigen::AngleAxisd(M_PI, Vec3(0.0, 0.2, 1.0).normalized()).toRotationMatrix();
  for (int v = 0; v < flip.x1.rows(); ++v)
    flip.x1.row(v) = (half_turn * flip.x0.row(v).transpose()).transpose();
  EXPECT_GT(expect_every_collision_found(flip).first, 100);
}

TEST(UnfoldedSubtrees, KeptFitsFlagAsFreshOnes) {
  // A sheet waving through a run of steps, searched as a step does: each step's swept update
  // from the last one's end, a second round of the impact zones with the end moved, a proximity
  // update at the step's start, and a start one rounding unit off the last end. Every update
  // of the one object (whose fits at positions it has seen are reused) flags as an object
  // updated there alone.
  const WavingSheet w;
  UnfoldedSubtrees kept = w.subtrees();
  // Distinct flag sets seen, told apart by the sum of their flagged nodes' indices.
  std::set<long> seen;
  const auto signature = [](const std::vector<std::uint8_t>& f) {
    long sum = 0;
    for (std::size_t i = 0; i < f.size(); ++i) sum += f[i] != 0 ? static_cast<long>(i) : 0;
    return sum;
  };
  int flagged = 0;
  for (int step = 0; step < 6; ++step) {
    Points x0 = w.at(step), x1 = w.at(step + 1);
    if (step == 4) x0(17, 1) = std::nextafter(x0(17, 1), 1.0);  // not the last end
    kept.update_swept(w.bvh, w.m.faces, w.topology, x0, x1, w.kSweptReach);
    EXPECT_EQ(kept.flags(), w.fresh_flags(x0, &x1)) << step;
    seen.insert(signature(kept.flags()));
    flagged += static_cast<int>(std::count(kept.flags().begin(), kept.flags().end(), 1));
    x1(40, 2) += 2e-3;  // the impact zones' next round: the same start, another end
    kept.update_swept(w.bvh, w.m.faces, w.topology, x0, x1, w.kSweptReach);
    EXPECT_EQ(kept.flags(), w.fresh_flags(x0, &x1)) << step;
    seen.insert(signature(kept.flags()));
    kept.update(w.bvh, x0, kRestDistance, kReach);
    EXPECT_EQ(kept.flags(), w.fresh_flags(x0, nullptr)) << step;
    seen.insert(signature(kept.flags()));
    flagged += static_cast<int>(std::count(kept.flags().begin(), kept.flags().end(), 1));
  }
  EXPECT_GE(seen.size(), 6u);
  EXPECT_GT(flagged, 100);
}

TEST(UnfoldedSubtrees, TwoSearchesSharingTheirFitsFitEachPositionOnce) {
  // A proximity search at each step's start and a swept search over the step, keeping their
  // fits in one place as the step has them: the swept search finds the start fitted, the next
  // proximity search its end, so six positions are fitted once each; every update flags as a
  // fresh object's. An object over another tree (a smaller sheet) leaves the shared fits alone.
  const WavingSheet w;
  UnfoldedSubtrees proximity = w.subtrees(), swept = w.subtrees();
  UnfoldedSubtrees::KeptFits kept;
  proximity.keep_fits_in(&kept);
  swept.keep_fits_in(&kept);
  const CollisionMesh small = sheet(8);
  Bvh small_bvh;
  small_bvh.build(small.faces, small.x0, small.x0, 0.5 * kReach);
  UnfoldedSubtrees other;
  other.build(small.rest, small.faces, small_bvh);
  other.keep_fits_in(&kept);
  int flagged = 0;
  for (int step = 0; step < 5; ++step) {
    const Points x0 = w.at(step), x1 = w.at(step + 1);
    proximity.update(w.bvh, x0, kRestDistance, kReach);
    EXPECT_EQ(proximity.flags(), w.fresh_flags(x0, nullptr)) << step;
    other.update(small_bvh, small.x0, kRestDistance, kReach);
    swept.update_swept(w.bvh, w.m.faces, w.topology, x0, x1, w.kSweptReach);
    EXPECT_EQ(swept.flags(), w.fresh_flags(x0, &x1)) << step;
    flagged += static_cast<int>(std::count(swept.flags().begin(), swept.flags().end(), 1));
  }
  EXPECT_EQ(proximity.fitted_sets(), 1);
  EXPECT_EQ(swept.fitted_sets(), 5);
  EXPECT_EQ(other.fitted_sets(), 1);
  EXPECT_GT(flagged, 100);
}

TEST(UnfoldedSubtrees, TheCandidatesOfSearchesSharingTheirFitsAreTheirOwn) {
  // Two CollisionCandidates sharing their fits (share_fits), searched as a step searches: the
  // pairs each finds are those of one that keeps its own, and the swept search fits only the
  // steps' ends.
  CollisionMesh m = sheet();
  const auto at = [&](double t) {  // waving, its right part folded back 2 mm over it
    Points x = m.rest;
    for (int v = 0; v < x.rows(); ++v) {
      x(v, 2) = 0.5e-3 * std::sin(250.0 * m.rest(v, 0) + t) * std::cos(200.0 * m.rest(v, 1));
      if (x(v, 0) > 0.02) x.row(v) << 0.04 - x(v, 0), x(v, 1), 2e-3 - x(v, 2);
    }
    return x;
  };
  CollisionCandidates proximity, swept, own_proximity, own_swept;
  for (CollisionCandidates* c : {&proximity, &own_proximity})
    c->set_rest_neighbour_distance(kRestDistance);
  swept.share_fits(proximity);
  const auto same = [](const CollisionCandidates& a, const CollisionCandidates& b) {
    if (a.vertex_face().size() != b.vertex_face().size() ||
        a.edge_edge().size() != b.edge_edge().size())
      return false;
    for (std::size_t k = 0; k < a.vertex_face().size(); ++k)
      if (a.vertex_face()[k].vertex != b.vertex_face()[k].vertex ||
          a.vertex_face()[k].face != b.vertex_face()[k].face)
        return false;
    for (std::size_t k = 0; k < a.edge_edge().size(); ++k)
      if (a.edge_edge()[k].edge_a != b.edge_edge()[k].edge_a ||
          a.edge_edge()[k].edge_b != b.edge_edge()[k].edge_b)
        return false;
    return true;
  };
  std::size_t pairs = 0;
  for (int step = 0; step < 4; ++step) {
    m.x0 = at(step);
    m.x1 = m.x0;
    proximity.update({&m}, false, 0.5 * kReach);
    own_proximity.update({&m}, false, 0.5 * kReach);
    EXPECT_TRUE(same(proximity, own_proximity)) << step;
    m.x1 = at(step + 1);
    swept.update({&m}, true, 0.5e-3);
    own_swept.update({&m}, true, 0.5e-3);
    EXPECT_TRUE(same(swept, own_swept)) << step;
    pairs += proximity.vertex_face().size() + swept.edge_edge().size();
  }
  EXPECT_GT(pairs, 1000u);
  ASSERT_NE(swept.unfolded(0), nullptr);
  EXPECT_EQ(proximity.unfolded(0)->fitted_sets(), 1);
  EXPECT_EQ(swept.unfolded(0)->fitted_sets(), 4);
  EXPECT_EQ(own_swept.unfolded(0)->fitted_sets(), 5);
}

TEST(Bvh, ASkippedNodeLeavesOutThePairsWithinItsSubtreeOnly) {
  // A flat sheet's self query with one flagged node: exactly the pairs whose faces both lie
  // under it go, split into pieces or not.
  const CollisionMesh m = sheet();
  Bvh bvh;
  bvh.build(m.faces, m.x0, m.x0, 0.5 * kReach);
  std::vector<FacePair> all;
  run_query(bvh, bvh, {0, 0, true}, nullptr, all);
  // Node 1 is the root's left subtree: its faces.
  std::vector<int> under(static_cast<std::size_t>(m.faces.rows()), 0);
  std::vector<int> stack{1};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    if (bvh.leaf_face(i) >= 0) {
      under[static_cast<std::size_t>(bvh.leaf_face(i))] = 1;
    } else {
      stack.push_back(i + 1);
      stack.push_back(bvh.right_child(i));
    }
  }
  std::vector<std::uint8_t> skip(static_cast<std::size_t>(bvh.num_nodes()), 0);
  skip[1] = 1;
  const QuerySkip self_skip{&skip, nullptr, nullptr, nullptr};
  std::vector<FacePair> expected;
  for (const FacePair& p : all)
    if (!(under[static_cast<std::size_t>(p.a)] && under[static_cast<std::size_t>(p.b)]))
      expected.push_back(p);
  ASSERT_LT(expected.size(), all.size());
  for (const int pieces : {1, 7, 64}) {
    std::vector<BvhQuery> queries;
    split_query(bvh, bvh, true, pieces, queries, &self_skip);
    std::vector<FacePair> found;
    for (const BvhQuery& q : queries) run_query(bvh, bvh, q, nullptr, found, &self_skip);
    ASSERT_EQ(found.size(), expected.size()) << pieces << " pieces";
    for (std::size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].a, expected[k].a);
      EXPECT_EQ(found[k].b, expected[k].b);
    }
  }
}
