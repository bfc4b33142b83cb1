#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coupling/patch_update.hpp"
#include "rigid/obstacle_mesh.hpp"

using namespace dexcloth;
using namespace dexcloth::coupling;

namespace {

/// A contact group of vertex 7 of cloth 0 with mesh `mesh`, normal `n` (toward the vertex).
ContactGroup group(int mesh, const Vec3& n) {
  ContactGroup g;
  g.cloth = 0;
  g.vertex = 7;
  g.other_mesh = mesh;
  g.normal = n.normalized();
  return g;
}

}  // namespace

TEST(PatchUpdate, APinchedVertexIsClusteredByItsFingersNormalNotItsWrinkle) {
  // Cloth normal tilted 35° by a wrinkle; the two fingers (meshes 2 and 3; 0 and 1 are cloths)
  // press along ±y.
  const Vec3 wrinkle(std::sin(0.61), std::cos(0.61), 0.0);
  const std::vector<ContactGroup> pinched{group(2, Vec3::UnitY()), group(3, -Vec3::UnitY())};
  EXPECT_NEAR((clustering_normal(wrinkle, pinched, 2) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  // Turned to the cloth normal's side.
  EXPECT_NEAR((clustering_normal(-wrinkle, pinched, 2) + Vec3::UnitY()).norm(), 0.0, 1e-12);
  // Touching a finger and another cloth layer: only the finger counts.
  const std::vector<ContactGroup> layered{group(1, Vec3::UnitX()), group(3, -Vec3::UnitY())};
  EXPECT_NEAR((clustering_normal(wrinkle, layered, 2) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  // Touching no rigid surface: the cloth normal.
  const std::vector<ContactGroup> cloth_only{group(1, Vec3::UnitX())};
  EXPECT_NEAR((clustering_normal(wrinkle, cloth_only, 2) - wrinkle).norm(), 0.0, 1e-12);
}

TEST(PatchUpdate, ATouchTakesTheBodysOwnNormalNotTheClothsItsRecordCarries) {
  // A 2 cm box; the cloth lies on its +y face, tilted 16° toward +x, and the group's normal is
  // the cloth's (a record of a box corner against a cloth face carries the cloth's normal).
  const rigid::LocalMesh box = rigid::box_mesh(Vec3(0.02, 0.02, 0.02));
  const collision::MeshTopology topology =
      collision::build_topology(box.faces, static_cast<int>(box.x.rows()));
  const auto corner_at = [&](const Vec3& p) {
    for (Eigen::Index i = 0; i < box.x.rows(); ++i)
      if ((box.x.row(i).transpose() - p).norm() < 1e-12) return static_cast<int>(i);
    return -1;
  };
  const int c0 = corner_at(Vec3(0.01, 0.01, 0.01)), c1 = corner_at(Vec3(-0.01, 0.01, 0.01));
  ASSERT_GE(c0, 0);
  ASSERT_GE(c1, 0);
  const double tilt = 16.0 * std::acos(-1.0) / 180.0;
  const Vec3 cloth(std::sin(tilt), std::cos(tilt), 0.0);
  // A corner of the box touching a cloth face: of the three faces there, the +y face.
  ContactGroup corner = group(2, cloth);
  corner.other_vertices = {c0, -1, -1};
  corner.other_weights = Vec3(1, 0, 0);
  EXPECT_NEAR((body_normal(corner, box.x, box.faces, topology) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  // Tilted past 45° toward +x, the cloth lies on the +x face.
  const Vec3 steep(std::sin(1.0), std::cos(1.0), 0.0);
  corner.normal = steep;
  EXPECT_NEAR((body_normal(corner, box.x, box.faces, topology) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  // An edge of the box (between the +y and +z faces): the +y face.
  ContactGroup edge = group(2, cloth);
  edge.other_vertices = {c0, c1, -1};
  edge.other_weights = Vec3(0.3, 0.7, 0);
  EXPECT_NEAR((body_normal(edge, box.x, box.faces, topology) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  // A cloth vertex over a face of the box: that face's normal, whatever the cloth's.
  for (Eigen::Index f = 0; f < box.faces.rows(); ++f) {
    const Vec3 n = (box.x.row(box.faces(f, 1)) - box.x.row(box.faces(f, 0)))
                       .transpose()
                       .cross((box.x.row(box.faces(f, 2)) - box.x.row(box.faces(f, 0))).transpose())
                       .normalized();
    if (n.dot(Vec3::UnitY()) < 0.99) continue;
    ContactGroup face = group(2, cloth);
    face.other_vertices = {box.faces(f, 0), box.faces(f, 1), box.faces(f, 2)};
    EXPECT_NEAR((body_normal(face, box.x, box.faces, topology) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  }
  // From below (the group's normal on the other side): turned to that side.
  ContactGroup below = group(2, -cloth);
  below.other_vertices = {c0, -1, -1};
  below.other_weights = Vec3(1, 0, 0);
  EXPECT_NEAR((body_normal(below, box.x, box.faces, topology) + Vec3::UnitY()).norm(), 0.0, 1e-12);
  // No corner (a degenerate record): the group's normal.
  ContactGroup none = group(2, cloth);
  EXPECT_NEAR((body_normal(none, box.x, box.faces, topology) - cloth).norm(), 0.0, 1e-12);
}
