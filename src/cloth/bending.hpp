#pragma once
/// Dihedral bending (Bridson et al. 2003; Grinspun et al. 2003, discrete shells) on one hinge.
///
/// A hinge is four vertices: x0, x1 the shared edge, x2 the wing of triangle (x0, x1, x2) and x3
/// the wing of triangle (x1, x0, x3). With n1 = (x1 − x0)×(x2 − x0), n2 = (x0 − x1)×(x3 − x1)
/// (equal directions when flat) and ê = (x1 − x0)/|x1 − x0|, the signed dihedral angle is
///   θ = atan2((n2 × n1)·ê, n1·n2) ∈ (−π, π],
/// 0 when flat and positive when the wings bend towards the side n1 points to. The energy is
///   E = k·(θ − θ̄)²·w,   w = |ē|² / (Ā1 + Ā2),   k = D/2,
/// with D = Material::bending_stiffness [N·m], |ē| the rest edge length, Ā1, Ā2 the rest
/// triangle areas and θ − θ̄ wrapped into (−π, π]. k = D/2 makes a grid of right triangles bent
/// into a cylinder of radius R (axis along a grid line) store the plate energy ½·D·A/R²;
/// it is the discrete-shells energy 3|ē|²/(Ā1 + Ā2) with constant D/6.
/// Vectors of 12 are (x0, x1, x2, x3) stacked; 12×12 matrices use the same ordering.
#include "core/types.hpp"

namespace dexcloth::cloth {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// Hinge energy constant k [N·m] from the plate bending stiffness D [N·m]: k = D/2.
inline double bending_constant(double bending_stiffness) { return 0.5 * bending_stiffness; }

/// Signed dihedral angle θ [rad] in (−π, π] of hinge (x0, x1, x2, x3); 0 for a degenerate hinge.
double dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Gradient ∂θ/∂(x0, x1, x2, x3) [1/m] (12); zero for a degenerate hinge.
Vec12 dihedral_angle_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Exact Hessian ∂²θ/∂x² [1/m²] (12×12, symmetric); zero for a degenerate hinge.
Mat12 dihedral_angle_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Bending energy [J] k·(θ − θ̄)²·w of a hinge with rest angle `rest_angle` [rad], rest weight
/// `weight` = |ē|²/(Ā1 + Ā2) [-] and constant `k` [N·m].
double bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                      double rest_angle, double weight, double k);

/// Gradient [N] (12): 2k·w·(θ − θ̄)·∇θ.
Vec12 bending_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                       double rest_angle, double weight, double k);

/// Exact Hessian [N/m] (12×12): 2k·w·(∇θ∇θᵀ + (θ − θ̄)·∇²θ).
Mat12 bending_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                      double rest_angle, double weight, double k);

/// Gauss–Newton Hessian [N/m] (12×12) for the implicit solver: 2k·w·∇θ∇θᵀ (PSD, rank ≤ 1,
/// annihilates rigid motions).
Mat12 bending_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                          double rest_angle, double weight, double k);

/// Gradient (12) [N] and Gauss–Newton Hessian (12×12) [N/m] in one pass (solver assembly).
void bending_gradient_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                  double rest_angle, double weight, double k, Vec12& gradient,
                                  Mat12& hessian);

}  // namespace dexcloth::cloth
