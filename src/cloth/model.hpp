#pragma once
/// The immutable cloth model: topology, rest shape, masses, material and the fixed system
/// sparsity (STYLE.md, model/data split). Built once from a rest mesh; stepping never changes it.
#include <array>
#include <vector>

#include "cloth/material.hpp"
#include "cloth/mesh.hpp"
#include "cloth/sparse_cholesky.hpp"
#include "cloth/stretching.hpp"
#include "cloth/system_pattern.hpp"
#include "cloth/topology.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// Linear solver of the implicit step.
enum class LinearSolver {
  /// Block-Jacobi preconditioned conjugate gradient, warm-started from the last step's Δv; falls
  /// back to cholesky for a step where it does not converge. Slower on stiff cloth: a 65×65
  /// sheet of the default material took 257 iterations, 85 ms per step, against 54 ms direct.
  pcg,
  /// Sparse multifrontal Cholesky (AMD vertex order, pattern analysed once): exact to rounding.
  /// The default: faster than pcg at 2k, 8k and 32k triangles (7.9 vs 11.5, 54 vs 85, 376 vs
  /// 1122 ms per step on the default material).
  cholesky,
};

/// Settings of the implicit step's linear solve.
struct SolverSettings {
  LinearSolver linear_solver{LinearSolver::cholesky};
  /// Relative residual ‖AΔv − b‖/‖b‖ accepted by pcg [-]. 1e-5 by measurement: against exact
  /// solves, 50 steps of a falling 11×11 sheet deviate by 8e-5 of the displacement at 1e-5
  /// (1e-5 at 1e-6, 6e-3 at 1e-4), a hanging strip's sag agrees to 7 digits and damped energy
  /// still decays monotonically, for 27–41 % fewer PCG iterations than 1e-8. Tests that check
  /// conservation to rounding set their own tolerance (or use cholesky).
  double tolerance{1e-5};
  int max_iterations{2000};  ///< PCG iteration cap
  /// Threads of the linear solve: the Cholesky factorisation's independent subtrees, the PCG
  /// vector work on large systems (≥ 512 vertices, OpenMP); the result is bitwise the same for
  /// any value. 1 by default: on a machine shared with other jobs, the PCG's per-iteration
  /// fork/join of several threads was measured 5–20× slower than one thread.
  int threads{1};
  /// Precision of the cholesky factor. single_precision factorises in float (about a third
  /// faster at 8k triangles) and refines every solve in double, a substitution pair and a
  /// product a round, until the relative residual is below refine_tolerance: the answers agree
  /// with the double factor's to that residual, not bitwise.
  Precision factor_precision{Precision::double_precision};
  /// See factor_precision. At most `tolerance` (a solve left above it is rejected); at 1e-5, the
  /// residual pcg is accepted at, most solves of an 8k-triangle cloth need no refinement round.
  double refine_tolerance{1e-10};
  int max_refinements{8};          ///< most refinement rounds of one solve
};

/// Immutable cloth model.
struct ClothModel {
  Triangles faces;                ///< |F|×3 vertex indices
  std::vector<Mat2> Dm_inv;       ///< |F| rest-shape inverses Dm⁻¹ [1/m] (see stretching.hpp)
  std::vector<double> rest_area;  ///< |F| rest areas [m²]
  std::vector<Hinge> hinges;      ///< interior edges with rest angle and weight
  std::vector<std::array<int, 2>> edges;  ///< unique undirected edges (i < j)
  Eigen::VectorXd mass;   ///< |V| lumped vertex masses [kg] (density·area/3 per corner)
  Material material;      ///< the material the model was built with
  StretchParams stretch;  ///< membrane Lamé parameters [N/m]
  double bending_k{};     ///< hinge energy constant k = D/2 [N·m] (see bending.hpp)
  SystemPattern pattern;  ///< fixed block sparsity of the 3|V|×3|V| system
  SolverSettings solver;  ///< linear solver of the implicit step

  /// |V|
  int num_vertices() const { return static_cast<int>(mass.size()); }
};

/// Builds the model of `rest` (positions = rest positions; face_uv, when present, = rest shape,
/// and then every hinge's rest angle is 0) with material `material`.
/// Throws InputRejected listing every degenerate rest triangle (zero or near-zero area, or a
/// repeated vertex) and every vertex that belongs to no face. Inconsistent inputs (index out of
/// range, face_uv rows ≠ |F|, material out of range) are programmer errors (DEXCLOTH_DEMAND).
ClothModel build_model(const ClothMesh& rest, const Material& material);

}  // namespace dexcloth::cloth
