#pragma once
/// Membrane stretching: St. Venant–Kirchhoff energy of the Green strain of one triangle.
///
/// With Ds = [x1 − x0, x2 − x0] (3×2) and the rest-shape inverse Dm⁻¹ (2×2), the deformation
/// gradient is F = Ds·Dm⁻¹ (3×2), the Green strain G = ½(FᵀF − I) and the energy
///   E = A·Ψ,  Ψ = μ‖G‖²_F + ½λ·tr(G)²,
/// with A the rest area and μ, λ the plane-stress 2-D Lamé parameters times thickness [N/m].
/// Vectors of 9 are (x0, x1, x2) stacked; 9×9 matrices use the same ordering.
#include "cloth/material.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// Plane-stress membrane Lamé parameters times thickness.
struct StretchParams {
  double mu{};      ///< μ = E·t / (2(1 + ν)) [N/m]
  double lambda{};  ///< λ = E·t·ν / (1 − ν²) [N/m]
};

/// Membrane parameters of `m` (with ν = 0 a uniaxial stress is S11 = E·t·G11).
StretchParams stretch_params(const Material& m);

/// Stretching energy [J] of triangle (x0, x1, x2) [m] with rest-shape inverse `Dm_inv` [1/m]
/// and rest area `rest_area` [m²].
double stretch_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                      double rest_area, const StretchParams& p);

/// Gradient ∂E/∂(x0, x1, x2) [N] (9).
Vec9 stretch_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                      double rest_area, const StretchParams& p);

/// Exact Hessian ∂²E/∂x² [N/m] (9×9, symmetric, indefinite in compression).
Mat9 stretch_hessian(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                     double rest_area, const StretchParams& p);

/// Positive semi-definite approximation of the Hessian [N/m] (9×9) for the implicit solver:
/// the exact material term plus the geometric term with the second Piola stress S clamped to
/// its positive semi-definite part. Rigid translations stay in its null space.
Mat9 stretch_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Mat2& Dm_inv,
                         double rest_area, const StretchParams& p);

/// Gradient (9) [N] and PSD Hessian (9×9) [N/m] in one pass, as used by the solver's assembly.
void stretch_gradient_hessian_psd(const Vec3& x0, const Vec3& x1, const Vec3& x2,
                                  const Mat2& Dm_inv, double rest_area, const StretchParams& p,
                                  Vec9& gradient, Mat9& hessian);

}  // namespace dexcloth::cloth
