#pragma once
/// RigidWorld: the rigid side of dexcloth, a DART 6.12 world stepped with the Bullet collision
/// detector and DART's LCP contact solver. This header exposes no DART types (pimpl); only
/// src/rigid/*.cpp include DART.
///
/// Frames and names: X_AB is the pose of frame B in frame A (W = world, B = body frame as
/// defined by the URDF link, P = patch). Vectors carry their expressed-in frame as suffix:
/// f_W force in world, p_B point in body B's frame. Generalized vectors of a skeleton follow
/// DART's DOF order (a floating root first: 3 rotation then 3 translation DOFs).
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/types.hpp"
#include "rigid/contacts.hpp"
#include "rigid/keyframes.hpp"
#include "rigid/obstacle_mesh.hpp"
#include "rigid/patch_pool.hpp"

namespace dexcloth::rigid {

/// 6-vector [angular; linear] in world coordinates (DART's spatial order).
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// How a URDF skeleton is placed and treated.
struct UrdfOptions {
  Eigen::Isometry3d X_WR{Eigen::Isometry3d::Identity()};  ///< root link pose in world
  bool fixed_root{false};             ///< weld the root link to the world (else 6-DOF free root)
  bool cylinders_as_capsules{true};   ///< collision <cylinder r, l> becomes a capsule (r, l)
  bool enforce_joint_limits{true};    ///< position limits as hard constraints (DART)
  bool self_collision{false};         ///< collide non-adjacent links of this skeleton
  double friction{1.0};               ///< Coulomb μ of every collision shape [-]
};

/// A prop: a single-body skeleton with one collision shape. Static (mass = 0, no motion),
/// kinematic (mass = 0, keyframed `motion`), or dynamic (mass > 0, free body).
struct PropSpec {
  enum class Shape { box, sphere, capsule, cylinder, plane, mesh };
  std::string name;                   ///< skeleton name; its body node is "<name>/body"
  Shape shape{Shape::box};
  Vec3 size{Vec3::Ones()};            ///< box full extents [m]; plane: x, y extents used
  double radius{};                    ///< sphere, capsule, cylinder radius [m]
  double length{};                    ///< capsule/cylinder length along local z [m]
  std::string mesh_path;              ///< OBJ (or any Assimp format) file (mesh)
  Vec3 mesh_scale{Vec3::Ones()};      ///< per-axis scale of the mesh
  Eigen::Isometry3d X_WP{Eigen::Isometry3d::Identity()};  ///< pose (plane: top face at z = 0 of P)
  std::vector<PoseKeyframe> motion;   ///< kinematic keyframes (X_WF of the prop frame), optional
  double mass{0.0};                   ///< > 0 makes a dynamic free body [kg]
  double friction{1.0};               ///< Coulomb μ [-]
};

/// World settings.
struct RigidWorldOptions {
  double time_step{0.005};                   ///< h [s]
  Vec3 gravity_W{0.0, 0.0, -9.81};           ///< [m/s²]
  int max_contacts{4000};                    ///< detector cap (DART silently truncates past it)
  int patch_capacity{64};                    ///< rigid cloth patches in the pool
  int substeps{1};                           ///< DART steps per step (contacts found at each)
};

namespace detail {
struct WorldImpl;
}

/// The rigid world. Not copyable; movable.
class RigidWorld {
 public:
  explicit RigidWorld(const RigidWorldOptions& options = {});
  ~RigidWorld();
  RigidWorld(RigidWorld&&) noexcept;
  RigidWorld& operator=(RigidWorld&&) noexcept;
  RigidWorld(const RigidWorld&) = delete;
  RigidWorld& operator=(const RigidWorld&) = delete;

  // ---- building ------------------------------------------------------------------------------
  /// Loads `urdf_path` as skeleton `name` (unique). Throws InputRejected naming the file on a
  /// missing or malformed file or a duplicate name.
  SkeletonId add_urdf(const std::string& name, const std::string& urdf_path,
                      const UrdfOptions& options = {});
  /// Adds a prop (see PropSpec). Throws InputRejected on bad sizes or an unreadable mesh.
  SkeletonId add_prop(const PropSpec& prop);

  // ---- time ----------------------------------------------------------------------------------
  /// Advances one step of h: generalized forces added since the last step act during it, then
  /// are cleared; contacts are collected afterwards; keyframed props move to their pose at the
  /// new time.
  void step();
  double time() const;        ///< simulated time [s]
  double time_step() const;   ///< h [s]
  /// Depth a body may rest inside another before the contact pushes it out [m].
  double contact_allowance() const;
  /// DART steps per step; contacts are found at the start of each.
  int substeps() const;
  long step_count() const;

  // ---- lookup (throw InputRejected naming the skeleton's file when not found) ----------------
  int num_skeletons() const;
  SkeletonId skeleton(std::string_view name) const;
  std::optional<SkeletonId> find_skeleton(std::string_view name) const;
  const std::string& skeleton_name(SkeletonId s) const;
  /// Source file of a URDF skeleton ("" for props and patches).
  const std::string& skeleton_file(SkeletonId s) const;
  /// Body node by "skeleton/body_node" path.
  BodyId body(std::string_view path) const;
  std::optional<BodyId> find_body(std::string_view path) const;
  BodyId body(SkeletonId s, std::string_view body_node) const;
  int num_bodies() const;
  /// "skeleton/body_node".
  const std::string& body_name(BodyId b) const;
  SkeletonId body_skeleton(BodyId b) const;
  /// Body nodes of a skeleton, in DART order (root first).
  std::vector<BodyId> skeleton_bodies(SkeletonId s) const;
  /// The root body of a skeleton.
  BodyId root_body(SkeletonId s) const;

  // ---- generalized coordinates ---------------------------------------------------------------
  int num_dofs(SkeletonId s) const;
  /// Index of DOF `k` of joint `joint` in the skeleton's generalized vectors.
  int dof_index(SkeletonId s, std::string_view joint, int k = 0) const;
  std::optional<int> find_dof(SkeletonId s, std::string_view joint, int k = 0) const;
  /// Name of DOF i (DART: "<joint>" for 1-DOF joints, "<joint>_<axis>" otherwise).
  std::string dof_name(SkeletonId s, int i) const;
  /// Joint name owning DOF i.
  std::string dof_joint(SkeletonId s, int i) const;
  /// Number of DOFs of the root joint (6 free, 0 welded).
  int root_dofs(SkeletonId s) const;
  Eigen::VectorXd positions(SkeletonId s) const;    ///< q [rad or m]
  Eigen::VectorXd velocities(SkeletonId s) const;   ///< q̇
  void set_positions(SkeletonId s, const Eigen::VectorXd& q);
  void set_velocities(SkeletonId s, const Eigen::VectorXd& qd);
  Eigen::VectorXd position_lower_limits(SkeletonId s) const;
  Eigen::VectorXd position_upper_limits(SkeletonId s) const;
  /// Adds generalized forces τ for the next step (accumulates; cleared by step()).
  void add_forces(SkeletonId s, const Eigen::VectorXd& tau);
  /// Generalized forces accumulated for the next step.
  Eigen::VectorXd forces(SkeletonId s) const;
  /// Joint PD τ_i = −kp (q_i − q_target) − kd q̇_i, realised as a stable PD (Tan et al. 2011)
  /// with the skeleton's full dynamics (its mass matrix, implicitly through DART's
  /// articulated-body pass): stable for stiff gains on light links at any h, and an
  /// explicit torque the contact/limit LCP sees, so at rest contact and limit forces balance
  /// exactly kp (q_i − q_target). Persists until changed. A URDF joint's <dynamics damping> is
  /// its initial kd. kp [N·m/rad or N/m], kd [N·m·s/rad or N·s/m].
  void set_joint_pd(SkeletonId s, int dof, double kp, double kd, double q_target);
  /// g(q): generalized gravity forces; adding them as forces cancels gravity on the skeleton.
  Eigen::VectorXd gravity_compensation(SkeletonId s) const;
  /// Total mass of the skeleton [kg].
  double mass(SkeletonId s) const;

  // ---- bodies --------------------------------------------------------------------------------
  Eigen::Isometry3d pose_W(BodyId b) const;                   ///< X_WB
  Vec3 point_W(BodyId b, const Vec3& p_B) const;              ///< X_WB · p_B [m]
  Vec3 point_velocity_W(BodyId b, const Vec3& p_B) const;     ///< [m/s]
  Vec3 angular_velocity_W(BodyId b) const;                    ///< [rad/s]
  Vec3 com_W(BodyId b) const;                                 ///< body centre of mass [m]
  double body_mass(BodyId b) const;                           ///< [kg]
  /// Translational point Jacobian, 3×num_dofs: v_W(p) = J q̇. For τ = Jᵀ f_W.
  Eigen::MatrixXd point_jacobian_W(BodyId b, const Vec3& p_B) const;
  /// Spatial Jacobian at a point, 6×num_dofs, rows [ω_W; v_W(p)].
  Eigen::MatrixXd jacobian_W(BodyId b, const Vec3& p_B) const;
  /// τ += Jᵀ f_W for force `f_W` [N] at point p_B of body b (next step).
  void add_force_at(BodyId b, const Vec3& p_B, const Vec3& f_W);
  /// τ += Jᵀ [t_W; f_W] for a wrench at p_B (torque t_W [N·m], force f_W [N]).
  void add_wrench_at(BodyId b, const Vec3& p_B, const Vec3& f_W, const Vec3& t_W);
  /// Sets every collision shape's Coulomb μ of a body.
  void set_friction(BodyId b, double mu);
  double friction(BodyId b) const;
  /// Sets the pose and velocity of a free (6-DOF root) single-body skeleton, e.g. a prop.
  void set_free_body_state(BodyId b, const Eigen::Isometry3d& X_WB, const Vec3& v_W,
                           const Vec3& w_W);

  // ---- contacts of the last step -------------------------------------------------------------
  /// Contacts on body b (empty before the first step).
  const std::vector<ContactPoint>& contacts(BodyId b) const;
  /// Σ f_W over contacts(b) [N].
  Vec3 contact_force_W(BodyId b) const;
  /// Σ f_n over contacts(b) [N].
  double normal_force_sum(BodyId b) const;
  /// Number of contact points the detector reported in the last step.
  int num_contacts() const;

  // ---- patches and obstacle geometry ---------------------------------------------------------
  PatchPool& patches();
  const PatchPool& patches() const;
  /// Fills `meshes` with one ObstacleMesh per non-patch body with collision shapes, in world
  /// coordinates at the current state. Topology is built on the first call and reused when
  /// `meshes` is passed again (no allocation then).
  void export_obstacle_meshes(std::vector<ObstacleMesh>& meshes) const;

  // ---- probes --------------------------------------------------------------------------------
  /// World position of point p_B on body "skeleton/body_node" [m].
  Vec3 probe_W(std::string_view body_path, const Vec3& p_B = Vec3::Zero()) const;

  /// Internal state, for src/rigid/*.cpp only.
  detail::WorldImpl& impl() { return *m_impl; }
  const detail::WorldImpl& impl() const { return *m_impl; }

 private:
  std::unique_ptr<detail::WorldImpl> m_impl;
};

}  // namespace dexcloth::rigid
