#include "rigid/keyframes.hpp"

#include <algorithm>

#include "core/assert.hpp"

namespace dexcloth::rigid {

std::pair<double, double> smoothstep(double t0, double t1, double t) {
  DEXCLOTH_DEMAND(t1 > t0);
  const double u = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  const double s = u * u * (3.0 - 2.0 * u);
  const double ds_dt = (t <= t0 || t >= t1) ? 0.0 : 6.0 * u * (1.0 - u) / (t1 - t0);
  return {s, ds_dt};
}

PoseSample sample_pose(const std::vector<PoseKeyframe>& keys, double t) {
  DEXCLOTH_DEMAND(!keys.empty());
  PoseSample out;
  // Hold the end poses outside the keyed interval.
  if (t <= keys.front().t) {
    out.X_WF = keys.front().X_WF;
    return out;
  }
  if (t >= keys.back().t) {
    out.X_WF = keys.back().X_WF;
    return out;
  }
  // Segment [k, k+1] containing t.
  const auto it = std::upper_bound(keys.begin(), keys.end(), t,
                                   [](double time, const PoseKeyframe& k) { return time < k.t; });
  const PoseKeyframe& b = *it;
  const PoseKeyframe& a = *(it - 1);
  const auto [s, ds_dt] = smoothstep(a.t, b.t, t);
  // Translation: straight line; rotation: slerp, angular velocity along the relative axis.
  const Vec3 pa = a.X_WF.translation();
  const Vec3 pb = b.X_WF.translation();
  const Eigen::Quaterniond qa(a.X_WF.linear());
  const Eigen::Quaterniond qb(b.X_WF.linear());
  out.X_WF.linear() = qa.slerp(s, qb).toRotationMatrix();
  out.X_WF.translation() = pa + s * (pb - pa);
  out.v_W = ds_dt * (pb - pa);
  const Eigen::AngleAxisd rel(qb * qa.conjugate());
  out.w_W = ds_dt * rel.angle() * rel.axis();
  return out;
}

}  // namespace dexcloth::rigid
