#include <gtest/gtest.h>

#include "cloth/collision/inside_obstacles.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

TEST(InsideObstacles, WindingNumberIsOneInsideAClosedMeshAndZeroOutside) {
  const CollisionMesh box = make_box(Vec3(-0.1, -0.2, -0.05), Vec3(0.1, 0.2, 0.05));
  EXPECT_NEAR(winding_number(box.x0, box.faces, Vec3(0.0, 0.0, 0.0)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(box.x0, box.faces, Vec3(0.099, 0.19, -0.049)), 1.0, 1e-9);
  EXPECT_NEAR(winding_number(box.x0, box.faces, Vec3(0.0, 0.0, 0.051)), 0.0, 1e-9);
  EXPECT_NEAR(winding_number(box.x0, box.faces, Vec3(0.3, -0.5, 0.2)), 0.0, 1e-12);
  const CollisionMesh sphere = make_sphere(Vec3(0.3, 0.0, 0.1), 0.05, 8, 16);
  EXPECT_NEAR(winding_number(sphere.x0, sphere.faces, Vec3(0.31, 0.01, 0.09)), 1.0, 1e-9);
  EXPECT_NEAR(winding_number(sphere.x0, sphere.faces, Vec3(0.3, 0.0, 0.16)), 0.0, 1e-9);
  // Inside-out (faces turned inward), the inside counts −1: not "inside" for the recovery.
  CollisionMesh flipped = box;
  flipped.faces.col(1).swap(flipped.faces.col(2));
  EXPECT_NEAR(winding_number(flipped.x0, flipped.faces, Vec3::Zero()), -1.0, 1e-12);
}

TEST(InsideObstacles, AVertexInsideABodyGoesToTheNearestFaceTheOthersStay) {
  // A 2 × 2-quad sheet at z = 0.04 (columns at x = −0.05, 0.05, 0.15) whose first column lies
  // inside a box (x < 0, z from −0.05 to 0.05), 10 mm under its top face and 50 mm or more
  // from its other faces.
  CollisionMesh sheet = make_sheet(2, 2, 0.2, 0.2, Vec3(-0.05, -0.1, 0.04), 1e-3);
  CollisionMesh box = make_box(Vec3(-0.1, -0.2, -0.05), Vec3(0.0, 0.2, 0.05));
  // One vertex of that column is a handle: never moved.
  sheet.frozen.assign(static_cast<std::size_t>(sheet.x1.rows()), 0);
  int handle = -1;
  for (int v = 0; v < sheet.x1.rows(); ++v)
    if (sheet.x1(v, 0) < 0.0 && handle < 0) handle = v;
  ASSERT_GE(handle, 0);
  sheet.frozen[static_cast<std::size_t>(handle)] = 1;
  const Points before = sheet.x1;
  const double offset = 1e-4;
  const InsideReport report = push_out_of_obstacles({&sheet, &box}, offset);

  int moved = 0;
  for (int v = 0; v < sheet.x1.rows(); ++v) {
    const bool inside = before(v, 0) < 0.0 && v != handle;
    if (!inside) {
      EXPECT_EQ(sheet.x1.row(v), before.row(v)) << "vertex " << v;
      continue;
    }
    ++moved;
    // Straight up through the top face, the closest, to `offset` above it.
    EXPECT_NEAR(sheet.x1(v, 0), before(v, 0), 1e-15);
    EXPECT_NEAR(sheet.x1(v, 1), before(v, 1), 1e-15);
    EXPECT_NEAR(sheet.x1(v, 2), 0.05 + offset, 1e-12);
    EXPECT_LT(winding_number(box.x1, box.faces, sheet.x1.row(v).transpose()), 0.5);
  }
  EXPECT_EQ(report.vertices, moved);
  EXPECT_EQ(moved, 2);
  EXPECT_NEAR(report.depth, 0.01, 1e-12);
}

TEST(InsideObstacles, AVertexDeepInACornerLeavesByTheClosestSide) {
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(0.0, 0.0, 0.0), 1e-3);
  CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  // Vertex 0 at (0.045, 0, 0.03): 5 mm from the x = 0.05 face, 20 mm from the top.
  sheet.x1.row(0) << 0.045, 0.0, 0.03;
  for (int v = 1; v < sheet.x1.rows(); ++v) sheet.x1.row(v) << 0.2, 0.2 + 0.01 * v, 0.0;
  const InsideReport report = push_out_of_obstacles({&sheet, &box}, 0.0);
  EXPECT_EQ(report.vertices, 1);
  EXPECT_NEAR(report.depth, 0.005, 1e-12);
  EXPECT_NEAR(sheet.x1(0, 0), 0.05, 1e-12);
  EXPECT_NEAR(sheet.x1(0, 1), 0.0, 1e-12);
  EXPECT_NEAR(sheet.x1(0, 2), 0.03, 1e-12);
}

TEST(InsideObstacles, AnOpenBodyHasNoInside) {
  // A box without its top, a cup: from a point in its hollow the walls fill most of the view
  // (winding number about 0.8), but the hollow is outside the body.
  CollisionMesh cup = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  CollisionMesh box = cup;
  Triangles open(10, 3);
  int row = 0;
  for (int f = 0; f < 12; ++f)
    if (f != 2 && f != 3) open.row(row++) = cup.faces.row(f);  // faces 2, 3: the top (z = hi)
  cup.faces = open;
  EXPECT_TRUE(closed_and_oriented(box.faces));
  EXPECT_FALSE(closed_and_oriented(cup.faces));
  const Vec3 hollow(0.0, 0.0, -0.03);
  EXPECT_GT(winding_number(cup.x1, cup.faces, hollow), 0.5);
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(-0.005, -0.005, -0.03), 1e-3);
  const Points before = sheet.x1;
  EXPECT_EQ(push_out_of_obstacles({&sheet, &cup}, 0.0).vertices, 0);
  EXPECT_EQ(sheet.x1, before);
  // The same vertices in the closed box are moved out.
  EXPECT_EQ(push_out_of_obstacles({&sheet, &box}, 0.0).vertices, 4);
}

TEST(InsideObstacles, TheMoveOutIsNotMotionAndWhatApproachedTheSurfaceIsLost) {
  // Vertex 0 ends 10 mm under the top of a box after moving 3 mm along x and 4 mm down over the
  // step; vertex 1, inside too, was moving up (out) by 2 mm. The box itself moves 1 mm along y.
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(0.0, 0.0, 0.0), 1e-3);
  CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  box.x0.col(1).array() -= 0.001;
  for (int v = 2; v < sheet.x1.rows(); ++v) {
    sheet.x1.row(v) << 0.2, 0.2 + 0.01 * v, 0.0;
    sheet.x0.row(v) = sheet.x1.row(v);
  }
  sheet.x1.row(0) << 0.0, 0.0, 0.04;
  sheet.x0.row(0) << -0.003, 0.0, 0.044;
  sheet.x1.row(1) << 0.01, 0.0, 0.04;
  sheet.x0.row(1) << 0.01, 0.0, 0.038;
  const InsideReport report = push_out_of_obstacles({&sheet, &box}, 0.0);
  EXPECT_EQ(report.vertices, 2);
  // Both on the top face; vertex 0 keeps its 3 mm along x and loses its 4 mm down (the top's
  // own motion is along y, tangential); vertex 1 keeps its 2 mm up.
  EXPECT_NEAR(sheet.x1(0, 2), 0.05, 1e-12);
  EXPECT_NEAR(sheet.x1(1, 2), 0.05, 1e-12);
  const Vec3 motion0 = (sheet.x1.row(0) - sheet.x0.row(0)).transpose();
  const Vec3 motion1 = (sheet.x1.row(1) - sheet.x0.row(1)).transpose();
  EXPECT_NEAR((motion0 - Vec3(0.003, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((motion1 - Vec3(0.0, 0.0, 0.002)).norm(), 0.0, 1e-12);
}

TEST(InsideObstacles, AVertexInsideOverlappingShapesLeavesByTheBodysOuterSurface) {
  // Box A, [−5, 5] cm cubed; box B, x in [0, 10] cm, z up to 4 cm, overlapping it. A vertex at
  // (4.5, 0, 3) cm, in both: the closest faces, A's x = 5 cm (5 mm) and B's top (10 mm), are
  // buried in the other box; the closest outer one is A's top (20 mm).
  const CollisionMesh body =
      join_obstacles(make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05)),
                     make_box(Vec3(0.0, -0.05, -0.05), Vec3(0.1, 0.05, 0.04)));
  ASSERT_TRUE(closed_and_oriented(body.faces));
  CollisionMesh obstacle = body;
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(0.3, 0.3, 0.0), 1e-3);
  sheet.x1.row(0) << 0.045, 0.0, 0.03;
  sheet.x0.row(0) = sheet.x1.row(0);
  const InsideReport report = push_out_of_obstacles({&sheet, &obstacle}, 1e-4);
  EXPECT_EQ(report.vertices, 1);
  EXPECT_NEAR((sheet.x1.row(0).transpose() - Vec3(0.045, 0.0, 0.05 + 1e-4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(report.depth, 0.02, 1e-12);
}

TEST(InsideObstacles, ANonConvexBodyIsLookedIntoByItsWindingNumber) {
  // A box with its (+, +, +) corner pulled in to the centre: a dent. A point in the dent is
  // outside the body; (3, 3, −4) cm is inside it though in front of a dented face's plane, so
  // a test that took the body for convex (behind every face) would miss it.
  CollisionMesh dented = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  dented.x0.row(7) << 0.0, 0.0, 0.0;
  dented.x1 = dented.x0;
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(0.3, 0.3, 0.0), 1e-3);
  sheet.x1.row(0) << 0.04, 0.04, 0.04;   // in the dent
  sheet.x1.row(1) << 0.03, 0.03, -0.04;  // inside
  sheet.x0 = sheet.x1;
  const Vec3 dent_point = sheet.x1.row(0).transpose(), inside = sheet.x1.row(1).transpose();
  EXPECT_LT(winding_number(dented.x1, dented.faces, dent_point), 0.5);
  EXPECT_GT(winding_number(dented.x1, dented.faces, inside), 0.5);
  bool behind_every_face = true;
  for (int f = 0; f < dented.faces.rows(); ++f) {
    const Vec3 a = dented.x1.row(dented.faces(f, 0)).transpose();
    const Vec3 n = (dented.x1.row(dented.faces(f, 1)).transpose() - a)
                       .cross(dented.x1.row(dented.faces(f, 2)).transpose() - a);
    behind_every_face = behind_every_face && n.dot(inside - a) < 0.0;
  }
  ASSERT_FALSE(behind_every_face);
  const InsideReport report = push_out_of_obstacles({&sheet, &dented}, 1e-4);
  EXPECT_EQ(report.vertices, 1);
  EXPECT_EQ(sheet.x1.row(0).transpose(), dent_point);
  EXPECT_LT(winding_number(dented.x1, dented.faces, sheet.x1.row(1).transpose()), 0.5);
}

TEST(InsideObstacles, AZeroAreaFaceDoesNotHideTheInside) {
  // A box whose top-front edge (4–5) carries a midpoint m: the top's triangle (4, 5, 7) becomes
  // (4, m, 7) and (m, 5, 7), and a zero-area sliver (4, 5, m) closes the mesh. The sliver has no
  // front or back; a vertex at the centre is still inside.
  CollisionMesh box = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  Points x(9, 3);
  x << box.x0, 0.5 * (box.x0.row(4) + box.x0.row(5));
  Triangles faces(14, 3);
  int row = 0;
  for (int f = 0; f < 12; ++f)
    if (f != 2) faces.row(row++) = box.faces.row(f);  // face 2 is (4, 5, 7)
  faces.row(row++) << 4, 8, 7;
  faces.row(row++) << 8, 5, 7;
  faces.row(row++) << 4, 5, 8;
  box.x0 = x;
  box.x1 = x;
  box.mass = Eigen::VectorXd::Ones(9);
  box.faces = faces;
  ASSERT_TRUE(closed_and_oriented(box.faces));
  CollisionMesh sheet = make_sheet(1, 1, 0.01, 0.01, Vec3(0.3, 0.3, 0.0), 1e-3);
  sheet.x1.row(0) << 0.0, 0.0, 0.04;
  sheet.x0 = sheet.x1;
  EXPECT_EQ(push_out_of_obstacles({&sheet, &box}, 0.0).vertices, 1);
  EXPECT_NEAR(sheet.x1(0, 2), 0.05, 1e-12);
}

TEST(ObstaclePieces, ConvexPiecesAreLookedIntoByTheirFacesOthersByWindingNumber) {
  // The dented box of the test above (not convex) and a convex box overlapping it on the side
  // away from the dent.
  CollisionMesh dented = make_box(Vec3(-0.05, -0.05, -0.05), Vec3(0.05, 0.05, 0.05));
  dented.x0.row(7) << 0.0, 0.0, 0.0;
  dented.x1 = dented.x0;
  const CollisionMesh body =
      join_obstacles(dented, make_box(Vec3(-0.1, -0.01, -0.01), Vec3(-0.04, 0.01, 0.01)));
  const MeshTopology topology = build_topology(body.faces, static_cast<int>(body.x0.rows()));
  ObstaclePieces pieces;
  pieces.update(body.x0, body.faces, topology);
  ASSERT_EQ(pieces.size(), 2);
  EXPECT_TRUE(pieces.inside(0, Vec3(0.03, 0.03, -0.04)));  // in front of a dented face's plane
  EXPECT_FALSE(pieces.inside(0, Vec3(0.04, 0.04, 0.04)));  // in the dent
  // The convex box: behind every face, by more than the margin when one is asked for.
  EXPECT_TRUE(pieces.inside(1, Vec3(-0.05, 0.0, 0.0)));
  EXPECT_TRUE(pieces.inside(1, Vec3(-0.05, 0.0, 0.0098), 1e-4));
  EXPECT_FALSE(pieces.inside(1, Vec3(-0.05, 0.0, 0.00995), 1e-4));
  EXPECT_FALSE(pieces.inside(1, Vec3(-0.05, 0.0, 0.01)));  // on its top face
  // Inside another piece than its own: a point of the small box's surface buried in the big one.
  EXPECT_TRUE(pieces.inside_other(1, Vec3(-0.045, 0.0, 0.01)));
  EXPECT_FALSE(pieces.inside_other(1, Vec3(-0.06, 0.0, 0.01)));
  EXPECT_FALSE(pieces.inside_other(0, Vec3(0.03, 0.03, -0.04)));
  // An open mesh has no inside.
  const Triangles open = body.faces.topRows(23);
  const MeshTopology open_topology = build_topology(open, static_cast<int>(body.x0.rows()));
  pieces.update(body.x0, open, open_topology);
  EXPECT_EQ(pieces.size(), 0);
}
