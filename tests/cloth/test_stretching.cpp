// Stretching energy: analytic values, gradient and Hessians against finite differences, PSD
// approximation properties.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "cloth/stretching.hpp"
#include "finite_difference.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

namespace {

/// A rest triangle in material space (2-D corners) and its derived Dm⁻¹ and area.
struct Rest {
  Mat2 Dm_inv;
  double area;
};

Rest make_rest(const Vec2& u0, const Vec2& u1, const Vec2& u2) {
  Mat2 Dm;
  Dm << u1 - u0, u2 - u0;
  return {Dm.inverse(), 0.5 * std::abs(Dm.determinant())};
}

StretchParams params(double poisson) {
  Material m;
  m.poisson = poisson;
  return stretch_params(m);
}

double energy(const Vec9& x, const Rest& r, const StretchParams& p) {
  return stretch_energy(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), r.Dm_inv, r.area, p);
}
Vec9 gradient(const Vec9& x, const Rest& r, const StretchParams& p) {
  return stretch_gradient(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), r.Dm_inv, r.area, p);
}
Mat9 hessian(const Vec9& x, const Rest& r, const StretchParams& p) {
  return stretch_hessian(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), r.Dm_inv, r.area, p);
}
Mat9 hessian_psd(const Vec9& x, const Rest& r, const StretchParams& p) {
  return stretch_hessian_psd(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), r.Dm_inv, r.area,
                             p);
}

/// Checks ∇E and ∇²E against central differences with step `eps` [m].
/// Tolerances: central differences with these steps are accurate to ~1e-8 relative (truncation
/// (eps/feature)² and roundoff 1e-16·E/eps); a wrong term is an O(1) relative error.
void expect_derivatives_match(const Vec9& x, const Rest& r, const StretchParams& p, double eps) {
  const Vec9 g = gradient(x, r, p);
  const Vec9 g_fd = test::fd_gradient<9>([&](const Vec9& y) { return energy(y, r, p); }, x, eps);
  EXPECT_LE((g - g_fd).norm(), 1e-6 * g.norm() + 1e-12)
      << "g=" << g.transpose() << "\nfd=" << g_fd.transpose();
  const Mat9 H = hessian(x, r, p);
  const Mat9 H_fd = test::fd_jacobian<9>([&](const Vec9& y) { return gradient(y, r, p); }, x, eps);
  EXPECT_LE((H - H_fd).norm(), 1e-5 * H.norm() + 1e-9);
}

/// The PSD Hessian has no eigenvalue below −1e-9·‖H‖ and maps rigid translations to zero.
void expect_psd_properties(const Vec9& x, const Rest& r, const StretchParams& p) {
  const Mat9 H = hessian_psd(x, r, p);
  const double scale = H.norm();
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat9>(H).eigenvalues().minCoeff(), -1e-9 * scale);
  for (int d = 0; d < 3; ++d) {
    Vec9 t = Vec9::Zero();
    t[d] = t[3 + d] = t[6 + d] = 1.0;
    EXPECT_LE((H * t).norm(), 1e-12 * scale);
  }
  EXPECT_LE((H - H.transpose()).norm(), 1e-12 * scale);
}

Vec9 stack(const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec9 x;
  x << a, b, c;
  return x;
}

}  // namespace

TEST(Stretching, LameParametersArePlaneStressTimesThickness) {
  Material m;
  m.youngs_modulus = 2e5;
  m.thickness = 2e-3;
  m.poisson = 0.25;
  const StretchParams p = stretch_params(m);
  EXPECT_DOUBLE_EQ(p.mu, 400.0 / 2.5);
  EXPECT_DOUBLE_EQ(p.lambda, 400.0 * 0.25 / (1.0 - 0.0625));
}

TEST(Stretching, UniaxialStretchEnergyMatchesClosedForm) {
  // Right triangle, stretched by factor s along u: G = diag(½(s² − 1), 0).
  const Rest r = make_rest(Vec2(0, 0), Vec2(0.02, 0), Vec2(0, 0.01));
  const StretchParams p = params(0.3);
  const double s = 1.05, g11 = 0.5 * (s * s - 1.0);
  const Vec9 x = stack(Vec3(0, 0, 0), Vec3(0.02 * s, 0, 0), Vec3(0, 0.01, 0));
  EXPECT_NEAR(energy(x, r, p), r.area * (p.mu + 0.5 * p.lambda) * g11 * g11, 1e-15);
  // ν = 0: the force on the stretched corner is the uniaxial stress E·t·G11 times the stretched
  // edge's share: |∂E/∂x1| = A·E·t·G11·s/|u1 − u0|.
  const StretchParams p0 = params(0.0);
  const Vec9 g = gradient(x, r, p0);
  EXPECT_NEAR(g[3], r.area * 5e5 * 1e-3 * g11 * s / 0.02, 1e-12);
}

TEST(Stretching, RigidMotionOfRestShapeHasZeroEnergyAndForce) {
  const Rest r = make_rest(Vec2(0, 0), Vec2(0.02, 0.003), Vec2(0.004, 0.015));
  const StretchParams p = params(0.3);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 t(0.3, -0.2, 1.0);
  const Vec9 x =
      stack(R * Vec3(0, 0, 0) + t, R * Vec3(0.02, 0.003, 0) + t, R * Vec3(0.004, 0.015, 0) + t);
  EXPECT_NEAR(energy(x, r, p), 0.0, 1e-18);
  EXPECT_LE(gradient(x, r, p).norm(), 1e-12);
}

TEST(Stretching, DerivativesMatchFiniteDifferencesOnRandomTriangles) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (double nu : {0.0, 0.3, 0.45}) {
    const StretchParams p = params(nu);
    for (int trial = 0; trial < 20; ++trial) {
      // Rest: a random well-shaped triangle of ~2 cm; current: rest corners mapped by a random
      // 3×2 deformation (stretch, shear and compression) plus noise.
      const Vec2 u0(0, 0), u1(0.02 + 0.005 * uni(rng), 0.005 * uni(rng));
      const Vec2 u2(0.005 * uni(rng), 0.02 + 0.005 * uni(rng));
      const Rest r = make_rest(u0, u1, u2);
      Mat32 A;
      A << 1 + 0.3 * uni(rng), 0.3 * uni(rng), 0.3 * uni(rng), 1 + 0.3 * uni(rng), 0.3 * uni(rng),
          0.3 * uni(rng);
      Vec9 x;
      const Vec2 u[3] = {u0, u1, u2};
      for (int k = 0; k < 3; ++k) {
        x.segment<3>(3 * k) = A * u[k] + 0.002 * Vec3(uni(rng), uni(rng), uni(rng));
      }
      expect_derivatives_match(x, r, p, 1e-7);
      expect_psd_properties(x, r, p);
    }
  }
}

TEST(Stretching, DerivativesMatchFiniteDifferencesOnSlivers) {
  // One vertex within 1e-3 (relative) of the opposite edge, in the rest shape and/or now.
  const StretchParams p = params(0.3);
  const double L = 0.02, d = 1e-3 * L;
  const Rest sliver_rest = make_rest(Vec2(0, 0), Vec2(L, 0), Vec2(0.4 * L, d));
  const Rest good_rest = make_rest(Vec2(0, 0), Vec2(L, 0), Vec2(0.4 * L, 0.8 * L));
  const Vec9 stretched_sliver =
      stack(Vec3(0, 0, 0), Vec3(1.02 * L, 0.001 * L, 0), Vec3(0.41 * L, 0.5 * d, 0.3 * d));
  const Vec9 flattened_good = stack(Vec3(0, 0, 0), Vec3(L, 0, 0), Vec3(0.4 * L, d, 0));
  // Steps well below the sliver height d = 2e-5 m.
  expect_derivatives_match(stretched_sliver, sliver_rest, p, 1e-4 * d);
  expect_derivatives_match(flattened_good, good_rest, p, 1e-4 * d);
  expect_psd_properties(stretched_sliver, sliver_rest, p);
  expect_psd_properties(flattened_good, good_rest, p);
}

TEST(Stretching, PsdHessianIsExactInTensionAndFixesCompression) {
  const Rest r = make_rest(Vec2(0, 0), Vec2(0.02, 0), Vec2(0.005, 0.02));
  const StretchParams p = params(0.3);
  // Uniform tension: S is positive definite, so the approximation equals the exact Hessian.
  const Vec9 tension = stack(Vec3(0, 0, 0), Vec3(0.022, 0, 0), Vec3(0.0055, 0.022, 0));
  EXPECT_LE((hessian_psd(tension, r, p) - hessian(tension, r, p)).norm(),
            1e-12 * hessian(tension, r, p).norm());
  // Strong compression: the exact Hessian is indefinite, the approximation is not.
  const Vec9 squeezed = stack(Vec3(0, 0, 0), Vec3(0.01, 0, 0), Vec3(0.0025, 0.01, 0));
  const Mat9 H = hessian(squeezed, r, p);
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Mat9>(H).eigenvalues().minCoeff(), -1e-3 * H.norm());
  expect_psd_properties(squeezed, r, p);
  // Mixed: tension along u, compression along v (indefinite S).
  const Vec9 mixed = stack(Vec3(0, 0, 0), Vec3(0.024, 0, 0), Vec3(0.006, 0.012, 0));
  expect_psd_properties(mixed, r, p);
  expect_derivatives_match(mixed, r, p, 1e-7);
}
