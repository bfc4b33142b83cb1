#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coupling/patch_update.hpp"

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
