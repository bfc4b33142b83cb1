#include "control/timeline.hpp"

#include <algorithm>

#include "core/assert.hpp"
#include "rigid/keyframes.hpp"

namespace dexcloth::control {
namespace {

/// Index k of the segment [k, k+1] holding t, or −1 before / size−1 after the keyed interval.
std::ptrdiff_t segment(const std::vector<VectorKeyframe>& keys, double t) {
  const auto it = std::upper_bound(keys.begin(), keys.end(), t,
                                   [](double time, const VectorKeyframe& k) { return time < k.t; });
  return (it - keys.begin()) - 1;
}

}  // namespace

Eigen::VectorXd sample_vector(const std::vector<VectorKeyframe>& keys, double t) {
  DEXCLOTH_DEMAND(!keys.empty());
  const auto k = segment(keys, t);
  if (k < 0) return keys.front().value;
  if (k + 1 >= static_cast<std::ptrdiff_t>(keys.size())) return keys.back().value;
  const auto& a = keys[static_cast<std::size_t>(k)];
  const auto& b = keys[static_cast<std::size_t>(k) + 1];
  const double s = rigid::smoothstep(a.t, b.t, t).first;
  return a.value + s * (b.value - a.value);
}

Eigen::VectorXd sample_vector_rate(const std::vector<VectorKeyframe>& keys, double t) {
  DEXCLOTH_DEMAND(!keys.empty());
  const auto k = segment(keys, t);
  if (k < 0 || k + 1 >= static_cast<std::ptrdiff_t>(keys.size())) return Eigen::VectorXd::Zero(keys.front().value.size());
  const auto& a = keys[static_cast<std::size_t>(k)];
  const auto& b = keys[static_cast<std::size_t>(k) + 1];
  return rigid::smoothstep(a.t, b.t, t).second * (b.value - a.value);
}

Eigen::VectorXd sample_vector_hold(const std::vector<VectorKeyframe>& keys, double t) {
  DEXCLOTH_DEMAND(!keys.empty());
  const auto k = segment(keys, t);
  return keys[static_cast<std::size_t>(std::max<std::ptrdiff_t>(k, 0))].value;
}

}  // namespace dexcloth::control
