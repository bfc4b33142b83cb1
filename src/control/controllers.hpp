#pragma once
/// Hand controllers (paper §6): each adds generalized forces (or sets joint PD gains) on a
/// RigidWorld before its step, as a function of time. Compose them in a ControllerSet.
#include <memory>
#include <vector>

#include "control/timeline.hpp"
#include "rigid/keyframes.hpp"
#include "rigid/world.hpp"

namespace dexcloth::control {

/// One controller: acts on the world for the step that starts at time t [s].
class Controller {
 public:
  virtual ~Controller() = default;
  virtual void apply(rigid::RigidWorld& world, double t) = 0;
};

/// Joint PD tracking of keyframed joint targets (paper §6, "PD actuators at joints"):
/// τ_i = −kp_i (q_i − q*_i(t)) − kd_i q̇_i through RigidWorld::set_joint_pd (a stable PD the
/// contact and limit solver sees). Targets are clamped 2 mrad inside the joint limits, so the PD
/// never presses a joint into its limit; the limits themselves are hard constraints, and a
/// joint held at a limit by other torques leaves its neighbours on their targets.
class JointPdController final : public Controller {
 public:
  /// `dofs`: indices in the skeleton's generalized vector; every key's value has dofs.size()
  /// entries [rad or m]; kp, kd per DOF [N·m/rad, N·m·s/rad] (or N/m, N·s/m).
  JointPdController(rigid::SkeletonId skeleton, std::vector<int> dofs, std::vector<VectorKeyframe> keys,
                    Eigen::VectorXd kp, Eigen::VectorXd kd);
  void apply(rigid::RigidWorld& world, double t) override;
  /// Target at time t.
  Eigen::VectorXd target(double t) const { return sample_vector(m_keys, t); }
  const std::vector<int>& dofs() const { return m_dofs; }

 private:
  rigid::SkeletonId m_skeleton;
  std::vector<int> m_dofs;
  std::vector<VectorKeyframe> m_keys;
  Eigen::VectorXd m_kp, m_kd;
};

/// Gains of a Cartesian PD on a body frame.
struct CartesianGains {
  double kp{2000.0};     ///< translational stiffness [N/m]
  double kd{60.0};       ///< translational damping [N·s/m]
  double kp_rot{10.0};   ///< rotational stiffness [N·m/rad]
  double kd_rot{0.3};    ///< rotational damping [N·m·s/rad]
};

/// Wrist control (paper §7: "external forces and torques were applied at the wrist"): a
/// Cartesian PD pulls frame F (point p_B of `body`, axes of the body) toward keyframed world
/// poses; the resulting wrench f_W, t_W acts on the body at p_B (τ += Jᵀ [t_W; f_W]).
/// When the body is a free root, the damping toward zero velocity is joint damping on the root
/// DOFs through RigidWorld::set_joint_pd (stable PD, acting at the root origin; stable at any
/// gain), and only the stiffness and target-velocity terms are explicit forces.
class WristController final : public Controller {
 public:
  WristController(rigid::BodyId body, Vec3 p_B, std::vector<rigid::PoseKeyframe> keys, CartesianGains gains);
  void apply(rigid::RigidWorld& world, double t) override;
  /// Last applied force and torque in world [N], [N·m].
  const Vec3& last_force_W() const { return m_f_W; }
  const Vec3& last_torque_W() const { return m_t_W; }

 private:
  rigid::BodyId m_body;
  Vec3 m_p_B;
  std::vector<rigid::PoseKeyframe> m_keys;
  CartesianGains m_gains;
  Vec3 m_f_W{Vec3::Zero()};
  Vec3 m_t_W{Vec3::Zero()};
};

/// Jacobian-transpose force control (paper eq. 13): τ = J_pᵀ F with F keyframed in world [N].
class PointForceController final : public Controller {
 public:
  PointForceController(rigid::BodyId body, Vec3 p_B, std::vector<VectorKeyframe> force_keys_W);
  void apply(rigid::RigidWorld& world, double t) override;

 private:
  rigid::BodyId m_body;
  Vec3 m_p_B;
  std::vector<VectorKeyframe> m_keys;
};

/// Generalized forces on chosen DOFs from a timeline (e.g. a gripper squeeze) [N·m or N].
/// `hold`: values step at keys (true) or are smoothstep-interpolated (false).
class JointForceController final : public Controller {
 public:
  JointForceController(rigid::SkeletonId skeleton, std::vector<int> dofs, std::vector<VectorKeyframe> keys, bool hold);
  void apply(rigid::RigidWorld& world, double t) override;

 private:
  rigid::SkeletonId m_skeleton;
  std::vector<int> m_dofs;
  std::vector<VectorKeyframe> m_keys;
  bool m_hold;
};

/// Gravity compensation τ = g(q) (DART's generalized gravity forces). `joints_only` leaves the
/// root DOFs alone (the hand's weight is then carried by the wrist controller); otherwise the
/// root DOFs also receive the wrench that carries the whole skeleton's weight.
class GravityCompensation final : public Controller {
 public:
  GravityCompensation(rigid::SkeletonId skeleton, bool joints_only);
  void apply(rigid::RigidWorld& world, double t) override;

 private:
  rigid::SkeletonId m_skeleton;
  bool m_joints_only;
};

/// Controllers applied in insertion order.
class ControllerSet {
 public:
  void add(std::unique_ptr<Controller> controller) { m_controllers.push_back(std::move(controller)); }
  void apply(rigid::RigidWorld& world, double t) {
    for (auto& c : m_controllers) c->apply(world, t);
  }
  std::size_t size() const { return m_controllers.size(); }
  Controller& operator[](std::size_t i) { return *m_controllers[i]; }

 private:
  std::vector<std::unique_ptr<Controller>> m_controllers;
};

}  // namespace dexcloth::control
