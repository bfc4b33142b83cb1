#include "cloth/bending.hpp"

#include <cmath>
#include <numbers>

namespace dexcloth::cloth {
namespace {

/// Cross-product matrix: skew(a)·b = a × b.
Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

/// Hinge geometry shared by θ, ∇θ and ∇²θ.
struct Hinge {
  Vec3 e;                 ///< x1 − x0
  Vec3 a2, a3;            ///< x2 − x0, x3 − x0
  Vec3 n1, n2;            ///< area-weighted normals of (x0, x1, x2) and (x1, x0, x3)
  double L2{}, L{};       ///< |e|², |e|
  double n1sq{}, n2sq{};  ///< |n1|², |n2|²
  double t2{}, t3{};      ///< projections of the wings onto the edge, in units of |e|
  bool degenerate{true};  ///< a zero-length edge or a (near-)zero-area triangle
};

Hinge make_hinge(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  Hinge g;
  g.e = x1 - x0;
  g.a2 = x2 - x0;
  g.a3 = x3 - x0;
  g.n1 = g.e.cross(g.a2);
  g.n2 = g.a3.cross(g.e);
  g.L2 = g.e.squaredNorm();
  g.n1sq = g.n1.squaredNorm();
  g.n2sq = g.n2.squaredNorm();
  // Guard: triangle heights below 1e-10 of the edge length (or NaN) have no usable normal.
  const double min_nsq = 1e-20 * g.L2 * g.L2;
  g.degenerate = !(g.L2 > 0.0) || !(g.n1sq > min_nsq) || !(g.n2sq > min_nsq);
  if (g.degenerate) return g;
  g.L = std::sqrt(g.L2);
  g.t2 = g.a2.dot(g.e) / g.L2;
  g.t3 = g.a3.dot(g.e) / g.L2;
  return g;
}

/// θ − θ̄ wrapped into (−π, π].
double angle_difference(double theta, double rest_angle) {
  double d = theta - rest_angle;
  if (d > std::numbers::pi) d -= 2.0 * std::numbers::pi;
  if (d <= -std::numbers::pi) d += 2.0 * std::numbers::pi;
  return d;
}

/// θ = atan2((n2 × n1)·ê, n1·n2); n2 × n1 is parallel to e, its ê component is |n1||n2|·sin θ.
double angle_of(const Hinge& g) {
  return g.degenerate ? 0.0 : std::atan2(g.n2.cross(g.n1).dot(g.e) / g.L, g.n1.dot(g.n2));
}

/// ∇θ (Bridson et al. 2003): wings |e|·n/|n|², edge vertices by the wings' edge projections.
Vec12 angle_gradient(const Hinge& g) {
  Vec12 grad = Vec12::Zero();
  if (g.degenerate) return grad;
  const Vec3 g2 = (g.L / g.n1sq) * g.n1;
  const Vec3 g3 = (g.L / g.n2sq) * g.n2;
  grad.segment<3>(0) = -(1.0 - g.t2) * g2 - (1.0 - g.t3) * g3;
  grad.segment<3>(3) = -g.t2 * g2 - g.t3 * g3;
  grad.segment<3>(6) = g2;
  grad.segment<3>(9) = g3;
  return grad;
}

}  // namespace

double dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  return angle_of(make_hinge(x0, x1, x2, x3));
}

Vec12 dihedral_angle_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  return angle_gradient(make_hinge(x0, x1, x2, x3));
}

Mat12 dihedral_angle_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  const Hinge g = make_hinge(x0, x1, x2, x3);
  Mat12 H = Mat12::Zero();
  if (g.degenerate) return H;
  const Vec3 e_hat = g.e / g.L;
  const Vec3 u1 = g.n1 / g.n1sq, u2 = g.n2 / g.n2sq;
  const Vec3 g2 = g.L * u1, g3 = g.L * u2;

  // Jacobians of the area-weighted normals (3×12): n1 = e × (x2 − x0), n2 = (x3 − x0) × e.
  Eigen::Matrix<double, 3, 12> dn1 = Eigen::Matrix<double, 3, 12>::Zero();
  dn1.block<3, 3>(0, 0) = skew(x2 - x1);
  dn1.block<3, 3>(0, 3) = -skew(g.a2);
  dn1.block<3, 3>(0, 6) = skew(g.e);
  Eigen::Matrix<double, 3, 12> dn2 = Eigen::Matrix<double, 3, 12>::Zero();
  dn2.block<3, 3>(0, 0) = -skew(x3 - x1);
  dn2.block<3, 3>(0, 3) = skew(g.a3);
  dn2.block<3, 3>(0, 9) = -skew(g.e);

  // Jacobian of the edge length (1×12).
  Eigen::Matrix<double, 1, 12> dL = Eigen::Matrix<double, 1, 12>::Zero();
  dL.segment<3>(0) = -e_hat.transpose();
  dL.segment<3>(3) = e_hat.transpose();

  // Jacobians of the wing gradients g = L·n/|n|² (3×12).
  const Mat3 P1 = (Mat3::Identity() - 2.0 * u1 * g.n1.transpose()) / g.n1sq;
  const Mat3 P2 = (Mat3::Identity() - 2.0 * u2 * g.n2.transpose()) / g.n2sq;
  const Eigen::Matrix<double, 3, 12> dg2 = u1 * dL + g.L * P1 * dn1;
  const Eigen::Matrix<double, 3, 12> dg3 = u2 * dL + g.L * P2 * dn2;

  // Jacobians of the edge projections t = (a·e)/|e|² (1×12).
  Eigen::Matrix<double, 1, 12> dt2 = Eigen::Matrix<double, 1, 12>::Zero();
  dt2.segment<3>(3) = (g.a2 - 2.0 * g.t2 * g.e).transpose() / g.L2;
  dt2.segment<3>(6) = g.e.transpose() / g.L2;
  dt2.segment<3>(0) = -dt2.segment<3>(3) - dt2.segment<3>(6);
  Eigen::Matrix<double, 1, 12> dt3 = Eigen::Matrix<double, 1, 12>::Zero();
  dt3.segment<3>(3) = (g.a3 - 2.0 * g.t3 * g.e).transpose() / g.L2;
  dt3.segment<3>(9) = g.e.transpose() / g.L2;
  dt3.segment<3>(0) = -dt3.segment<3>(3) - dt3.segment<3>(9);

  // Differentiate g0 = −(1 − t2)g2 − (1 − t3)g3 and g1 = −t2·g2 − t3·g3 by the product rule.
  H.block<3, 12>(0, 0) = -(1.0 - g.t2) * dg2 + g2 * dt2 - (1.0 - g.t3) * dg3 + g3 * dt3;
  H.block<3, 12>(3, 0) = -g.t2 * dg2 - g2 * dt2 - g.t3 * dg3 - g3 * dt3;
  H.block<3, 12>(6, 0) = dg2;
  H.block<3, 12>(9, 0) = dg3;
  // Symmetric in exact arithmetic; remove the rounding asymmetry.
  return 0.5 * (H + H.transpose());
}

double bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                      double rest_angle, double weight, double k) {
  const double d = angle_difference(dihedral_angle(x0, x1, x2, x3), rest_angle);
  return k * weight * d * d;
}

Vec12 bending_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                       double rest_angle, double weight, double k) {
  const double d = angle_difference(dihedral_angle(x0, x1, x2, x3), rest_angle);
  return (2.0 * k * weight * d) * dihedral_angle_gradient(x0, x1, x2, x3);
}

Mat12 bending_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                      double rest_angle, double weight, double k) {
  const double d = angle_difference(dihedral_angle(x0, x1, x2, x3), rest_angle);
  const Vec12 grad = dihedral_angle_gradient(x0, x1, x2, x3);
  return 2.0 * k * weight * (grad * grad.transpose() + d * dihedral_angle_hessian(x0, x1, x2, x3));
}

Mat12 bending_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                          double /*rest_angle*/, double weight, double k) {
  const Vec12 grad = dihedral_angle_gradient(x0, x1, x2, x3);
  return (2.0 * k * weight) * grad * grad.transpose();
}

void bending_gradient_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                  double rest_angle, double weight, double k, Vec12& gradient,
                                  Mat12& hessian) {
  const Hinge g = make_hinge(x0, x1, x2, x3);
  const Vec12 grad = angle_gradient(g);
  const double theta = angle_of(g);
  const double c = 2.0 * k * weight;
  gradient = (c * angle_difference(theta, rest_angle)) * grad;
  hessian = c * grad * grad.transpose();
}

}  // namespace dexcloth::cloth
