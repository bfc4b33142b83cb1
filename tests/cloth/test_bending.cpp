// Dihedral bending: angle values and sign, gradient and Hessians against finite differences on
// bent, flat, strongly folded and sliver hinges, PSD approximation, and the bending constant.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <random>

#include "cloth/bending.hpp"
#include "cloth/energy.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"
#include "finite_difference.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

namespace {

constexpr double kL = 0.02;  // edge length of the test hinges [m]

/// Hinge on the x axis: x0 = 0, x1 = (L, 0, 0); wing x2 at edge position a, height h, lifted by
/// phi towards +z; wing x3 at edge position b, height h3, lifted by psi towards +z.
Vec12 hinge(double a, double h, double phi, double b, double h3, double psi) {
  Vec12 x;
  x << 0, 0, 0, kL, 0, 0, a, h * std::cos(phi), h * std::sin(phi), b, -h3 * std::cos(psi),
      h3 * std::sin(psi);
  return x;
}

double theta(const Vec12& x) {
  return dihedral_angle(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9));
}
Vec12 theta_gradient(const Vec12& x) {
  return dihedral_angle_gradient(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                 x.segment<3>(9));
}

struct Params {
  double rest_angle, weight, k;
};
double energy(const Vec12& x, const Params& p) {
  return bending_energy(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9),
                        p.rest_angle, p.weight, p.k);
}
Vec12 gradient(const Vec12& x, const Params& p) {
  return bending_gradient(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9),
                          p.rest_angle, p.weight, p.k);
}

/// ∇θ, ∇²θ, ∇E and ∇²E against central differences with step `eps` [m]. Tolerances as in
/// test_stretching: the differences are accurate to ~1e-8 relative, a wrong term is O(1).
void expect_derivatives_match(const Vec12& x, const Params& p, double eps) {
  const Vec12 gt = theta_gradient(x);
  EXPECT_LE((gt - test::fd_gradient<12>(theta, x, eps)).norm(), 1e-6 * gt.norm());
  const Mat12 Ht =
      dihedral_angle_hessian(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9));
  EXPECT_LE((Ht - test::fd_jacobian<12>(theta_gradient, x, eps)).norm(), 1e-5 * Ht.norm());

  const Vec12 g = gradient(x, p);
  const Vec12 g_fd = test::fd_gradient<12>([&](const Vec12& y) { return energy(y, p); }, x, eps);
  EXPECT_LE((g - g_fd).norm(), 1e-6 * g.norm() + 1e-12 * gt.norm());
  const Mat12 H = bending_hessian(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                  x.segment<3>(9), p.rest_angle, p.weight, p.k);
  const Mat12 H_fd = test::fd_jacobian<12>([&](const Vec12& y) { return gradient(y, p); }, x, eps);
  EXPECT_LE((H - H_fd).norm(), 1e-5 * H.norm());
}

/// Gauss–Newton Hessian: PSD (no eigenvalue below −1e-9·‖H‖), symmetric, and zero on rigid
/// translations and infinitesimal rotations.
void expect_psd_properties(const Vec12& x, const Params& p) {
  const Mat12 H = bending_hessian_psd(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6),
                                      x.segment<3>(9), p.rest_angle, p.weight, p.k);
  const double scale = H.norm();
  ASSERT_GT(scale, 0.0);
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat12>(H).eigenvalues().minCoeff(), -1e-9 * scale);
  for (int d = 0; d < 3; ++d) {
    Vec12 t = Vec12::Zero(), r = Vec12::Zero();
    for (int v = 0; v < 4; ++v) {
      t[3 * v + d] = 1.0;
      r.segment<3>(3 * v) = Vec3::Unit(d).cross(Vec3(x.segment<3>(3 * v)));
    }
    EXPECT_LE((H * t).norm(), 1e-12 * scale);
    EXPECT_LE((H * r).norm(), 1e-9 * scale * kL);
  }
}

}  // namespace

TEST(Bending, DihedralAngleValueAndSign) {
  EXPECT_NEAR(theta(hinge(0.01, 0.015, 0.0, 0.008, 0.012, 0.0)), 0.0, 1e-15);
  // Wings lifted towards the normal side (+z) give a positive angle, the sum of the lifts.
  EXPECT_NEAR(theta(hinge(0.01, 0.015, 0.3, 0.008, 0.012, 0.2)), 0.5, 1e-12);
  EXPECT_NEAR(theta(hinge(0.01, 0.015, -0.3, 0.008, 0.012, -0.4)), -0.7, 1e-12);
  EXPECT_NEAR(theta(hinge(0.01, 0.015, 1.55, 0.008, 0.012, 1.56)), 3.11, 1e-12);
  EXPECT_NEAR(theta(hinge(0.01, 0.015, -1.55, 0.008, 0.012, -1.56)), -3.11, 1e-12);
  // Swapping the roles of the two triangles (edge reversed) gives the same angle.
  const Vec12 x = hinge(0.01, 0.015, 0.4, 0.008, 0.012, 0.1);
  Vec12 swapped;
  swapped << x.segment<3>(3), x.segment<3>(0), x.segment<3>(9), x.segment<3>(6);
  EXPECT_NEAR(theta(swapped), theta(x), 1e-12);
}

TEST(Bending, FullyFoldedAndDegenerateHingesStayFinite) {
  // θ = ±π exactly: both wings on the same side.
  const Vec12 folded =
      hinge(0.01, 0.015, 0.5 * std::numbers::pi, 0.008, 0.012, 0.5 * std::numbers::pi);
  EXPECT_NEAR(std::abs(theta(folded)), std::numbers::pi, 1e-12);
  EXPECT_TRUE(theta_gradient(folded).allFinite());
  // Zero-area wing and zero-length edge: zero angle, gradient and Hessian, never NaN.
  Vec12 flat_wing = hinge(0.01, 0.0, 0.0, 0.008, 0.012, 0.0);
  Vec12 no_edge = hinge(0.01, 0.015, 0.2, 0.008, 0.012, 0.1);
  no_edge.segment<3>(3).setZero();
  for (const Vec12& x : {flat_wing, no_edge}) {
    EXPECT_EQ(theta(x), 0.0);
    EXPECT_EQ(theta_gradient(x).norm(), 0.0);
    const Params p{0.3, 1.0, 1.0};
    EXPECT_TRUE(gradient(x, p).allFinite());
    EXPECT_TRUE(bending_hessian(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9),
                                p.rest_angle, p.weight, p.k)
                    .allFinite());
  }
}

TEST(Bending, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  // Bent, flat and strongly folded (near ±π) hinges with random rest angles and noise.
  const double lifts[][2] = {{0.0, 0.0},   {0.3, -0.1}, {0.7, 0.6},
                             {-0.9, -0.5}, {1.5, 1.45}, {-1.5, -1.52}};
  for (const auto& lift : lifts) {
    for (int trial = 0; trial < 5; ++trial) {
      Vec12 x =
          hinge(0.01 + 0.005 * uni(rng), 0.015, lift[0], 0.008 + 0.005 * uni(rng), 0.012, lift[1]);
      for (int i = 0; i < 12; ++i) x[i] += 0.001 * uni(rng);
      const Params p{0.5 * uni(rng), 1.0 + 0.5 * uni(rng), 1.0};
      expect_derivatives_match(x, p, 1e-7);
      expect_psd_properties(x, p);
    }
  }
}

TEST(Bending, DerivativesMatchFiniteDifferencesOnSlivers) {
  // A wing within 1e-3·L of the edge line (sliver triangle), bent and flat; and a wing whose
  // foot lies far outside the edge (obtuse sliver).
  const double d = 1e-3 * kL;
  const Params p{0.25, 1.2, 1.0};  // no hinge sits at its rest angle (zero gradient)
  const Vec12 bent_sliver = hinge(0.012, d, 0.4, 0.008, 0.012, 0.2);
  const Vec12 flat_sliver = hinge(0.012, d, 0.0, 0.008, 0.012, 0.0);
  const Vec12 obtuse_sliver = hinge(-0.01, d, 0.3, 0.03, d, -0.2);
  for (const Vec12& x : {bent_sliver, flat_sliver, obtuse_sliver}) {
    expect_derivatives_match(x, p, 1e-4 * d);  // steps well below the sliver height
    expect_psd_properties(x, p);
  }
}

TEST(Bending, GridBentIntoCylinderStoresPlateEnergy) {
  // A right-triangle grid wrapped isometrically around a cylinder of radius R (axis along y):
  // every interior y-edge has θ = a_x/R, all other hinges stay flat, so with k = D/2 the energy
  // is ½·D·A_interior/R² exactly, A_interior = (nx − 2)(ny − 1)·a_x·a_y.
  const int nx = 9, ny = 5;
  const double width = 0.4, height = 0.2, R = 0.3;
  const ClothMesh rest = make_grid(width, height, nx, ny);
  Material m;
  m.bending_stiffness = 2e-5;
  const ClothModel model = build_model(rest, m);
  Points x = rest.x;
  for (int i = 0; i < x.rows(); ++i) {
    const double s = rest.x(i, 0);
    x.row(i) << R * std::sin(s / R), rest.x(i, 1), R * (1.0 - std::cos(s / R));
  }
  const double ax = width / (nx - 1), ay = height / (ny - 1);
  const double expected = 0.5 * m.bending_stiffness * (nx - 2) * (ny - 1) * ax * ay / (R * R);
  EXPECT_NEAR(total_bending_energy(model, x), expected, 1e-9 * expected);
}
