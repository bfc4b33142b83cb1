#include "control/controllers.hpp"

#include <algorithm>

#include "core/assert.hpp"

namespace dexcloth::control {

JointPdController::JointPdController(rigid::SkeletonId skeleton, std::vector<int> dofs,
                                     std::vector<VectorKeyframe> keys, Eigen::VectorXd kp, Eigen::VectorXd kd)
    : m_skeleton(skeleton), m_dofs(std::move(dofs)), m_keys(std::move(keys)), m_kp(std::move(kp)), m_kd(std::move(kd)) {
  const auto n = static_cast<Eigen::Index>(m_dofs.size());
  DEXCLOTH_DEMAND(!m_keys.empty() && m_kp.size() == n && m_kd.size() == n);
  for (const auto& k : m_keys) DEXCLOTH_DEMAND(k.value.size() == n);
}

namespace {
/// PD targets stay this far inside the joint limits [rad or m].
constexpr double kLimitMargin = 2.0e-3;
}  // namespace

void JointPdController::apply(rigid::RigidWorld& world, double t) {
  const Eigen::VectorXd q_target = sample_vector(m_keys, t);
  const Eigen::VectorXd lo = world.position_lower_limits(m_skeleton);
  const Eigen::VectorXd hi = world.position_upper_limits(m_skeleton);
  for (std::size_t i = 0; i < m_dofs.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const int d = m_dofs[i];
    world.set_joint_pd(m_skeleton, d, m_kp[k], m_kd[k], std::clamp(q_target[k], lo[d] + kLimitMargin, hi[d] - kLimitMargin));
  }
}

WristController::WristController(rigid::BodyId body, Vec3 p_B, std::vector<rigid::PoseKeyframe> keys, CartesianGains gains)
    : m_body(body), m_p_B(std::move(p_B)), m_keys(std::move(keys)), m_gains(gains) {
  DEXCLOTH_DEMAND(!m_keys.empty());
}

void WristController::apply(rigid::RigidWorld& world, double t) {
  const rigid::PoseSample target = rigid::sample_pose(m_keys, t);
  // Current frame F: the body's axes at point p_B.
  const Eigen::Isometry3d X_WB = world.pose_W(m_body);
  const Vec3 x_W = X_WB * m_p_B;
  // Damping toward zero velocity is the stable-PD joint damping of the free root's DOFs (stable
  // for any gain); the target-velocity part and the stiffness are explicit forces.
  const rigid::SkeletonId s = world.body_skeleton(m_body);
  if (world.root_body(s) == m_body && world.root_dofs(s) == 6) {
    for (int i = 0; i < 3; ++i) world.set_joint_pd(s, i, 0.0, m_gains.kd_rot, 0.0);
    for (int i = 3; i < 6; ++i) world.set_joint_pd(s, i, 0.0, m_gains.kd, 0.0);
    m_f_W = m_gains.kp * (target.X_WF.translation() - x_W) + m_gains.kd * target.v_W;
  } else {
    m_f_W = m_gains.kp * (target.X_WF.translation() - x_W) + m_gains.kd * (target.v_W - world.point_velocity_W(m_body, m_p_B));
  }
  // Rotational PD on the rotation-vector error.
  const Eigen::AngleAxisd error(target.X_WF.linear() * X_WB.linear().transpose());
  m_t_W = m_gains.kp_rot * error.angle() * error.axis() + m_gains.kd_rot * target.w_W;
  if (!(world.root_body(s) == m_body && world.root_dofs(s) == 6)) m_t_W -= m_gains.kd_rot * world.angular_velocity_W(m_body);
  world.add_wrench_at(m_body, m_p_B, m_f_W, m_t_W);
}

PointForceController::PointForceController(rigid::BodyId body, Vec3 p_B, std::vector<VectorKeyframe> force_keys_W)
    : m_body(body), m_p_B(std::move(p_B)), m_keys(std::move(force_keys_W)) {
  DEXCLOTH_DEMAND(!m_keys.empty());
  for (const auto& k : m_keys) DEXCLOTH_DEMAND(k.value.size() == 3);
}

void PointForceController::apply(rigid::RigidWorld& world, double t) {
  // paper eq. (13): τ = J_pᵀ F.
  const Vec3 f_W = sample_vector(m_keys, t);
  world.add_force_at(m_body, m_p_B, f_W);
}

JointForceController::JointForceController(rigid::SkeletonId skeleton, std::vector<int> dofs,
                                           std::vector<VectorKeyframe> keys, bool hold)
    : m_skeleton(skeleton), m_dofs(std::move(dofs)), m_keys(std::move(keys)), m_hold(hold) {
  DEXCLOTH_DEMAND(!m_keys.empty());
  for (const auto& k : m_keys) DEXCLOTH_DEMAND(k.value.size() == static_cast<Eigen::Index>(m_dofs.size()));
}

void JointForceController::apply(rigid::RigidWorld& world, double t) {
  const Eigen::VectorXd f = m_hold ? sample_vector_hold(m_keys, t) : sample_vector(m_keys, t);
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(world.num_dofs(m_skeleton));
  for (std::size_t i = 0; i < m_dofs.size(); ++i) tau[m_dofs[i]] += f[static_cast<Eigen::Index>(i)];
  world.add_forces(m_skeleton, tau);
}

GravityCompensation::GravityCompensation(rigid::SkeletonId skeleton, bool joints_only)
    : m_skeleton(skeleton), m_joints_only(joints_only) {}

void GravityCompensation::apply(rigid::RigidWorld& world, double) {
  Eigen::VectorXd g = world.gravity_compensation(m_skeleton);
  if (m_joints_only) g.head(world.root_dofs(m_skeleton)).setZero();
  world.add_forces(m_skeleton, g);
}

}  // namespace dexcloth::control
