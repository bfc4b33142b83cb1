#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "cloth/collision/closest_points.hpp"
#include "cloth/collision/collision_candidates.hpp"
#include "cloth/collision/obstacle_pieces.hpp"
#include "cloth/collision/proximity.hpp"
#include "core/worker_pool.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

std::vector<Proximity> proximities(const std::vector<const CollisionMesh*>& meshes,
                                   double thickness) {
  CollisionCandidates candidates;
  std::vector<Proximity> out;
  find_proximities(meshes, thickness, candidates, out);
  return out;
}

// A 3,200-face, 0.2 m sheet folded over itself 4 mm apart (its right half back over the left),
// crumpled by noise of 1 mm (a linear congruential sequence from `seed`) and moving down by
// about 2 mm (x1); its rest shape is the flat sheet.
CollisionMesh folded_crumpled_sheet(std::uint32_t seed) {
  CollisionMesh sheet = make_sheet(40, 40, 0.2, 0.2, Vec3(-0.1, -0.1, 0.0), 1e-4);
  sheet.rest = sheet.x0;
  std::uint32_t state = seed;
  const auto noise = [&] {
    state = state * 1664525u + 1013904223u;
    return 1e-3 * (static_cast<double>(state >> 8) / 16777216.0 - 0.5);
  };
  for (int v = 0; v < sheet.x0.rows(); ++v) {
    if (sheet.x0(v, 0) > 0.0) {
      sheet.x0(v, 0) = -sheet.x0(v, 0);
      sheet.x0(v, 2) = 4e-3;
    }
    for (int k = 0; k < 3; ++k) sheet.x0(v, k) += noise();
  }
  sheet.x1 = sheet.x0;
  for (int v = 0; v < sheet.x1.rows(); ++v) sheet.x1(v, 2) -= 2e-3 + noise();
  return sheet;
}

}  // namespace

TEST(Proximity, FlatSheetHasNoInPlaneSelfPairs) {
  // Grid spacing h = 5 mm: a vertex is h/√2 = 3.5 mm from the diagonal of a non-incident
  // triangle, and parallel diagonals are 3.5 mm apart. With a 4.5 mm thickness these in-plane
  // neighbours are within the thickness but are not contacts.
  CollisionMesh sheet = make_sheet(20, 20, 0.1, 0.1, Vec3::Zero(), 1e-4);
  EXPECT_TRUE(proximities({&sheet}, 4.5e-3).empty());
  // A gently curved sheet (1 mm bumps) has none either.
  for (int v = 0; v < sheet.x0.rows(); ++v) {
    sheet.x0(v, 2) = 1e-3 * std::sin(60.0 * sheet.x0(v, 0)) * std::cos(45.0 * sheet.x0(v, 1));
  }
  sheet.x1 = sheet.x0;
  EXPECT_TRUE(proximities({&sheet}, 4.5e-3).empty());
}

TEST(Proximity, StackedSheetsMeetAcrossTheirSurfaces) {
  // Two sheets 2 mm apart, offset in-plane: every pair is across the gap (within 60° of ±z,
  // exactly ±z at 2 mm where the closest point is interior) and every vertex of the upper sheet
  // that lies over the lower one has a vertex–face pair.
  CollisionMesh a = make_sheet(10, 10, 0.05, 0.05, Vec3(0, 0, 0), 1e-4);
  CollisionMesh b = make_sheet(10, 10, 0.05, 0.05, Vec3(0.0012, 0.0021, 2e-3), 1e-4);
  const std::vector<Proximity> found = proximities({&a, &b}, 4.5e-3);
  ASSERT_FALSE(found.empty());
  std::vector<int> over(static_cast<std::size_t>(b.x0.rows()), 0);
  for (const Proximity& p : found) {
    EXPECT_GE(std::abs(p.normal.z()), 0.5);
    EXPECT_GE(p.distance, 2e-3 - 1e-12);
    if (p.distance < 2e-3 + 1e-12) {
      EXPECT_NEAR(std::abs(p.normal.z()), 1.0, 1e-9);
    }
    if (!p.edge_edge && p.mesh[0] == 1) over[static_cast<std::size_t>(p.first)] = 1;
  }
  for (int v = 0; v < b.x0.rows(); ++v) {
    const bool inside = b.x0(v, 0) <= 0.05 && b.x0(v, 1) <= 0.05;
    if (inside) {
      EXPECT_EQ(over[static_cast<std::size_t>(v)], 1) << "vertex " << v;
    }
  }
}

TEST(Proximity, AnObstacleReachFindsTheMarkedObstaclesPairsBeyondTheThicknessButNoClothOnes) {
  // A sheet 7 mm over a box's top, and a second sheet 7 mm over the first; thickness 5 mm.
  CollisionMesh box = make_box(Vec3(-0.1, -0.1, -0.1), Vec3(0.2, 0.2, 0.0));
  CollisionMesh a = make_sheet(4, 4, 0.05, 0.05, Vec3(0, 0, 7e-3), 1e-4);
  CollisionMesh b = make_sheet(4, 4, 0.05, 0.05, Vec3(0, 0, 14e-3), 1e-4);
  const std::vector<const CollisionMesh*> meshes{&a, &b, &box};
  CollisionCandidates candidates;
  std::vector<Proximity> found;
  std::vector<std::vector<Proximity>> scratch;
  find_proximities(meshes, 5e-3, 5e-3, candidates, found, scratch);
  EXPECT_TRUE(found.empty());
  find_proximities(meshes, 5e-3, 10e-3, candidates, found, scratch);
  EXPECT_TRUE(found.empty());  // the box is not marked to be searched beyond the thickness
  box.beyond_thickness = true;
  find_proximities(meshes, 5e-3, 10e-3, candidates, found, scratch);
  std::vector<int> seen(static_cast<std::size_t>(a.x0.rows()), 0);
  for (const Proximity& p : found) {
    ASSERT_EQ(p.mesh[1], 2);  // the box: never the two sheets, 7 mm apart
    ASSERT_EQ(p.mesh[0], 0);
    EXPECT_FALSE(p.edge_edge);
    EXPECT_NEAR(p.distance, 7e-3, 1e-12);
    EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
    seen[static_cast<std::size_t>(p.first)] = 1;
  }
  for (int v = 0; v < a.x0.rows(); ++v) EXPECT_EQ(seen[static_cast<std::size_t>(v)], 1) << v;
  // Just short of 7 mm: none.
  find_proximities(meshes, 5e-3, 6.9e-3, candidates, found, scratch);
  EXPECT_TRUE(found.empty());
}

TEST(Proximity, ObstacleEdgesStillRepelAClothVertexBesideThem) {
  // A cloth vertex 3 mm beside the edge of an obstacle triangle, nearly in its plane (gap at 80°
  // from the face normal, which a cloth–cloth pair would not count): it is a contact, the
  // across-surface test applies to cloth pairs only.
  CollisionMesh obstacle;
  obstacle.obstacle = true;
  obstacle.x0.resize(3, 3);
  obstacle.x0 << -0.05, -0.05, 0.0, 0.0, -0.05, 0.0, 0.0, 0.05, 0.0;
  obstacle.x1 = obstacle.x0;
  obstacle.faces.resize(1, 3);
  obstacle.faces << 0, 1, 2;
  CollisionMesh cloth = make_sheet(1, 1, 0.01, 0.01, Vec3(0.003, 0.0, 0.0005), 1e-4);
  const std::vector<Proximity> found = proximities({&cloth, &obstacle}, 5e-3);
  bool vertex0 = false;
  for (const Proximity& p : found)
    vertex0 = vertex0 || (!p.edge_edge && p.mesh[0] == 0 && p.first == 0);
  EXPECT_TRUE(vertex0);
}

namespace {

/// A flat 10 cm square obstacle in z = 0, two triangles sharing the diagonal from (−5, −5) to
/// (5, 5) cm: the diagonal is no feature of its surface.
CollisionMesh flat_square() {
  CollisionMesh square;
  square.obstacle = true;
  square.x0.resize(4, 3);
  square.x0 << -0.05, -0.05, 0.0, 0.05, -0.05, 0.0, 0.05, 0.05, 0.0, -0.05, 0.05, 0.0;
  square.x1 = square.x0;
  square.faces.resize(2, 3);
  square.faces << 0, 1, 2, 0, 2, 3;
  return square;
}

}  // namespace

TEST(Proximity, AFlatObstaclesDiagonalGivesNoSidewaysNormal) {
  // A cloth triangle 2 mm up whose vertex 0 lies 2 mm off the diagonal, over the lower face:
  // the upper face is nearest it on the diagonal, 2.8 mm away along a normal 45° off vertical.
  // Only the face under it counts, straight up; the cloth's edge crossing above the diagonal
  // and rising 4 mm over its 10 mm has no edge–edge pair with it (its lower end is the nearest
  // point to the plane, a vertex–face pair). Before, those pairs pushed crumpled cloth along a
  // frictionless table.
  const CollisionMesh square = flat_square();
  CollisionMesh cloth;
  cloth.x0.resize(3, 3);
  const double off = 0.002 / std::sqrt(2.0);
  cloth.x0 << off, -off, 0.002, off - 0.01 / std::sqrt(2.0), -off + 0.01 / std::sqrt(2.0), 0.006,
      off + 0.005, -off + 0.01, 0.006;
  cloth.x1 = cloth.x0;
  cloth.faces.resize(1, 3);
  cloth.faces << 0, 1, 2;
  cloth.mass = Eigen::VectorXd::Constant(3, 1e-4);
  cloth.frozen.assign(3, 0);
  const std::vector<Proximity> found = proximities({&cloth, &square}, 5e-3);
  int vertex0 = 0;
  for (const Proximity& p : found) {
    EXPECT_NEAR(p.normal.z(), 1.0, 1e-12) << (p.edge_edge ? "edge–edge" : "vertex–face");
    if (!p.edge_edge && p.mesh[0] == 0 && p.first == 0) {
      ++vertex0;
      EXPECT_EQ(p.second, 0);  // the face under it
      EXPECT_NEAR(p.distance, 0.002, 1e-12);
    }
  }
  EXPECT_EQ(vertex0, 1);
}

TEST(Proximity, AVertexInsideAFlatObstacleGivesNoSidewaysNormal) {
  // The square again, split into four triangles around a vertex at its centre: a cloth vertex
  // 2 mm up and 2 mm off the centre, over the lower face, is nearest the upper face at that
  // centre vertex, 2.8 mm away along a normal 45° off vertical (and the side faces on their
  // flat edges). A vertex whose faces all lie in one plane is no feature either: only the face
  // under the cloth vertex counts.
  CollisionMesh square;
  square.obstacle = true;
  square.x0.resize(5, 3);
  square.x0 << -0.05, -0.05, 0.0, 0.05, -0.05, 0.0, 0.05, 0.05, 0.0, -0.05, 0.05, 0.0, 0.0, 0.0,
      0.0;
  square.x1 = square.x0;
  square.faces.resize(4, 3);
  square.faces << 4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0;
  CollisionMesh cloth = make_sheet(1, 1, 0.01, 0.01, Vec3(-0.005, -0.012, 0.002), 1e-4);
  // Vertex 2 of the sheet sits at (−5, −2, 2) mm: move it to (0, −2, 2) mm.
  int v = -1;
  for (int k = 0; k < cloth.x0.rows(); ++k)
    if (std::abs(cloth.x0(k, 0) + 0.005) < 1e-12 && std::abs(cloth.x0(k, 1) + 0.002) < 1e-12) v = k;
  ASSERT_GE(v, 0);
  cloth.x0(v, 0) = 0.0;
  cloth.x1 = cloth.x0;
  int under = 0;
  for (const Proximity& p : proximities({&cloth, &square}, 5e-3)) {
    EXPECT_NEAR(p.normal.z(), 1.0, 1e-12)
        << (p.edge_edge ? "edge–edge" : "vertex–face") << " of cloth primitive " << p.first;
    if (!p.edge_edge && p.mesh[0] == 0 && p.first == v) {
      ++under;
      EXPECT_EQ(p.second, 0);  // the face under it
      EXPECT_NEAR(p.distance, 0.002, 1e-12);
    }
  }
  EXPECT_EQ(under, 1);
}

TEST(Proximity, ABoxsCornerStillMeetsAClothVertexBeyondIt) {
  // A cloth vertex 2 mm beyond a box's top corner along each axis: the corner is a feature (its
  // faces at 90°), so the pair stays, its normal along the diagonal.
  const CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.0, 0.0, 0.0));
  CollisionMesh cloth = make_sheet(1, 1, 0.01, 0.01, Vec3(0.002, 0.002, 0.002), 1e-4);
  bool corner = false;
  for (const Proximity& p : proximities({&cloth, &box}, 5e-3))
    corner = corner || (!p.edge_edge && p.mesh[0] == 0 && p.first == 0 &&
                        std::abs(p.normal.z() - 1.0 / std::sqrt(3.0)) < 1e-9);
  EXPECT_TRUE(corner);
}

TEST(Proximity, ABoxsSharpEdgeStillMeetsAClothEdgeAcrossIt) {
  // A cloth edge 3 mm beyond a box's top edge, across it: the edge–edge pair with a feature edge
  // (faces at 90°) stays, its normal off both faces.
  const CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.0, 0.05, 0.0));
  CollisionMesh cloth;
  cloth.x0.resize(3, 3);
  const double d = 0.003 / std::sqrt(2.0);
  cloth.x0 << d - 0.01, 0.0, d + 0.01, d + 0.01, 0.0, d - 0.01, d, 0.02, d;
  cloth.x1 = cloth.x0;
  cloth.faces.resize(1, 3);
  cloth.faces << 0, 1, 2;
  cloth.mass = Eigen::VectorXd::Constant(3, 1e-4);
  cloth.frozen.assign(3, 0);
  bool across = false;
  for (const Proximity& p : proximities({&cloth, &box}, 5e-3))
    across = across || (p.edge_edge && p.normal.x() > 0.5 && p.normal.z() > 0.5);
  EXPECT_TRUE(across);
}

namespace {

/// A 5 mm grid strip 0.2 m long folded in the middle into a U of inner radius r (arms 2r
/// apart along z), its rest shape the flat strip.
CollisionMesh folded_strip(double r) {
  CollisionMesh strip = make_sheet(40, 2, 0.2, 0.01, Vec3::Zero(), 1e-4);
  strip.rest = strip.x0;
  const double half_arc = 0.5 * M_PI * r;
  for (int v = 0; v < strip.x0.rows(); ++v) {
    const double s = strip.rest(v, 0) - 0.1;  // arc length from the fold's bottom
    double x = 0.0, z = 0.0;
    if (std::abs(s) <= half_arc) {
      x = r - r * std::cos(s / r);
      z = r * std::sin(s / r);
    } else {
      x = r + std::abs(s) - half_arc;
      z = s > 0 ? r : -r;
    }
    strip.x0(v, 0) = x;
    strip.x0(v, 2) = z;
  }
  strip.x1 = strip.x0;
  return strip;
}

/// Distance in the rest shape between the two primitives of `p` (one mesh) [m].
double rest_distance(const CollisionMesh& m, const Proximity& p) {
  const auto at = [&](int k) {
    return Vec3(m.rest.row(p.corner[static_cast<std::size_t>(k)]).transpose());
  };
  if (p.edge_edge) {
    const Vec2 su = closest_points_segments(at(0), at(1), at(2), at(3));
    return ((at(0) + su[0] * (at(1) - at(0))) - (at(2) + su[1] * (at(3) - at(2)))).norm();
  }
  const Vec3 b = closest_point_triangle(at(0), at(1), at(2), at(3));
  return (at(0) - (b[0] * at(1) + b[1] * at(2) + b[2] * at(3))).norm();
}

}  // namespace

TEST(Proximity, AFoldedClothRepelsAcrossTheFoldButNotItsOwnBendingNeighbours) {
  // Arms 4 mm apart, thickness 5 mm: a fold joins two points within the thickness only if they
  // are at least π/2 · 5 = 7.85 mm apart along the cloth. Closer pairs at rest bend, they do
  // not touch; the arms beyond them still repel each other.
  const double thickness = 5e-3, fold = 0.5 * M_PI * thickness;
  CollisionMesh strip = folded_strip(2e-3);
  const std::vector<Proximity> found = proximities({&strip}, thickness);
  int across_arms = 0;
  for (const Proximity& p : found) {
    EXPECT_GE(rest_distance(strip, p), fold)
        << (p.edge_edge ? "edge-edge " : "vertex-face ") << p.first << " " << p.second;
    if (p.distance < 4e-3 + 1e-9) ++across_arms;
  }
  EXPECT_GT(across_arms, 20);
  // The same fold without a rest shape counts the bending neighbours at the fold as contacts.
  CollisionMesh no_rest = strip;
  no_rest.rest.resize(0, 3);
  const std::vector<Proximity> all = proximities({&no_rest}, thickness);
  int neighbours = 0;
  for (const Proximity& p : all) neighbours += rest_distance(strip, p) < fold;
  EXPECT_GT(neighbours, 0);
  EXPECT_EQ(all.size(), found.size() + static_cast<std::size_t>(neighbours));
}

TEST(Proximity, AClothWithoutSelfCollisionHasNoContactsWithItselfOnly) {
  // The folded strip's arms 4 mm apart: no pairs with itself once self-collision is off, while a
  // second sheet 2 mm under the lower arm still meets it.
  CollisionMesh strip = folded_strip(2e-3);
  ASSERT_FALSE(proximities({&strip}, 5e-3).empty());
  strip.self_collision = false;
  EXPECT_TRUE(proximities({&strip}, 5e-3).empty());
  const CollisionMesh below = make_sheet(10, 2, 0.05, 0.01, Vec3(0.01, 0, -4e-3), 1e-4);
  const std::vector<Proximity> found = proximities({&strip, &below}, 5e-3);
  ASSERT_FALSE(found.empty());
  for (const Proximity& p : found) EXPECT_NE(p.mesh[0], p.mesh[1]);
}

TEST(Proximity, RestNeighboursAreLeftOutOfTheCandidatesBeforeAnyPairTest) {
  // A fold crumpled by seeded noise: the candidates with rest neighbours left out are the ones
  // without, in the same order, less every pair that lies within the distance at rest and
  // less only pairs farther apart than the reach otherwise (UnfoldedSubtrees).
  CollisionMesh strip = folded_strip(2e-3);
  std::uint32_t state = 12345u;
  const auto noise = [&] {
    state = state * 1664525u + 1013904223u;
    return 1e-3 * (static_cast<double>(state >> 8) / 16777216.0 - 0.5);
  };
  for (int v = 0; v < strip.x0.rows(); ++v)
    for (int k = 0; k < 3; ++k) strip.x0(v, k) += noise();
  strip.x1 = strip.x0;
  const double d = 0.5 * M_PI * 5e-3;
  const std::vector<const CollisionMesh*> meshes{&strip};
  CollisionCandidates all, fewer;
  all.update(meshes, false, 2.5e-3);
  fewer.set_rest_neighbour_distance(d);
  fewer.update(meshes, false, 2.5e-3);
  const auto& ea = all.topology(0).edges;
  // Distances between a pair's primitives at positions x (at rest, or now).
  const auto vf_at = [&](const Points& x, const VertexFacePair& p) {
    return rest_vertex_face_distance(
        x, p.vertex, {strip.faces(p.face, 0), strip.faces(p.face, 1), strip.faces(p.face, 2)});
  };
  const auto ee_at = [&](const Points& x, const EdgeEdgePair& p) {
    return rest_edge_edge_distance(x, ea[static_cast<std::size_t>(p.edge_a)],
                                   ea[static_cast<std::size_t>(p.edge_b)]);
  };
  const auto vf_rest = [&](const VertexFacePair& p) { return vf_at(strip.rest, p); };
  const auto vf_now = [&](const VertexFacePair& p) { return vf_at(strip.x0, p); };
  const auto ee_rest = [&](const EdgeEdgePair& p) { return ee_at(strip.rest, p); };
  const auto ee_now = [&](const EdgeEdgePair& p) { return ee_at(strip.x0, p); };
  const auto same = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  // Walks both lists: every kept pair appears in order; every dropped one is a rest neighbour
  // or out of reach. Returns {rest neighbours dropped, rest neighbours in the full list}.
  const auto check = [&](const auto& full, const auto& kept, const auto& rest, const auto& now) {
    std::size_t k = 0, dropped = 0, neighbours = 0;
    for (const auto& p : full) {
      const bool neighbour = rest(p) < d;
      neighbours += neighbour;
      if (k < kept.size() && same(p, kept[k])) {
        ++k;
      } else {
        dropped += neighbour;
        EXPECT_TRUE(neighbour || now(p) >= 5e-3);
      }
    }
    EXPECT_EQ(k, kept.size()) << "a kept pair is missing from the full list or out of order";
    return std::pair{dropped, neighbours};
  };
  const auto [vf_dropped, vf_neighbours] =
      check(all.vertex_face(), fewer.vertex_face(), vf_rest, vf_now);
  const auto [ee_dropped, ee_neighbours] =
      check(all.edge_edge(), fewer.edge_edge(), ee_rest, ee_now);
  // Every rest neighbour goes before any pair test; the arms' pairs across the fold are kept.
  EXPECT_EQ(vf_dropped, vf_neighbours);
  EXPECT_EQ(ee_dropped, ee_neighbours);
  EXPECT_GT(vf_dropped, 100u);
  EXPECT_GT(fewer.vertex_face().size(), 20u);
  // And the proximities found are those of the full candidate list.
  std::vector<Proximity> out;
  find_proximities(meshes, 5e-3, fewer, out);
  CollisionMesh no_rest = strip;
  no_rest.rest.resize(0, 3);
  int neighbours = 0, kept = 0;
  for (const Proximity& p : proximities({&no_rest}, 5e-3))
    (rest_distance(strip, p) < d ? neighbours : kept)++;
  EXPECT_EQ(static_cast<int>(out.size()), kept);
  EXPECT_GT(neighbours, 0);
}

TEST(CollisionCandidates, OnAPoolTheCandidatesAreTheSameInTheSameOrder) {
  // A 3,200-face sheet folded over itself 4 mm apart, crumpled by seeded noise and moving, over
  // a sphere: the candidates (proximity search with rest neighbours left out, and swept for
  // continuous detection) found on a pool's threads must be one thread's, pair for pair.
  const CollisionMesh sheet = folded_crumpled_sheet(99u);
  const CollisionMesh sphere = make_sphere(Vec3(0, 0, -0.05), 0.052, 12, 24);
  const std::vector<const CollisionMesh*> meshes{&sheet, &sphere};
  const auto same = [](const auto& a, const auto& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  };
  for (const bool swept : {false, true}) {
    CollisionCandidates serial;
    serial.set_rest_neighbour_distance(swept ? 0.0 : 0.5 * M_PI * 5e-3);
    serial.update(meshes, swept, swept ? 1e-6 : 2.5e-3);
    ASSERT_GT(serial.vertex_face().size(), 100u);
    ASSERT_GT(serial.edge_edge().size(), 100u);
    for (const int threads : {2, 3}) {
      WorkerPool pool(threads);
      CollisionCandidates threaded;
      threaded.set_pool(&pool);
      threaded.set_rest_neighbour_distance(swept ? 0.0 : 0.5 * M_PI * 5e-3);
      threaded.update(meshes, swept, swept ? 1e-6 : 2.5e-3);
      EXPECT_TRUE(same(threaded.vertex_face(), serial.vertex_face()))
          << threads << " threads, swept " << swept;
      EXPECT_TRUE(same(threaded.edge_edge(), serial.edge_edge()))
          << threads << " threads, swept " << swept;
    }
  }
}

TEST(CollisionCandidates, AfterSomeVerticesMovedTheirPairsAreFoundInTheWholeSearchsOrder) {
  // The folded, crumpled 3,200-face sheet falling onto a sphere again (swept, as the impact
  // zones search): a patch of vertices then changes its x1. update_moved must find every pair
  // of a whole search at the new positions that has a moved corner, in that search's order,
  // with nothing the whole search would not find, and leave out most of the rest.
  CollisionMesh sheet = folded_crumpled_sheet(7u);
  std::uint32_t state = 3u;
  const auto noise = [&] {
    state = state * 1664525u + 1013904223u;
    return 1e-3 * (static_cast<double>(state >> 8) / 16777216.0 - 0.5);
  };
  const CollisionMesh sphere = make_sphere(Vec3(0, 0, -0.05), 0.052, 12, 24);
  const std::vector<const CollisionMesh*> meshes{&sheet, &sphere};
  constexpr double kMargin = 1e-6;
  const Points start = sheet.x1;

  for (const int threads : {1, 2}) {
    sheet.x1 = start;
    WorkerPool pool(threads);
    CollisionCandidates candidates;
    if (threads > 1) candidates.set_pool(&pool);
    candidates.update(meshes, true, kMargin);
    // The patch within 3 cm of a point of the fold's upper layer moves down by up to 3 mm.
    std::vector<std::vector<std::uint8_t>> moved{
        std::vector<std::uint8_t>(static_cast<std::size_t>(sheet.x0.rows()), 0), {}};
    int count = 0;
    for (int v = 0; v < sheet.x0.rows(); ++v) {
      if (std::hypot(sheet.x0(v, 0) + 0.05, sheet.x0(v, 1)) > 0.03) continue;
      sheet.x1(v, 2) -= 1.5e-3 + 3.0 * noise();
      moved[0][static_cast<std::size_t>(v)] = 1;
      ++count;
    }
    ASSERT_GT(count, 50);
    candidates.update_moved(meshes, kMargin, moved);
    // The whole search at the new positions, nothing left out (no rest shape).
    CollisionMesh plain = sheet;
    plain.rest.resize(0, 3);
    CollisionCandidates whole;
    whole.update({&plain, &sphere}, true, kMargin);

    const auto moves = [&](int mesh, int v) {
      return mesh == 0 && moved[0][static_cast<std::size_t>(v)] != 0;
    };
    const auto check = [&](const auto& found, const auto& all, auto touches, const char* kind) {
      std::size_t k = 0, touching = 0, missing = 0;
      for (const auto& pair : all) {
        const bool here = k < found.size() && std::memcmp(&found[k], &pair, sizeof pair) == 0;
        if (here) ++k;
        if (touches(pair)) {
          ++touching;
          if (!here) ++missing;
        }
      }
      EXPECT_EQ(missing, 0u) << kind << ": pairs with a moved corner missing";
      EXPECT_EQ(k, found.size()) << kind << ": pairs out of order or not in the whole search";
      EXPECT_GT(touching, 20u) << kind;
      EXPECT_LT(found.size(), all.size() / 2) << kind << ": most pairs should be left out";
    };
    check(
        candidates.vertex_face(), whole.vertex_face(),
        [&](const VertexFacePair& p) {
          const CollisionMesh& f = *meshes[static_cast<std::size_t>(p.face_mesh)];
          return moves(p.vertex_mesh, p.vertex) || moves(p.face_mesh, f.faces(p.face, 0)) ||
                 moves(p.face_mesh, f.faces(p.face, 1)) || moves(p.face_mesh, f.faces(p.face, 2));
        },
        "vertex-face");
    check(
        candidates.edge_edge(), whole.edge_edge(),
        [&](const EdgeEdgePair& p) {
          const auto& a = candidates.topology(p.mesh_a).edges[static_cast<std::size_t>(p.edge_a)];
          const auto& b = candidates.topology(p.mesh_b).edges[static_cast<std::size_t>(p.edge_b)];
          return moves(p.mesh_a, a[0]) || moves(p.mesh_a, a[1]) || moves(p.mesh_b, b[0]) ||
                 moves(p.mesh_b, b[1]);
        },
        "edge-edge");
  }
}

TEST(Proximity, ASurfaceBuriedInAnotherShapeOfTheBodyGivesNoPair) {
  // A body of two shapes: a slab whose top is at z = 0 and a 10 mm pad box on it, sunk 3 mm
  // into it and standing 1 mm out. Under the pad, the slab's top is buried in the pad, and the
  // pad's bottom and the lower parts of its sides in the slab: no surface of the body. A cloth
  // vertex 2 mm over the pad is 3 mm from the slab's buried top, and one beside the pad, 0.5 mm
  // over the slab, 4 mm from the pad's buried bottom edge; only the outer surface meets them.
  // (Each is the near corner of a triangle whose other corners are far up.)
  const CollisionMesh body =
      join_obstacles(make_box(Vec3(-0.05, -0.05, -0.02), Vec3(0.05, 0.05, 0.0)),
                     make_box(Vec3(-0.005, -0.005, -0.003), Vec3(0.005, 0.005, 0.001)));
  CollisionMesh cloth;
  cloth.x0.resize(6, 3);
  cloth.x0 << 0.001, 0.002, 0.003, 0.001, 0.03, 0.03, -0.03, 0.002, 0.03,  //
      0.007, 0.0, 0.0005, 0.03, 0.0, 0.03, 0.03, 0.03, 0.03;
  cloth.x1 = cloth.x0;
  cloth.faces.resize(2, 3);
  cloth.faces << 0, 1, 2, 3, 4, 5;
  cloth.mass = Eigen::VectorXd::Constant(6, 1e-4);
  cloth.frozen.assign(6, 0);
  const MeshTopology topology = build_topology(body.faces, static_cast<int>(body.x0.rows()));
  ObstaclePieces pieces;
  pieces.update(body.x0, body.faces, topology);
  bool over = false, beside_slab = false, beside_pad = false;
  for (const Proximity& p : proximities({&cloth, &body}, 5e-3)) {
    if (p.mesh[0] == 1) {  // a corner of the body near a cloth face
      EXPECT_FALSE(pieces.inside_other(-1, body.x0.row(p.first).transpose(), 1e-9))
          << "buried vertex " << p.first << " meets cloth face " << p.second;
      continue;
    }
    // The pair's point on the cloth (vertex, or point of the edge) and on the body.
    Vec3 x = p.w[0] * cloth.x0.row(p.corner[0]).transpose();
    if (p.edge_edge) x += p.w[1] * cloth.x0.row(p.corner[1]).transpose();
    const Vec3 surface = x - p.distance * p.normal;
    EXPECT_FALSE(pieces.inside_other(-1, surface, 1e-9))
        << (p.edge_edge ? "edge " : "vertex ") << p.first << " meets a buried point of "
        << (p.edge_edge ? "edge " : "face ") << p.second;
    const auto is = [&](int v, double d, const Vec3& n) {
      return !p.edge_edge && p.first == v && std::abs(p.distance - d) < 1e-12 &&
             (p.normal - n).norm() < 1e-12;
    };
    over = over || is(0, 0.002, Vec3::UnitZ());
    beside_slab = beside_slab || is(3, 0.0005, Vec3::UnitZ());
    beside_pad = beside_pad || is(3, 0.002, Vec3::UnitX());
  }
  EXPECT_TRUE(over);
  EXPECT_TRUE(beside_slab);
  EXPECT_TRUE(beside_pad);
}
