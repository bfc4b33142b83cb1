#include <gtest/gtest.h>

#include <algorithm>

#include "cloth/collision/ccd.hpp"
#include "cloth/collision/polynomial_roots.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;

namespace {

constexpr double kTol = 1e-6;

// Unit right triangle in z = 0 preceded by the vertex positions at the start and end.
Corners vf(const Vec3& p) { return {p, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}; }

}  // namespace

TEST(PolynomialRoots, FindsThreeSimpleRootsToFullPrecision) {
  // (t − 0.2)(t − 0.5)(t − 0.9) = t³ − 1.6t² + 0.73t − 0.09
  CubicCandidates out{};
  const int n = cubic_candidates({-0.09, 0.73, -1.6, 1.0}, 0.0, out);
  ASSERT_EQ(n, 3);
  EXPECT_NEAR(out[0], 0.2, 1e-14);
  EXPECT_NEAR(out[1], 0.5, 1e-14);
  EXPECT_NEAR(out[2], 0.9, 1e-14);
}

TEST(PolynomialRoots, HoldsEveryCandidateOfThreePiecesTouchingZero) {
  // (t − 0.1)(t − 0.5)(t − 0.9) with a near-zero bound above |p| at 0, at both critical points
  // and at 1: each of the three monotone pieces gives its start and its root, then the end.
  // Five candidates were room for (AddressSanitizer caught the overflow in CCD).
  CubicCandidates out{};
  const int n = cubic_candidates({-0.045, 0.59, -1.5, 1.0}, 0.05, out);
  ASSERT_EQ(n, 7);
  EXPECT_EQ(out[0], 0.0);
  EXPECT_NEAR(out[1], 0.1, 1e-14);
  EXPECT_NEAR(out[3], 0.5, 1e-14);
  EXPECT_NEAR(out[5], 0.9, 1e-14);
  EXPECT_EQ(out[6], 1.0);
  EXPECT_TRUE(std::is_sorted(out.begin(), out.begin() + n));
}

TEST(PolynomialRoots, HandlesDegenerateLeadingCoefficients) {
  CubicCandidates out{};
  // Linear 2t − 1.
  ASSERT_EQ(cubic_candidates({-1.0, 2.0, 0.0, 0.0}, 0.0, out), 1);
  EXPECT_NEAR(out[0], 0.5, 1e-15);
  // Quadratic with a double root at 0.25: only reachable through the near-zero test.
  ASSERT_EQ(cubic_candidates({0.0625, -0.5, 1.0, 0.0}, 1e-12, out), 1);
  EXPECT_NEAR(out[0], 0.25, 1e-12);
  // Non-zero constant: no root; zero constant: both ends touch.
  EXPECT_EQ(cubic_candidates({1.0, 0.0, 0.0, 0.0}, 1e-12, out), 0);
  ASSERT_EQ(cubic_candidates({0.0, 0.0, 0.0, 0.0}, 0.0, out), 2);
  EXPECT_EQ(out[0], 0.0);
  EXPECT_EQ(out[1], 1.0);
  // Roots outside [0,1] are not reported.
  EXPECT_EQ(cubic_candidates({-2.0, 1.0, 0.0, 0.0}, 0.0, out), 0);
}

TEST(QuadraticRoots, StableForTinyLeadingCoefficient) {
  std::array<double, 2> r{};
  ASSERT_EQ(quadratic_roots(-0.5, 1.0, 1e-20, r), 2);
  EXPECT_NEAR(r[1], 0.5, 1e-15);
}

TEST(VertexFaceCcd, VertexThroughFaceAtKnownTime) {
  const auto hit = vertex_face_ccd(vf({0.2, 0.2, 1.0}), vf({0.2, 0.2, -2.0}), kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 1.0 / 3.0, 1e-9);
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);  // toward the side the vertex came from
  EXPECT_NEAR(hit->w[0], 1.0, 1e-12);
  EXPECT_NEAR(hit->w[1], -0.6, 1e-9);
  EXPECT_NEAR(hit->w[2], -0.2, 1e-9);
  EXPECT_NEAR(hit->w[3], -0.2, 1e-9);
  EXPECT_LE(hit->distance, kTol);
}

TEST(VertexFaceCcd, MovingFaceHitsStaticVertexFromBelow) {
  // Face rises from z = −1 to z = 1 under a vertex at z = 0.5: contact at t = 0.75, normal −z→+z.
  const Corners x0{Vec3(0.3, 0.3, 0.5), Vec3(0, 0, -1), Vec3(1, 0, -1), Vec3(0, 1, -1)};
  const Corners x1{Vec3(0.3, 0.3, 0.5), Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)};
  const auto hit = vertex_face_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.75, 1e-9);
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);
}

TEST(VertexFaceCcd, ExactTouchAtEndOfStep) {
  const auto hit = vertex_face_ccd(vf({0.2, 0.3, 0.7}), vf({0.2, 0.3, 0.0}), kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->t, 1.0);
}

TEST(VertexFaceCcd, MissByAHairOutsideAnEdgeButHitJustInside) {
  // The vertex crosses the plane 10·tolerance outside edge x = 0, then just inside it.
  EXPECT_FALSE(vertex_face_ccd(vf({-1e-5, 0.4, 1.0}), vf({-1e-5, 0.4, -1.0}), kTol).has_value());
  const auto hit = vertex_face_ccd(vf({1e-9, 0.4, 1.0}), vf({1e-9, 0.4, -1.0}), kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.5, 1e-9);
}

TEST(VertexFaceCcd, GrazingThroughAnEdgeAndACorner) {
  // Crossing the plane exactly on edge y = 0 and exactly at corner (1, 0, 0).
  const auto edge = vertex_face_ccd(vf({0.5, 0.0, 1.0}), vf({0.5, 0.0, -3.0}), kTol);
  ASSERT_TRUE(edge.has_value());
  EXPECT_NEAR(edge->t, 0.25, 1e-9);
  const auto corner = vertex_face_ccd(vf({1.0, 0.0, 1.0}), vf({1.0, 0.0, -1.0}), kTol);
  ASSERT_TRUE(corner.has_value());
  EXPECT_NEAR(corner->t, 0.5, 1e-9);
}

TEST(VertexFaceCcd, TangentialTouchAtDoubleRoot) {
  // Tilting face a = 0, b = x̂, c = (0, 1, t) and p(t) = (0.25, 0.75 − t, 0.25 − t/4): the
  // coplanarity function is (t − 1/2)², touching zero inside the face at t = 1/2 without a sign
  // change.
  const Corners x0{Vec3(0.25, 0.75, 0.25), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const Corners x1{Vec3(0.25, -0.25, 0.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1)};
  const auto hit = vertex_face_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.5, 1e-6);
  // Lifting the vertex by 1 mm turns the touch into a miss.
  Corners y0 = x0, y1 = x1;
  y0[0].z() += 1e-3;
  y1[0].z() += 1e-3;
  EXPECT_FALSE(vertex_face_ccd(y0, y1, kTol).has_value());
}

TEST(VertexFaceCcd, CoplanarMotionEntersAtKnownTime) {
  // Everything in z = 0: the vertex slides in through edge x = 0 at t = 0.5.
  const auto hit = vertex_face_ccd(vf({-1.0, 0.2, 0.0}), vf({1.0, 0.2, 0.0}), kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.5, 1e-9);
  // The same slide beside the triangle misses.
  EXPECT_FALSE(vertex_face_ccd(vf({-1.0, 1.5, 0.0}), vf({1.0, 1.5, 0.0}), kTol).has_value());
}

TEST(VertexFaceCcd, StartInContactReportsTimeZero) {
  const auto hit = vertex_face_ccd(vf({0.2, 0.2, 0.0}), vf({0.2, 0.2, 1.0}), kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->t, 0.0);
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);  // oriented toward where it ends
}

TEST(VertexFaceCcd, ParallelMotionAboveFaceMisses) {
  EXPECT_FALSE(vertex_face_ccd(vf({-1.0, 0.2, 1e-3}), vf({2.0, 0.2, 1e-3}), kTol).has_value());
}

TEST(EdgeEdgeCcd, CrossingAtKnownTime) {
  // Edge p along x descends from z = 0.3 to z = −0.7; edge q along y at z = 0: t = 0.3.
  const Corners x0{Vec3(-1, 0.1, 0.3), Vec3(1, 0.1, 0.3), Vec3(0.4, -1, 0), Vec3(0.4, 1, 0)};
  const Corners x1{Vec3(-1, 0.1, -0.7), Vec3(1, 0.1, -0.7), Vec3(0.4, -1, 0), Vec3(0.4, 1, 0)};
  const auto hit = edge_edge_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.3, 1e-9);
  EXPECT_NEAR(hit->w[1], 0.7, 1e-9);    // s = 0.7 along p
  EXPECT_NEAR(hit->w[3], -0.55, 1e-9);  // u = 0.55 along q
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);
}

TEST(EdgeEdgeCcd, SkewEdgesPassingEachOtherMiss) {
  // Same descent, but edge q is too short to reach edge p's line (y = 0.1).
  const Corners x0{Vec3(-1, 0.1, 0.3), Vec3(1, 0.1, 0.3), Vec3(0.4, -1, 0), Vec3(0.4, 0.09, 0)};
  const Corners x1{Vec3(-1, 0.1, -0.7), Vec3(1, 0.1, -0.7), Vec3(0.4, -1, 0), Vec3(0.4, 0.09, 0)};
  EXPECT_FALSE(edge_edge_ccd(x0, x1, kTol).has_value());
}

TEST(EdgeEdgeCcd, ParallelEdgesMeetAtKnownTime) {
  // Parallel edges (always coplanar: the cubic vanishes); q drops onto p at t = 0.25.
  const Corners x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 1), Vec3(1.5, 0, 1)};
  const Corners x1{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, -3), Vec3(1.5, 0, -3)};
  const auto hit = edge_edge_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.25, 1e-9);
  EXPECT_NEAR(hit->normal.z(), -1.0, 1e-9);  // from q (above) toward p (below)
}

TEST(EdgeEdgeCcd, ParallelEdgesSlidingApartMiss) {
  const Corners x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1), Vec3(1, 1, 1)};
  const Corners x1{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 1), Vec3(1, -1, 1)};
  EXPECT_FALSE(edge_edge_ccd(x0, x1, kTol).has_value());
}

TEST(EdgeEdgeCcd, CollinearEdgesSlidingTogetherMeetAtKnownTime) {
  // On the x axis: q = [2, 3] slides to [0.5, 1.5], touching p = [0, 1] at t = 2/3.
  const Corners x0{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  const Corners x1{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0), Vec3(1.5, 0, 0)};
  const auto hit = edge_edge_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 2.0 / 3.0, 1e-9);
}

TEST(EdgeEdgeCcd, EdgesMeetingEndOnInTheirCommonPlaneGetTheApproachNormal) {
  // A cloth edge along y at the pole of a tessellated sphere drops onto a meridian edge below it;
  // both stay in the plane x = 0 and touch where the cloth edge's end meets the meridian. Their
  // cross product is ±x, perpendicular to the approach, with a sign set by round-off: the normal
  // must be the direction the pair came from (+z), which every other contact there agrees with.
  const Vec3 pole(0, 0, 0), ring(0, 0.1, -0.02);
  const Corners x0{Vec3(0, 0.025, 0.003), Vec3(0, 0.05, 0.003), pole, ring};
  const Corners x1{Vec3(0, 0.025, -0.007), Vec3(0, 0.05, -0.007), pole, ring};
  const auto hit = edge_edge_ccd(x0, x1, kTol);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.8, 1e-6);  // the end at y = 0.025 reaches z = −0.005 at t = 0.8
  EXPECT_NEAR(hit->w[0], 1.0, 1e-9);
  EXPECT_NEAR(hit->normal.x(), 0.0, 1e-9);
  EXPECT_GT(hit->normal.z(), 0.9);
}
