#include "control/body_spec.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <sstream>

#include "control/poses.hpp"
#include "core/transform.hpp"
#include "rigid/ik.hpp"

namespace dexcloth::control {
namespace {

using nlohmann::json;

/// Reads typed values out of JSON objects, reporting problems with file and pointer.
class Reader {
 public:
  Reader(const std::string& file, ErrorList& errors) : m_file(file), m_errors(errors) {}

  void error(const std::string& ptr, const std::string& message) { m_errors.add(m_file, ptr, message); }

  /// `j` must be an object whose keys are all in `allowed`.
  bool object(const json& j, const std::string& ptr, std::initializer_list<const char*> allowed) {
    if (!j.is_object()) {
      error(ptr, "must be an object");
      return false;
    }
    const std::set<std::string> keys(allowed.begin(), allowed.end());
    for (const auto& [key, value] : j.items()) {
      if (!keys.contains(key)) {
        std::string list;
        for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
        error(ptr + "/" + key, "unknown key (expected one of: " + list + ")");
      }
    }
    return true;
  }

  /// Number at j[key] (if present) with value ≥ min (strict: > min); stored in `out`.
  void number(const json& j, const char* key, const std::string& ptr, double& out,
              double min = -INFINITY, bool strict = false) {
    if (!j.contains(key)) return;
    const std::string p = ptr + "/" + key;
    const json& v = j.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      error(p, "must be a finite number, got " + v.dump());
      return;
    }
    const double x = v.get<double>();
    if (strict ? !(x > min) : !(x >= min)) {
      std::ostringstream s;
      s << "must be " << (strict ? "> " : "≥ ") << min << ", got " << x;
      error(p, s.str());
      return;
    }
    out = x;
  }

  void boolean(const json& j, const char* key, const std::string& ptr, bool& out) {
    if (!j.contains(key)) return;
    if (!j.at(key).is_boolean()) {
      error(ptr + "/" + key, "must be true or false, got " + j.at(key).dump());
      return;
    }
    out = j.at(key).get<bool>();
  }

  void string(const json& j, const char* key, const std::string& ptr, std::string& out, bool required) {
    if (!j.contains(key)) {
      if (required) error(ptr + "/" + key, "is required");
      return;
    }
    if (!j.at(key).is_string() || j.at(key).get<std::string>().empty()) {
      error(ptr + "/" + key, "must be a non-empty string, got " + j.at(key).dump());
      return;
    }
    out = j.at(key).get<std::string>();
  }

  void vec3(const json& j, const char* key, const std::string& ptr, Vec3& out) {
    if (!j.contains(key)) return;
    const json& v = j.at(key);
    if (!v.is_array() || v.size() != 3 || !std::all_of(v.begin(), v.end(), [](const json& x) {
          return x.is_number() && std::isfinite(x.get<double>());
        })) {
      error(ptr + "/" + key, "must be an array of 3 finite numbers, got " + v.dump());
      return;
    }
    out = Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  }

  /// Object {name: number}.
  void number_map(const json& j, const char* key, const std::string& ptr, std::map<std::string, double>& out) {
    if (!j.contains(key)) return;
    const std::string p = ptr + "/" + key;
    if (!j.at(key).is_object()) {
      error(p, "must be an object {joint: number}");
      return;
    }
    for (const auto& [name, v] : j.at(key).items()) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) {
        error(p + "/" + name, "must be a finite number, got " + v.dump());
        continue;
      }
      out[name] = v.get<double>();
    }
  }

  /// Array at j[key]; calls f(element, pointer) for each element.
  template <class F>
  void array(const json& j, const char* key, const std::string& ptr, bool required, F&& f) {
    if (!j.contains(key)) {
      if (required) error(ptr + "/" + key, "is required");
      return;
    }
    const json& a = j.at(key);
    if (!a.is_array() || a.empty()) {
      error(ptr + "/" + key, "must be a non-empty array");
      return;
    }
    for (std::size_t i = 0; i < a.size(); ++i) f(a[i], ptr + "/" + key + "/" + std::to_string(i));
  }

  /// Key times must strictly increase.
  template <class K>
  void increasing(const std::vector<K>& keys, const std::string& ptr) {
    for (std::size_t i = 1; i < keys.size(); ++i) {
      if (!(keys[i].t > keys[i - 1].t)) {
        std::ostringstream s;
        s << "must be > the previous keyframe's t (" << keys[i - 1].t << "), got " << keys[i].t;
        error(ptr + "/" + std::to_string(i) + "/t", s.str());
      }
    }
  }

  /// t of a keyframe: required, ≥ 0.
  double time(const json& j, const std::string& ptr) {
    double t = 0.0;
    if (!j.is_object() || !j.contains("t")) {
      error(ptr + "/t", "is required");
      return t;
    }
    number(j, "t", ptr, t, 0.0);
    return t;
  }

 private:
  const std::string& m_file;
  ErrorList& m_errors;
};

std::string resolve(const std::string& path, const std::string& dir) {
  const std::filesystem::path p(path);
  return p.is_absolute() ? path : (std::filesystem::path(dir) / p).lexically_normal().string();
}

JointPdSpec parse_joint_pd(Reader& r, const json& j, const std::string& ptr) {
  JointPdSpec pd;
  pd.pointer = ptr;
  if (!r.object(j, ptr, {"kp", "kd", "gains", "keyframes"})) return pd;
  r.number(j, "kp", ptr, pd.gains.kp, 0.0);
  r.number(j, "kd", ptr, pd.gains.kd, 0.0);
  if (j.contains("gains")) {
    const std::string gp = ptr + "/gains";
    if (!j.at("gains").is_object()) {
      r.error(gp, "must be an object {joint: {kp, kd}}");
    } else {
      for (const auto& [joint, g] : j.at("gains").items()) {
        GainSpec gain = pd.gains;
        if (r.object(g, gp + "/" + joint, {"kp", "kd"})) {
          r.number(g, "kp", gp + "/" + joint, gain.kp, 0.0);
          r.number(g, "kd", gp + "/" + joint, gain.kd, 0.0);
        }
        pd.joint_gains[joint] = gain;
      }
    }
  }
  r.array(j, "keyframes", ptr, true, [&](const json& k, const std::string& kp) {
    PoseKeySpec key;
    key.pointer = kp;
    key.t = r.time(k, kp);
    if (!r.object(k, kp, {"t", "pose", "joints", "ik"})) return;
    r.string(k, "pose", kp, key.pose, false);
    r.number_map(k, "joints", kp, key.joints);
    r.array(k, "ik", kp, false, [&](const json& ik, const std::string& ip) {
      IkTargetSpec target;
      target.pointer = ip;
      if (!r.object(ik, ip, {"body", "point", "target"})) return;
      r.string(ik, "body", ip, target.body, true);
      r.vec3(ik, "point", ip, target.point_B);
      if (!ik.contains("target")) r.error(ip + "/target", "is required");
      r.vec3(ik, "target", ip, target.target_R);
      key.ik.push_back(target);
    });
    pd.keyframes.push_back(std::move(key));
  });
  r.increasing(pd.keyframes, ptr + "/keyframes");
  return pd;
}

WristSpec parse_wrist(Reader& r, const json& j, const std::string& ptr) {
  WristSpec w;
  if (!r.object(j, ptr, {"kp", "kd", "kp_rot", "kd_rot", "point", "keyframes"})) return w;
  r.number(j, "kp", ptr, w.gains.kp, 0.0);
  r.number(j, "kd", ptr, w.gains.kd, 0.0);
  r.number(j, "kp_rot", ptr, w.gains.kp_rot, 0.0);
  r.number(j, "kd_rot", ptr, w.gains.kd_rot, 0.0);
  r.vec3(j, "point", ptr, w.point_B);
  r.array(j, "keyframes", ptr, false, [&](const json& k, const std::string& kp) {
    WristKeySpec key;
    key.t = r.time(k, kp);
    if (!r.object(k, kp, {"t", "translation", "rotation_deg"})) return;
    r.vec3(k, "translation", kp, key.translation);
    r.vec3(k, "rotation_deg", kp, key.rotation_deg);
    w.keyframes.push_back(key);
  });
  r.increasing(w.keyframes, ptr + "/keyframes");
  return w;
}

}  // namespace

BodySpec parse_body_spec(const json& j, const std::string& file, const std::string& pointer,
                         const std::string& scene_dir, ErrorList& errors) {
  Reader r(file, errors);
  BodySpec spec;
  spec.pointer = pointer;
  if (!r.object(j, pointer, {"name", "urdf", "poses", "root", "fixed_root", "friction", "controller"})) return spec;
  r.string(j, "name", pointer, spec.name, true);
  if (spec.name.find('/') != std::string::npos) r.error(pointer + "/name", "must not contain '/', got \"" + spec.name + "\"");
  r.string(j, "urdf", pointer, spec.urdf, true);
  if (!spec.urdf.empty()) spec.urdf = resolve(spec.urdf, scene_dir);
  r.string(j, "poses", pointer, spec.poses, false);
  if (!spec.poses.empty()) spec.poses = resolve(spec.poses, scene_dir);
  if (j.contains("root")) {
    const std::string rp = pointer + "/root";
    if (r.object(j.at("root"), rp, {"translation", "rotation_deg"})) {
      r.vec3(j.at("root"), "translation", rp, spec.root_translation);
      r.vec3(j.at("root"), "rotation_deg", rp, spec.root_rotation_deg);
    }
  }
  r.boolean(j, "fixed_root", pointer, spec.fixed_root);
  r.number(j, "friction", pointer, spec.friction, 0.0);
  if (!j.contains("controller")) return spec;
  // Controller.
  const std::string cp = pointer + "/controller";
  const json& c = j.at("controller");
  if (!r.object(c, cp, {"gravity_compensation", "joint_pd", "wrist", "forces", "joint_forces"})) return spec;
  ControllerSpec& ctl = spec.controller;
  if (c.contains("gravity_compensation")) {
    const json& g = c.at("gravity_compensation");
    const std::string s = g.is_string() ? g.get<std::string>() : "";
    if (s == "none") ctl.gravity_compensation = GravityCompensationMode::none;
    else if (s == "joints") ctl.gravity_compensation = GravityCompensationMode::joints;
    else if (s == "full") ctl.gravity_compensation = GravityCompensationMode::full;
    else r.error(cp + "/gravity_compensation", "must be \"none\", \"joints\" or \"full\", got " + g.dump());
  }
  if (c.contains("joint_pd")) ctl.joint_pd = parse_joint_pd(r, c.at("joint_pd"), cp + "/joint_pd");
  if (c.contains("wrist")) {
    ctl.wrist = parse_wrist(r, c.at("wrist"), cp + "/wrist");
    if (spec.fixed_root) r.error(cp + "/wrist", "needs a free root (fixed_root is true)");
  }
  r.array(c, "forces", cp, false, [&](const json& f, const std::string& fp) {
    PointForceSpec force;
    force.pointer = fp;
    if (!r.object(f, fp, {"body", "point", "keyframes"})) return;
    r.string(f, "body", fp, force.body, true);
    r.vec3(f, "point", fp, force.point_B);
    r.array(f, "keyframes", fp, true, [&](const json& k, const std::string& kp) {
      ForceKeySpec key;
      key.t = r.time(k, kp);
      if (!r.object(k, kp, {"t", "force"})) return;
      if (!k.contains("force")) r.error(kp + "/force", "is required");
      r.vec3(k, "force", kp, key.force_W);
      force.keyframes.push_back(key);
    });
    r.increasing(force.keyframes, fp + "/keyframes");
    ctl.forces.push_back(std::move(force));
  });
  if (c.contains("joint_forces")) {
    const std::string fp = cp + "/joint_forces";
    const json& f = c.at("joint_forces");
    JointForcesSpec jf;
    jf.pointer = fp;
    if (r.object(f, fp, {"interpolate", "keyframes"})) {
      bool interpolate = false;
      r.boolean(f, "interpolate", fp, interpolate);
      jf.hold = !interpolate;
      r.array(f, "keyframes", fp, true, [&](const json& k, const std::string& kp) {
        JointForceKeySpec key;
        key.pointer = kp;
        key.t = r.time(k, kp);
        if (!r.object(k, kp, {"t", "joints"})) return;
        if (!k.contains("joints")) r.error(kp + "/joints", "is required");
        r.number_map(k, "joints", kp, key.joints);
        jf.keyframes.push_back(std::move(key));
      });
      r.increasing(jf.keyframes, fp + "/keyframes");
    }
    ctl.joint_forces = std::move(jf);
  }
  return spec;
}

BuiltBody build_body(rigid::RigidWorld& world, const BodySpec& spec, const std::string& file) {
  ErrorList errors;
  // Skeleton (URDF problems are reported against the URDF file by RigidWorld).
  rigid::UrdfOptions options;
  options.fixed_root = spec.fixed_root;
  options.friction = spec.friction;
  options.X_WR.linear() = rotation_xyz_deg(spec.root_rotation_deg);
  options.X_WR.translation() = spec.root_translation;
  BuiltBody built;
  try {
    built.skeleton = world.add_urdf(spec.name, spec.urdf, options);
  } catch (const InputRejected& e) {
    for (const auto& err : e.errors().errors()) errors.add(file, spec.pointer + "/urdf", err.to_string());
    throw InputRejected(std::move(errors));
  }
  const rigid::SkeletonId s = built.skeleton;
  const int n = world.num_dofs(s);
  const int root = world.root_dofs(s);
  auto dof = [&](const std::string& joint, const std::string& ptr) -> std::optional<int> {
    auto i = world.find_dof(s, joint);
    if (!i) errors.add(file, ptr, "no joint '" + joint + "' in " + spec.urdf);
    return i;
  };
  auto body = [&](const std::string& name, const std::string& ptr) -> std::optional<rigid::BodyId> {
    auto b = world.find_body(spec.name + "/" + name);
    if (!b) errors.add(file, ptr, "no body '" + name + "' in " + spec.urdf);
    return b;
  };
  PoseLibrary poses;
  if (!spec.poses.empty()) {
    ErrorList pose_errors;
    poses = load_poses(spec.poses, pose_errors);
    for (const auto& err : pose_errors.errors()) errors.add(file, spec.pointer + "/poses", err.to_string());
  }
  const ControllerSpec& ctl = spec.controller;
  // Gravity compensation first: its forces are state-dependent, like everything else.
  if (ctl.gravity_compensation != GravityCompensationMode::none) {
    built.controllers.add(std::make_unique<GravityCompensation>(s, ctl.gravity_compensation == GravityCompensationMode::joints));
  }
  // Joint PD over every non-root DOF; each key starts from the previous key's targets.
  if (ctl.joint_pd) {
    const JointPdSpec& pd = *ctl.joint_pd;
    std::vector<int> dofs;
    for (int i = root; i < n; ++i) dofs.push_back(i);
    Eigen::VectorXd kp = Eigen::VectorXd::Constant(n - root, pd.gains.kp);
    Eigen::VectorXd kd = Eigen::VectorXd::Constant(n - root, pd.gains.kd);
    for (const auto& [joint, g] : pd.joint_gains) {
      if (auto i = dof(joint, pd.pointer + "/gains/" + joint)) {
        kp[*i - root] = g.kp;
        kd[*i - root] = g.kd;
      }
    }
    std::vector<VectorKeyframe> keys;
    Eigen::VectorXd q = world.positions(s);
    const Eigen::VectorXd q_start = q;
    for (const PoseKeySpec& key : pd.keyframes) {
      if (!key.pose.empty()) {
        const auto it = poses.find(key.pose);
        if (it == poses.end()) {
          errors.add(file, key.pointer + "/pose", "no pose '" + key.pose + "'" + (spec.poses.empty() ? " (no \"poses\" file given)" : " in " + spec.poses));
        } else {
          for (const auto& [joint, value] : it->second) {
            if (auto i = dof(joint, key.pointer + "/pose")) q[*i] = value;
          }
        }
      }
      for (const auto& [joint, value] : key.joints) {
        if (auto i = dof(joint, key.pointer + "/joints/" + joint)) q[*i] = value;
      }
      // IK in the root frame: solve with the root at the identity pose.
      if (!key.ik.empty()) {
        std::vector<rigid::IkTarget> targets;
        for (const auto& t : key.ik) {
          if (auto b = body(t.body, t.pointer + "/body")) targets.push_back({*b, t.point_B, t.target_R, 1.0});
        }
        if (targets.size() == key.ik.size()) {
          Eigen::VectorXd q_seed = q;
          if (root == 6) q_seed.head<6>().setZero();
          world.set_positions(s, q_seed);
          const rigid::IkResult ik = rigid::solve_ik(world, s, targets);
          world.set_positions(s, q_start);
          if (ik.max_error > 2.0e-3) {
            errors.add(file, key.pointer + "/ik", "targets not reachable: best fit misses by " + std::to_string(ik.max_error * 1000.0) + " mm");
          }
          q.tail(n - root) = ik.q.tail(n - root);
        }
      }
      keys.push_back({key.t, q.tail(n - root)});
    }
    if (errors.empty()) built.controllers.add(std::make_unique<JointPdController>(s, dofs, std::move(keys), kp, kd));
  }
  // Wrist: Cartesian PD on the root body toward keyframed world poses (hold the start if none).
  if (ctl.wrist) {
    std::vector<rigid::PoseKeyframe> keys;
    const rigid::BodyId rb = world.root_body(s);
    for (const auto& k : ctl.wrist->keyframes) {
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = rotation_xyz_deg(k.rotation_deg);
      X.translation() = k.translation + X.linear() * ctl.wrist->point_B;
      keys.push_back({k.t, X});
    }
    if (keys.empty()) {
      Eigen::Isometry3d X = world.pose_W(rb);
      X.translation() = world.point_W(rb, ctl.wrist->point_B);
      keys.push_back({0.0, X});
    }
    built.controllers.add(std::make_unique<WristController>(rb, ctl.wrist->point_B, std::move(keys), ctl.wrist->gains));
  }
  // Jacobian-transpose point forces.
  for (const auto& f : ctl.forces) {
    auto b = body(f.body, f.pointer + "/body");
    if (!b) continue;
    std::vector<VectorKeyframe> keys;
    for (const auto& k : f.keyframes) keys.push_back({k.t, k.force_W});
    built.controllers.add(std::make_unique<PointForceController>(*b, f.point_B, std::move(keys)));
  }
  // Joint force timeline over the union of the joints named in any key (0 where a key omits one).
  if (ctl.joint_forces) {
    std::map<std::string, int> columns;
    std::vector<int> dofs;
    for (const auto& k : ctl.joint_forces->keyframes) {
      for (const auto& [joint, value] : k.joints) {
        if (columns.contains(joint)) continue;
        if (auto i = dof(joint, k.pointer + "/joints/" + joint)) {
          columns[joint] = static_cast<int>(dofs.size());
          dofs.push_back(*i);
        }
      }
    }
    std::vector<VectorKeyframe> keys;
    for (const auto& k : ctl.joint_forces->keyframes) {
      Eigen::VectorXd v = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dofs.size()));
      for (const auto& [joint, value] : k.joints) {
        if (columns.contains(joint)) v[columns[joint]] = value;
      }
      keys.push_back({k.t, v});
    }
    if (!dofs.empty()) built.controllers.add(std::make_unique<JointForceController>(s, dofs, std::move(keys), ctl.joint_forces->hold));
  }
  if (!errors.empty()) throw InputRejected(std::move(errors));
  return built;
}

Vec3 probe(const rigid::RigidWorld& world, const std::string& body_path, const Vec3& p_B) {
  return world.probe_W(body_path, p_B);
}

}  // namespace dexcloth::control
