#include "core/keyframes.hpp"

#include <algorithm>

#include "core/transform.hpp"

namespace dexcloth {

KeyTrack::KeyTrack(std::vector<Key> keys) : m_keys(std::move(keys)) {
  m_rotations.reserve(m_keys.size());
  for (const Key& k : m_keys) m_rotations.emplace_back(rotation_xyz_deg(k.rotation_deg));
}

void KeyTrack::locate(double t, std::size_t& k, double& s) const {
  const auto it = std::upper_bound(m_keys.begin(), m_keys.end(), t,
                                   [](double v, const Key& key) { return v < key.t; });
  if (it == m_keys.begin()) {
    k = 0;
    s = 0.0;
  } else if (it == m_keys.end()) {
    k = m_keys.size() - 1;
    s = 0.0;
  } else {
    k = static_cast<std::size_t>(it - m_keys.begin()) - 1;
    s = (t - m_keys[k].t) / (m_keys[k + 1].t - m_keys[k].t);
  }
}

Vec3 KeyTrack::translation(double t) const {
  if (m_keys.empty()) return Vec3::Zero();
  std::size_t k = 0;
  double s = 0.0;
  locate(t, k, s);
  if (s == 0.0) return m_keys[k].translation;
  // Catmull–Rom tangents (per unit time), zero at the ends.
  const auto tangent = [&](std::size_t i) -> Vec3 {
    if (i == 0 || i + 1 >= m_keys.size()) return Vec3::Zero();
    return (m_keys[i + 1].translation - m_keys[i - 1].translation) /
           (m_keys[i + 1].t - m_keys[i - 1].t);
  };
  const double dt = m_keys[k + 1].t - m_keys[k].t;
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * m_keys[k].translation + h10 * dt * tangent(k) + h01 * m_keys[k + 1].translation +
         h11 * dt * tangent(k + 1);
}

Eigen::Quaterniond KeyTrack::rotation(double t) const {
  if (m_keys.empty()) return Eigen::Quaterniond::Identity();
  std::size_t k = 0;
  double s = 0.0;
  locate(t, k, s);
  if (s == 0.0) return m_rotations[k];
  const double smooth = s * s * (3.0 - 2.0 * s);
  return m_rotations[k].slerp(smooth, m_rotations[k + 1]);
}

Eigen::Isometry3d KeyTrack::pose(double t) const {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rotation(t).toRotationMatrix();
  X.translation() = translation(t);
  return X;
}

}  // namespace dexcloth
