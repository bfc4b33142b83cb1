#include <gtest/gtest.h>

#include <string>

#include "cloth/collision/cloth_contacts.hpp"
#include "cloth/collision/impact_zones.hpp"
#include "cloth/collision/intersection.hpp"
#include "cloth/collision/strain_limit.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

constexpr double kDt = 5e-3;         // step [s]
constexpr double kThickness = 5e-3;  // repulsion thickness [m]
constexpr double kRadius = 0.25;     // sphere radius [m]

// Inverse rest-shape matrices of a flat sheet's faces (material space = rest x, y).
std::vector<Mat2> rest_shapes(const CollisionMesh& sheet) {
  std::vector<Mat2> dm_inv;
  for (int f = 0; f < sheet.faces.rows(); ++f) {
    Mat2 dm;
    for (int k = 0; k < 2; ++k) {
      const auto e = sheet.x0.row(sheet.faces(f, k + 1)) - sheet.x0.row(sheet.faces(f, 0));
      dm.col(k) = Vec2(e[0], e[1]);
    }
    dm_inv.push_back(dm.inverse());
  }
  return dm_inv;
}

}  // namespace

// The drape_sphere scene's first contact, reduced to the collision pipeline of one coupling
// step (repulsion → strain limit → impact zones): a sheet falling at 1.5 m/s (7.5 mm per step,
// more than the thickness) onto the pole of a 16 × 8 tessellated sphere. The sheet's centre
// vertex lands on the pole and its grid lines lie in the planes of the pole's meridian edges,
// so cloth and sphere edges meet end-on in common planes.
TEST(SphereDrop, FallingSheetDrapesWithoutIntersectionsOrWarnings) {
  CollisionMesh sheet = make_sheet(24, 24, 0.6, 0.6, Vec3(-0.3, -0.3, kRadius + 0.03), 2e-4);
  CollisionMesh sphere = make_sphere(Vec3::Zero(), kRadius, 8, 16);
  ASSERT_EQ(sheet.x0(12 * 25 + 12, 0), 0.0);  // the centre vertex is above the pole
  const std::vector<Mat2> dm_inv = rest_shapes(sheet);
  const std::vector<CollisionMesh*> meshes{&sheet, &sphere};
  const std::vector<const CollisionMesh*> view{&sheet, &sphere};

  Points v = Points::Zero(sheet.x0.rows(), 3);
  v.col(2).setConstant(-1.5);
  const Vec3 gravity(0.0, 0.0, -9.81);
  RepulsionOptions repulsion;
  repulsion.thickness = kThickness;
  repulsion.dt = kDt;
  StrainLimitOptions strain;
  ImpactZoneOptions zones;
  zones.offset = 0.03 * kThickness;  // as the coupling step sets it
  ClothContacts contacts;
  ImpactZoneSolver solver;

  int touching_steps = 0;
  for (int step = 0; step < 40; ++step) {
    // Free fall, then the collision pipeline of coupling::step.
    v.rowwise() += kDt * gravity.transpose();
    sheet.x1 = sheet.x0 + kDt * v;
    detect_cloth_contacts(meshes, repulsion, contacts);
    touching_steps += contacts.contacts.empty() ? 0 : 1;
    const StrainLimitReport limited =
        limit_strain(sheet.x1, sheet.faces, dm_inv, sheet.mass, sheet.frozen, strain);
    ASSERT_TRUE(limited.converged) << "step " << step;
    const ImpactZoneReport report = solver.resolve(meshes, zones);
    ASSERT_TRUE(report.converged) << "step " << step;
    ASSERT_TRUE(report.warnings.empty()) << "step " << step << ": " << report.warnings.front();
    ASSERT_EQ(count_intersections(view, true), 0) << "step " << step;
    v = (sheet.x1 - sheet.x0) / kDt;
    sheet.x0 = sheet.x1;
  }
  // It did land: in contact for most of the run, the centre resting on the pole within the
  // thickness (not tunnelled, not stopped short).
  EXPECT_GT(touching_steps, 25);
  const double centre_height = sheet.x0(12 * 25 + 12, 2) - kRadius;
  EXPECT_GT(centre_height, 0.0);
  EXPECT_LT(centre_height, 2.0 * kThickness);
}
