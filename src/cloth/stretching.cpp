#include "cloth/stretching.hpp"

namespace dexcloth::cloth {
namespace {

/// Per-triangle kinematics: F, the shape-function gradients d_k (F = Σ x_k d_kᵀ) and G.
struct Kinematics {
  Mat32 F;
  Eigen::Matrix<double, 2, 3> d;  ///< column k is d_k
  Mat2 G;
};

Kinematics kinematics(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv) {
  Kinematics k;
  Mat32 Ds;
  Ds.col(0) = x1 - x0;
  Ds.col(1) = x2 - x0;
  k.F = Ds * Dm_inv;
  // F = (x1 − x0)·row0(Dm⁻¹) + (x2 − x0)·row1(Dm⁻¹), so d1 = row0ᵀ, d2 = row1ᵀ, d0 = −d1 − d2.
  k.d.col(1) = Dm_inv.row(0).transpose();
  k.d.col(2) = Dm_inv.row(1).transpose();
  k.d.col(0) = -k.d.col(1) - k.d.col(2);
  k.G = 0.5 * (k.F.transpose() * k.F - Mat2::Identity());
  return k;
}

/// Second Piola–Kirchhoff stress S = ∂Ψ/∂G = 2μG + λ·tr(G)·I [N/m].
Mat2 piola2(const Mat2& G, const StretchParams& p) {
  return 2.0 * p.mu * G + p.lambda * G.trace() * Mat2::Identity();
}

/// Positive semi-definite part of a symmetric 2×2 matrix (negative eigenvalues set to 0).
Mat2 psd_part(const Mat2& S) {
  const double a = S(0, 0), b = 0.5 * (S(0, 1) + S(1, 0)), c = S(1, 1);
  const double mean = 0.5 * (a + c);
  const double radius = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  const double l1 = mean + radius, l2 = mean - radius;
  if (l2 >= 0.0) return S;
  if (l1 <= 0.0) return Mat2::Zero();
  // Eigenvector of l1: (b, l1 − a) or (l1 − c, b), whichever is better conditioned.
  Vec2 e = (std::abs(l1 - a) > std::abs(l1 - c)) ? Vec2(b, l1 - a) : Vec2(l1 - c, b);
  const double n = e.squaredNorm();
  if (n == 0.0) return Mat2::Zero();
  return (l1 / n) * e * e.transpose();
}

/// Hessian [N/m] for stress `S` (exact S gives the exact Hessian):
/// H_kl = A[(d_lᵀ S d_k) I + μ a_l a_kᵀ + μ (d_l·d_k) FFᵀ + λ a_k a_lᵀ],  a_k = F d_k.
Mat9 hessian_with_stress(const Kinematics& k, const Mat2& S, double area, const StretchParams& p) {
  const Mat3 FFt = k.F * k.F.transpose();
  const Eigen::Matrix<double, 3, 3> a = k.F * k.d;  // column k is a_k
  const Eigen::Matrix<double, 3, 3> dSd = k.d.transpose() * S * k.d;
  const Eigen::Matrix<double, 3, 3> dd = k.d.transpose() * k.d;
  Mat9 H;
  for (int r = 0; r < 3; ++r) {
    for (int c = r; c < 3; ++c) {
      const Mat3 block =
          area * (dSd(c, r) * Mat3::Identity() + p.mu * a.col(c) * a.col(r).transpose() +
                  p.mu * dd(c, r) * FFt + p.lambda * a.col(r) * a.col(c).transpose());
      H.block<3, 3>(3 * r, 3 * c) = block;
      if (c != r) H.block<3, 3>(3 * c, 3 * r) = block.transpose();
    }
  }
  return H;
}

/// Gradient [N]: ∂E/∂x_k = A·F·S·d_k.
Vec9 gradient_with_stress(const Kinematics& k, const Mat2& S, double area) {
  const Eigen::Matrix<double, 3, 3> g = area * k.F * S * k.d;
  return Eigen::Map<const Vec9>(g.data());
}

}  // namespace

StretchParams stretch_params(const Material& m) {
  const double et = m.youngs_modulus * m.thickness;
  return {et / (2.0 * (1.0 + m.poisson)), et * m.poisson / (1.0 - m.poisson * m.poisson)};
}

double stretch_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                      double rest_area, const StretchParams& p) {
  const Kinematics k = kinematics(x0, x1, x2, Dm_inv);
  const double tr = k.G.trace();
  return rest_area * (p.mu * k.G.squaredNorm() + 0.5 * p.lambda * tr * tr);
}

Vec9 stretch_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                      double rest_area, const StretchParams& p) {
  const Kinematics k = kinematics(x0, x1, x2, Dm_inv);
  return gradient_with_stress(k, piola2(k.G, p), rest_area);
}

Mat9 stretch_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                     double rest_area, const StretchParams& p) {
  const Kinematics k = kinematics(x0, x1, x2, Dm_inv);
  return hessian_with_stress(k, piola2(k.G, p), rest_area, p);
}

Mat9 stretch_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                         double rest_area, const StretchParams& p) {
  const Kinematics k = kinematics(x0, x1, x2, Dm_inv);
  return hessian_with_stress(k, psd_part(piola2(k.G, p)), rest_area, p);
}

void stretch_gradient_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                  const Mat2& Dm_inv, double rest_area, const StretchParams& p,
                                  Vec9& gradient, Mat9& hessian) {
  const Kinematics k = kinematics(x0, x1, x2, Dm_inv);
  const Mat2 S = piola2(k.G, p);
  gradient = gradient_with_stress(k, S, rest_area);
  hessian = hessian_with_stress(k, psd_part(S), rest_area, p);
}

}  // namespace dexcloth::cloth
