#pragma once
/// SceneSpec: a scene file after parsing and validation, in SI units, before compilation into
/// models. Field names mirror the JSON keys documented in docs/scene-format.md.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"

namespace dexcloth::scene {

/// Rigid placement: translation after rotation; rotations in degrees about x, then y, then z.
struct TransformSpec {
  Vec3 translation{Vec3::Zero()};    ///< [m]
  Vec3 rotation_deg{Vec3::Zero()};   ///< [deg], applied x then y then z (R = Rz·Ry·Rx)
};

/// One keyframe of a scripted motion (a handle or an obstacle).
struct KeyframeSpec {
  double t{};                                ///< time [s]
  Vec3 translation{Vec3::Zero()};            ///< offset from the rest placement [m]
  Vec3 rotation_deg{Vec3::Zero()};           ///< extra rotation [deg] (obstacles only)
};

/// Cloth material (areal quantities: the cloth is a surface).
struct MaterialSpec {
  double density{0.15};            ///< areal density [kg/m²]
  double youngs_modulus{5.0e5};    ///< Young's modulus [Pa] (3D; times thickness gives N/m)
  double poisson{0.3};             ///< Poisson ratio [-], in [0, 0.5)
  double thickness{1.0e-3};        ///< thickness [m]
  double bending_stiffness{1.0e-6};///< bending stiffness [N·m]
  double damping{0.005};           ///< stiffness-proportional damping [s]
  double friction{0.5};            ///< Coulomb friction coefficient μ [-]
  std::optional<std::array<double, 2>> strain_limits;  ///< [min, max] singular values, off if absent
};

/// A pinned vertex set: explicit indices or all vertices whose rest world position is in a box.
struct HandleSpec {
  std::vector<int> vertices;              ///< explicit vertex indices (may be empty if box given)
  std::optional<std::array<Vec3, 2>> box; ///< {min, max} world-space box [m]
  std::vector<KeyframeSpec> motion;       ///< optional translation keyframes
  std::optional<double> release;          ///< time [s] the handle lets go (held forever if absent)
  std::optional<Vec3> slide;              ///< unit direction the vertices move freely along
};

/// Cloth geometry: a grid or an OBJ file.
struct MeshSpec {
  /// Grid: size [w,h] [m] and resolution [nx,ny] vertices; lies in local x–y, centred.
  std::optional<std::array<double, 2>> grid_size;
  std::optional<std::array<int, 2>> grid_resolution;
  /// OBJ file path, already resolved relative to the scene file's folder.
  std::optional<std::string> obj_path;
};

struct ClothSpec {
  std::string name;
  MeshSpec mesh;
  TransformSpec transform;
  MaterialSpec material;
  std::vector<HandleSpec> handles;
};

/// Obstacle shape: exactly one of the alternatives is set.
struct ShapeSpec {
  enum class Kind { box, sphere, capsule, plane, obj };
  Kind kind{Kind::box};
  Vec3 box_size{Vec3::Ones()};  ///< [m] full extents (box)
  double radius{};              ///< [m] (sphere, capsule)
  double length{};              ///< [m] capsule cylinder length along local z
  std::string obj_path;         ///< resolved path (obj)
};

struct ObstacleSpec {
  std::string name;
  ShapeSpec shape;
  TransformSpec transform;
  std::vector<KeyframeSpec> motion;  ///< keyframes relative to `transform`, smooth interpolation
  double friction{0.5};             ///< μ against cloth
  double mass{0.0};                 ///< > 0: a dynamic free body [kg]; 0: static or scripted
};

/// A point whose trajectory goes to summary.json: a cloth vertex or a point on a rigid body.
struct ProbeSpec {
  std::string name;
  std::string cloth;                ///< cloth name (cloth probe) or empty
  Vec3 near{Vec3::Zero()};          ///< rest-pose world point; the nearest vertex is probed
  std::string body;                 ///< "skeleton/body_node" (body probe) or empty
  Vec3 point{Vec3::Zero()};         ///< point in the body's frame [m]
};

/// Collision settings shared by all cloths.
struct CollisionSpec {
  double thickness{5.0e-3};  ///< repulsion thickness [m] (paper: 5 mm)
  bool self_collision{true};
};

/// Coupling parameters (paper §5 thresholds).
struct CouplingSpec {
  std::string mode{"bai-liu"};  ///< "bai-liu" or "kinematic"
  double cluster_distance{0.040};    ///< δw [m]
  double cluster_normal_deg{20.0};   ///< δn [deg]
  double cluster_offset{0.003};      ///< δd [m]
  int rigid_substeps{1};             ///< DART steps (and contact detections) per time step
};

/// The cloths' implicit solve.
struct SolverSpec {
  std::string factor_precision{"double"};  ///< "double" or "single" (refined in double)
  double refine_tolerance{1e-10};  ///< relative residual a single factor's solves are refined to
};

struct SceneSpec {
  std::string file;                 ///< path of the scene file as given
  std::string name;
  std::string description;
  double dt{0.005};                 ///< time step [s]
  double duration{1.0};             ///< simulated time [s]
  double frame_rate{50.0};          ///< recorded frames per second
  Vec3 gravity{0.0, 0.0, -9.81};    ///< [m/s²]
  CouplingSpec coupling;
  CollisionSpec collision;
  SolverSpec solver;
  std::vector<ClothSpec> cloths;
  std::vector<ObstacleSpec> obstacles;
  std::vector<ProbeSpec> probes;
  /// Rigid skeletons (DART): kept as validated-later JSON until the rigid side lands.
  nlohmann::json bodies = nlohmann::json::array();
};

}  // namespace dexcloth::scene
