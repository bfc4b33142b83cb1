#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "coupling/contact_forces.hpp"

using namespace dexcloth;
using namespace dexcloth::coupling;

namespace {

/// Meshes 0 and 1 are cloths; 2 and 3 are the fingers of a hand, 4 is a table.
constexpr int kCloths = 2;

ContactGroup group(int mesh, const Vec3& n, double fn) {
  ContactGroup g;
  g.cloth = 0;
  g.vertex = 5;
  g.other_mesh = mesh;
  g.normal = n.normalized();
  g.normal_force = fn;
  g.other_vertices = {0, 1, 2};
  g.other_weights = Vec3(0.2, 0.3, 0.5);
  return g;
}

/// Fingers move at (0.1, 0, 0) and (0.3, 0, 0) m/s with μ 0.5; the table is still, μ 0.4;
/// cloth 0 moves at (0, 0.2, 0) and cloth 1 at (0, 0.4, 0) m/s, μ 0.5.
GripSurface surface(const ContactGroup& g) {
  if (g.other_mesh == 0) return {true, Vec3(0, 0.2, 0), 0.5};
  if (g.other_mesh == 1) return {true, Vec3(0, 0.4, 0), 0.5};
  if (g.other_mesh == 2) return {true, Vec3(0.1, 0, 0), 0.5};
  if (g.other_mesh == 3) return {true, Vec3(0.3, 0, 0), 0.5};
  return {false, Vec3::Zero(), 0.4};
}

std::optional<cloth::FrictionConstraint> grip(const std::vector<ContactGroup>& groups) {
  return grip_constraint(groups, kCloths, std::sin(2.0 * M_PI / 180.0), 0.005, surface);
}

}  // namespace

TEST(GripConstraint, APinchedVertexIsHeldByBothFingersWhateverClothItAlsoTouches) {
  // Squeezed between the fingers (1 N and 3 N), with the cloth folded onto it from the side.
  const std::vector<ContactGroup> pinched{group(1, Vec3::UnitX(), 0.02), group(2, Vec3::UnitZ(), 1.0),
                                          group(3, -Vec3::UnitZ(), 3.0)};
  const auto c = grip(pinched);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->vertex, 5);
  EXPECT_NEAR((c->normal - Vec3::UnitZ()).norm(), 0.0, 1e-15);  // the first finger's, not the fold's
  EXPECT_NEAR(c->max_impulse, 0.5 * (1.0 + 3.0) * 0.005, 1e-15);  // μ Σ fN h
  EXPECT_NEAR((c->surface_velocity - Vec3(0.25, 0, 0)).norm(), 0.0, 1e-15);  // fN-weighted
  // The same without the fold gives the same constraint.
  const auto bare = grip({pinched[1], pinched[2]});
  ASSERT_TRUE(bare.has_value());
  EXPECT_EQ(bare->max_impulse, c->max_impulse);
}

TEST(GripConstraint, VerticesNotHeldByAHandAloneAreLeftToThePerVertexProblem) {
  // Cloth only; a prop (the table) with a finger; fingers whose planes differ by 5°; a finger
  // without a surface record; no normal force.
  EXPECT_FALSE(grip({group(1, Vec3::UnitZ(), 0.5)}).has_value());
  EXPECT_FALSE(grip({group(2, Vec3::UnitZ(), 1.0), group(4, -Vec3::UnitZ(), 1.0)}).has_value());
  const Vec3 tilted(std::sin(5.0 * M_PI / 180.0), 0, -std::cos(5.0 * M_PI / 180.0));
  EXPECT_FALSE(grip({group(2, Vec3::UnitZ(), 1.0), group(3, tilted, 1.0)}).has_value());
  ContactGroup unrecorded = group(3, -Vec3::UnitZ(), 1.0);
  unrecorded.other_vertices = {-1, -1, -1};
  EXPECT_FALSE(grip({group(2, Vec3::UnitZ(), 1.0), unrecorded}).has_value());
  EXPECT_FALSE(grip({group(2, Vec3::UnitZ(), 0.0)}).has_value());
  // Planes 1° apart are one plane.
  const Vec3 close(std::sin(1.0 * M_PI / 180.0), 0, -std::cos(1.0 * M_PI / 180.0));
  EXPECT_TRUE(grip({group(2, Vec3::UnitZ(), 1.0), group(3, close, 1.0)}).has_value());
}

TEST(GripConstraint, AMiddleLayerSqueezedInAStackIsHeldByTheClothsBesideIt) {
  // A vertex between cloths 0 and 1 (0.1 N and 0.3 N of squeeze, marked by the stack's patch)
  // grips them as a pinched vertex grips two fingers; with their repulsion force only (no patch)
  // it is left to the per-vertex problem.
  ContactGroup below = group(0, Vec3::UnitZ(), 0.1), above = group(1, -Vec3::UnitZ(), 0.3);
  EXPECT_FALSE(grip({below, above}).has_value());
  below.rigid_patch = above.rigid_patch = 4;
  const auto c = grip({below, above});
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->max_impulse, 0.5 * (0.1 + 0.3) * 0.005, 1e-15);
  EXPECT_NEAR((c->surface_velocity - Vec3(0, 0.35, 0)).norm(), 0.0, 1e-15);  // fN-weighted
}
