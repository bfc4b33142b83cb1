#pragma once
/// Keyframed vectors (joint targets, forces) over time, smoothstep-interpolated.
#include <vector>

#include "core/types.hpp"

namespace dexcloth::control {

/// At time `t` [s] the value is `value` (units of whatever it drives).
struct VectorKeyframe {
  double t{};
  Eigen::VectorXd value;
};

/// Value of `keys` (strictly increasing t, equal sizes, at least one) at `t`: smoothstep
/// (C¹, zero slope at keys) between neighbours, held outside the keyed interval.
Eigen::VectorXd sample_vector(const std::vector<VectorKeyframe>& keys, double t);

/// Time derivative of sample_vector at `t`.
Eigen::VectorXd sample_vector_rate(const std::vector<VectorKeyframe>& keys, double t);

/// Step (hold) interpolation: the value of the last key with key.t ≤ t (the first before it).
Eigen::VectorXd sample_vector_hold(const std::vector<VectorKeyframe>& keys, double t);

}  // namespace dexcloth::control
