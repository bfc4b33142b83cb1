/// Cloth–cloth friction as equal and opposite pair impulses (pair_friction.hpp): momentum is
/// kept exactly, and at convergence every pair meets Coulomb's conditions.
#include <gtest/gtest.h>

#include "cloth/collision/cloth_contacts.hpp"
#include "cloth/collision/pair_friction.hpp"
#include "mesh_builders.hpp"

using namespace dexcloth;
using namespace dexcloth::collision;
using namespace dexcloth::collision::testing;

namespace {

constexpr double kThickness = 5e-3;
constexpr double kDt = 5e-3;

/// Two sheets 2 mm apart closing at 1 m/s and sliding past each other at (0.5, −0.1) m/s, of
/// vertex masses 1 g and 2 g, after the repulsion (no friction): the pairs and their impulses.
struct Layers {
  CollisionMesh a = make_sheet(4, 4, 0.1, 0.1, Vec3(0, 0, 0), 1e-3);
  CollisionMesh b = make_sheet(4, 4, 0.1, 0.1, Vec3(0.01, 0.012, 2e-3), 2e-3);
  ClothContacts contacts;
  std::vector<CollisionMesh*> meshes() { return {&a, &b}; }

  explicit Layers(double mu) {
    a.friction = b.friction = mu;
    for (Eigen::Index v = 0; v < a.x1.rows(); ++v) {
      a.x1.row(v) += kDt * Eigen::RowVector3d(0.3, 0.0, 0.5);
      b.x1.row(v) += kDt * Eigen::RowVector3d(-0.2, 0.1, -0.5);
    }
    RepulsionOptions repulsion;
    repulsion.thickness = kThickness;
    repulsion.dt = kDt;
    repulsion.friction = false;
    detect_cloth_contacts(meshes(), repulsion, contacts);
  }
};

Vec3 momentum(const CollisionMesh& m) {
  Vec3 p = Vec3::Zero();
  for (Eigen::Index v = 0; v < m.x1.rows(); ++v)
    p += m.mass[v] * (m.x1.row(v) - m.x0.row(v)).transpose() / kDt;
  return p;
}

/// Relative tangential velocity of pair `p`'s closest points.
Vec3 tangential_velocity(const std::vector<CollisionMesh*>& meshes, const Proximity& p) {
  Vec3 vr = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    const CollisionMesh& m = *meshes[static_cast<std::size_t>(p.corner_mesh(k))];
    const int v = p.corner[static_cast<std::size_t>(k)];
    vr += p.w[k] * (m.x1.row(v) - m.x0.row(v)).transpose() / kDt;
  }
  return vr - p.normal.dot(vr) * p.normal;
}

/// Counts of pairs found stuck and sliding; fails where a pair breaks Coulomb's conditions:
/// ‖J‖ ≤ μλ, stuck inside the disc, and on its rim against the sliding velocity.
std::pair<int, int> expect_coulomb(Layers& s, const std::vector<Vec3>& impulses, double mu) {
  int stuck = 0, sliding = 0;
  for (std::size_t i = 0; i < s.contacts.proximities.size(); ++i) {
    const double bound = mu * s.contacts.impulses[i];
    const Vec3& j = impulses[i];
    const Vec3 vt = tangential_velocity(s.meshes(), s.contacts.proximities[i]);
    EXPECT_LE(j.norm(), bound * (1.0 + 1e-12)) << "pair " << i;
    if (bound == 0.0) continue;
    if (vt.norm() <= 1e-9) {
      ++stuck;
    } else {
      ++sliding;
      EXPECT_NEAR(j.norm(), bound, 1e-9 * bound) << "pair " << i << " slides inside its cone";
      EXPECT_LT(j.dot(vt), -(1.0 - 1e-6) * j.norm() * vt.norm()) << "pair " << i;
    }
  }
  return {stuck, sliding};
}

}  // namespace

TEST(PairFriction, TheTwoSidesMomentaChangeByOppositeAmounts) {
  for (const int sweeps : {1, 8}) {
    Layers s(0.4);
    const Vec3 before = momentum(s.a) + momentum(s.b);
    const Vec3 a_before = momentum(s.a);
    PairFrictionOptions options;
    options.dt = kDt;
    options.sweeps = sweeps;
    std::vector<Vec3> impulses;
    apply_pair_friction(s.meshes(), s.contacts.proximities, s.contacts.impulses, options, impulses);
    const Vec3 after = momentum(s.a) + momentum(s.b);
    EXPECT_LT((after - before).norm(), 1e-15) << sweeps << " sweeps";
    // And friction acted: the lower sheet (moving +x relative to the upper) was slowed along x.
    EXPECT_LT(momentum(s.a).x(), a_before.x() - 1e-4) << sweeps << " sweeps";
  }
}

TEST(PairFriction, ConvergedPairsStickInsideTheirConesAndSlideOnTheRim) {
  // μ = 0.05 cannot stop a pair sliding at 0.5 m/s (μλK ≤ 0.05·1.05 m/s); with μ = 2 most
  // pairs stick (those of small λ, at the overlap's rim or with a small weight, still slide).
  for (const double mu : {2.0, 0.05}) {
    Layers s(mu);
    PairFrictionOptions options;
    options.dt = kDt;
    options.sweeps = 2000;
    std::vector<Vec3> impulses;
    apply_pair_friction(s.meshes(), s.contacts.proximities, s.contacts.impulses, options, impulses);
    const auto [stuck, sliding] = expect_coulomb(s, impulses, mu);
    if (mu > 1.0) {
      EXPECT_GT(stuck, 2 * sliding);
    } else {
      EXPECT_EQ(stuck, 0);
      EXPECT_GT(sliding, 10);
    }
  }
}

TEST(PairFriction, HeldVerticesDriveTheirSide) {
  // The upper sheet is held (a grip drives it): it does not move, and the lower one's pairs
  // meet Coulomb's conditions against it.
  Layers s(2.0);
  const std::vector<std::vector<std::uint8_t>> held = {{}, std::vector<std::uint8_t>(25, 1)};
  const Points b_before = s.b.x1;
  PairFrictionOptions options;
  options.dt = kDt;
  options.sweeps = 2000;
  options.held = &held;
  std::vector<Vec3> impulses;
  apply_pair_friction(s.meshes(), s.contacts.proximities, s.contacts.impulses, options, impulses);
  EXPECT_EQ(s.b.x1, b_before);
  const auto [stuck, sliding] = expect_coulomb(s, impulses, 2.0);
  EXPECT_GT(stuck, 2 * sliding);
}

TEST(PairFriction, ClothOnlyLeavesPairsWithAnObstacleAlone) {
  CollisionMesh cloth = make_sheet(2, 2, 0.02, 0.02, Vec3(0, 0, 2e-3), 1e-3);
  CollisionMesh table = make_sheet(1, 1, 1.0, 1.0, Vec3(-0.5, -0.5, 0), 1.0);
  table.obstacle = true;
  for (Eigen::Index v = 0; v < cloth.x1.rows(); ++v)
    cloth.x1.row(v) += kDt * Eigen::RowVector3d(0.3, 0.0, -0.5);
  RepulsionOptions repulsion;
  repulsion.thickness = kThickness;
  repulsion.dt = kDt;
  repulsion.friction = false;
  ClothContacts contacts;
  detect_cloth_contacts({&cloth, &table}, repulsion, contacts);
  ASSERT_FALSE(contacts.proximities.empty());
  const Points before = cloth.x1;
  PairFrictionOptions options;
  options.dt = kDt;
  options.cloth_only = true;
  std::vector<Vec3> impulses;
  apply_pair_friction({&cloth, &table}, contacts.proximities, contacts.impulses, options, impulses);
  EXPECT_EQ(cloth.x1, before);
  options.cloth_only = false;
  apply_pair_friction({&cloth, &table}, contacts.proximities, contacts.impulses, options, impulses);
  EXPECT_LT(cloth.x1(0, 0) - cloth.x0(0, 0), before(0, 0) - cloth.x0(0, 0));
}
