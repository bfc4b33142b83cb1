#pragma once
/// Body specs: one entry of a scene's "bodies" array (docs/bodies-format.md), parsed and
/// validated into plain structs, then built into a RigidWorld skeleton with its controllers.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/controllers.hpp"
#include "core/errors.hpp"
#include "core/types.hpp"
#include "rigid/world.hpp"

namespace dexcloth::control {

/// A fingertip (or any body point) target for IK, in the skeleton's root frame R.
struct IkTargetSpec {
  std::string body;               ///< body node name (in this skeleton)
  Vec3 point_B{Vec3::Zero()};     ///< point in the body frame [m]
  Vec3 target_R{Vec3::Zero()};    ///< target in the root frame [m]
  std::string pointer;            ///< JSON pointer, for errors
};

/// One joint-target keyframe: a named pose, then per-joint overrides, then IK targets.
struct PoseKeySpec {
  double t{};                                  ///< [s]
  std::string pose;                            ///< name in the pose file, "" = previous key
  std::map<std::string, double> joints;        ///< joint → position [rad or m]
  std::vector<IkTargetSpec> ik;
  std::string pointer;
};

struct GainSpec {
  double kp{};  ///< [N·m/rad] or [N/m]
  double kd{};  ///< [N·m·s/rad] or [N·s/m]
};

struct JointPdSpec {
  GainSpec gains{2.0, 0.05};                  ///< default gains of every non-root DOF
  std::map<std::string, GainSpec> joint_gains; ///< per-joint overrides
  std::vector<PoseKeySpec> keyframes;
  std::string pointer;
};

struct WristKeySpec {
  double t{};
  Vec3 translation{Vec3::Zero()};   ///< [m] world
  Vec3 rotation_deg{Vec3::Zero()};  ///< [deg] about x, then y, then z (R = Rz·Ry·Rx)
};

struct WristSpec {
  CartesianGains gains;
  Vec3 point_B{Vec3::Zero()};       ///< controlled point on the root body [m]
  std::vector<WristKeySpec> keyframes;  ///< world poses of the root body frame; empty: hold start
};

struct ForceKeySpec {
  double t{};
  Vec3 force_W{Vec3::Zero()};       ///< [N]
};

struct PointForceSpec {
  std::string body;
  Vec3 point_B{Vec3::Zero()};       ///< [m]
  std::vector<ForceKeySpec> keyframes;
  std::string pointer;
};

struct JointForceKeySpec {
  double t{};
  std::map<std::string, double> joints;  ///< joint → generalized force [N·m or N]
  std::string pointer;
};

struct JointForcesSpec {
  bool hold{true};                   ///< step at keys (true) or smoothstep (false)
  std::vector<JointForceKeySpec> keyframes;
  std::string pointer;
};

enum class GravityCompensationMode { none, joints, full };

struct ControllerSpec {
  GravityCompensationMode gravity_compensation{GravityCompensationMode::full};
  std::optional<JointPdSpec> joint_pd;
  std::optional<WristSpec> wrist;
  std::vector<PointForceSpec> forces;
  std::optional<JointForcesSpec> joint_forces;
};

/// One "bodies" entry, paths resolved against the scene file's folder.
struct BodySpec {
  std::string name;
  std::string urdf;                         ///< resolved path
  std::string poses;                        ///< resolved pose file path, "" if none
  Vec3 root_translation{Vec3::Zero()};      ///< [m]
  Vec3 root_rotation_deg{Vec3::Zero()};     ///< [deg] x, then y, then z
  bool fixed_root{false};
  double friction{1.0};                     ///< Coulomb μ of every collision shape
  ControllerSpec controller;
  std::string pointer;                      ///< e.g. "/bodies/0"
};

/// Parses `j` (the entry at JSON pointer `pointer` of `file`; relative paths are resolved
/// against `scene_dir`). Every problem goes into `errors` (file, pointer, message); unknown
/// keys are problems too. Returns what was read.
BodySpec parse_body_spec(const nlohmann::json& j, const std::string& file, const std::string& pointer,
                         const std::string& scene_dir, ErrorList& errors);

/// A skeleton built from a BodySpec, with its controllers.
struct BuiltBody {
  rigid::SkeletonId skeleton;
  ControllerSet controllers;
};

/// Loads the URDF and pose file, resolves joint and body names, solves IK keyframes, and makes
/// the controllers. Throws InputRejected listing every problem (against `file` and pointers).
BuiltBody build_body(rigid::RigidWorld& world, const BodySpec& spec, const std::string& file);


/// World position of point p_B [m] on body "skeleton/body_node" (a probe).
Vec3 probe(const rigid::RigidWorld& world, const std::string& body_path, const Vec3& p_B = Vec3::Zero());

}  // namespace dexcloth::control
