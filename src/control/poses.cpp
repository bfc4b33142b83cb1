#include "control/poses.hpp"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

namespace dexcloth::control {

PoseLibrary load_poses(const std::string& path, ErrorList& errors) {
  PoseLibrary out;
  std::ifstream in(path);
  if (!in) {
    errors.add(path, "", "cannot open pose file");
    return out;
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    errors.add(path, "", std::string("invalid JSON: ") + e.what());
    return out;
  }
  if (!j.is_object()) {
    errors.add(path, "", "must be an object of poses");
    return out;
  }
  for (const auto& [name, pose] : j.items()) {
    const std::string ptr = "/" + name;
    if (name == "description") continue;
    if (!pose.is_object()) {
      errors.add(path, ptr, "must be an object {joint: position}");
      continue;
    }
    JointPose p;
    for (const auto& [joint, value] : pose.items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>())) {
        errors.add(path, ptr + "/" + joint, "must be a finite number [rad or m]");
        continue;
      }
      p[joint] = value.get<double>();
    }
    out[name] = std::move(p);
  }
  return out;
}

}  // namespace dexcloth::control
