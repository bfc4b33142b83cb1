#pragma once
/// Strain limiting on positions (Provot 1995; Wang et al. 2010, as in ARCSim): every triangle's
/// principal stretches are clamped into [min_stretch, max_stretch] by moving its vertices.
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace dexcloth::collision {

/// Bounds and budget of strain limiting.
struct StrainLimitOptions {
  double min_stretch{0.9};  ///< smallest allowed singular value of the deformation gradient [-]
  double max_stretch{1.1};  ///< largest allowed singular value [-]
  double tolerance{1e-3};   ///< converged when every singular value is within the bounds ± this
  int max_iterations{1000};  ///< Gauss–Seidel sweeps over the triangles
  double relaxation{1.5};   ///< over-relaxation ω ∈ [1, 2) of each triangle's correction,
                            ///< reduced per triangle so it never overshoots past the other bound
};

/// What `limit_strain` did.
struct StrainLimitReport {
  int iterations{};     ///< sweeps run
  bool converged{};     ///< every singular value within the bounds ± tolerance
  double violation{};   ///< largest remaining distance of a singular value outside the bounds [-]
};

/// Moves `x` (|V|×3 [m]) so that every face of `faces` (|F|×3) has the singular values of its
/// deformation gradient F = [x1 − x0, x2 − x0]·Dm⁻¹ within the bounds; `dm_inv` (|F|) holds the
/// inverse 2×2 rest-shape matrices (material space [m] → [1/m]). Each triangle in turn (Gauss–
/// Seidel, ordered outward from the frozen vertices) moves ω of the way to its clamped shape U·clamp(Σ)·Vᵀ·Dm placed to keep its
/// mass-weighted centre (`mass`, |V| [kg]); stretches are clamped a quarter tolerance inside the
/// bounds so the sweeps end in finitely many steps; vertices with `frozen` = 1 (|V|, or empty for none) never move and
/// anchor their triangles. Sweeps until converged or `max_iterations`.
StrainLimitReport limit_strain(Points& x, const Triangles& faces, const std::vector<Mat2>& dm_inv,
                               const Eigen::VectorXd& mass, const std::vector<std::uint8_t>& frozen,
                               const StrainLimitOptions& options);

}  // namespace dexcloth::collision
