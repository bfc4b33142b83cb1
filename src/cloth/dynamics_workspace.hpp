#pragma once
/// Internal to the dynamics: the buffers of the implicit step, allocated on the first step.
#include <span>
#include <vector>

#include "cloth/block_pcg.hpp"
#include "cloth/dynamics.hpp"
#include "cloth/sparse_ldlt.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// Buffers of solve_velocities (see dynamics.cpp). Sized for one model on the first step.
struct DynamicsWorkspace {
  int num_vertices{-1};           ///< |V| the buffers are sized for; −1 before the first step
  std::vector<Mat3> blocks;       ///< values of the system matrix, one per pattern block
  Eigen::VectorXd rhs;            ///< 3|V| right-hand side
  Eigen::VectorXd dv;             ///< 3|V| velocity change (PCG warm start)
  Eigen::VectorXd work;           ///< 3|V| scratch (residual, permuted vectors)
  std::vector<char> constrained;  ///< |V| flags of velocity-constrained vertices
  std::vector<Mat3> saved_rows;   ///< constrained rows' blocks A(i, j) before elimination
  std::vector<Vec3> saved_rhs;    ///< constrained rows' right-hand sides before elimination
  // Friction rounds: the assembled system before elimination, and the round's constraints.
  std::vector<Mat3> base_blocks;
  Eigen::VectorXd base_rhs;
  std::vector<VelocityConstraint> all_constraints;
  std::vector<VelocityConstraint> solve_constraints;  ///< a friction solve's, squeezed normals too
  std::vector<Vec3> last_slip;  ///< each friction vertex's slip at the last Newton iterate
  std::vector<char> held;  ///< |V| flags of vertices held by the caller's velocity constraints
  Eigen::VectorXd dv_iterate;  ///< friction Newton: current iterate
  Eigen::VectorXd dv_step;     ///< friction Newton: step to the next iterate
  // Direct solver: the system's upper triangle in fill-reducing order.
  bool ldlt_ready{false};
  std::vector<int> ldlt_col_start;  ///< 3|V|+1
  std::vector<int> ldlt_row;        ///< permuted row of each stored entry
  std::vector<int> ldlt_source;     ///< offset of each stored entry in `blocks` (as doubles)
  std::vector<int> ldlt_dof;        ///< permuted unknown k is original unknown ldlt_dof[k]
  std::vector<double> ldlt_values;  ///< gathered values
  SparseLdlt ldlt;
  // Iterative solver.
  bool pcg_ready{false};
  BlockPcg pcg;
};

/// First half of solve_velocities: sizes `ws` for `model` (first step only) and assembles the
/// implicit step's system A·Δv = b into ws.blocks and ws.rhs, with the constrained unknowns
/// eliminated. Exposed so that benchmarks can time assembly and solve separately.
void assemble_system(const ClothModel& model, const ClothState& state, double h,
                     const Vec3& gravity, std::span<const VelocityConstraint> constraints,
                     DynamicsWorkspace& ws);

/// Second half of solve_velocities: solves the assembled system into ws.dv (PCG warm-started
/// from the Δv already in ws.dv, or LDLT, per model.solver), PCG to the larger of the model's
/// tolerance and `tolerance`. On failure ws.dv is zeroed.
DynamicsReport solve_system(const ClothModel& model,
                            std::span<const VelocityConstraint> constraints,
                            DynamicsWorkspace& ws, double tolerance = 0.0);

}  // namespace dexcloth::cloth
