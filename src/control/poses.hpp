#pragma once
/// Named hand poses: JSON files mapping pose name → {joint name → position [rad or m]}.
#include <map>
#include <string>

#include "core/errors.hpp"

namespace dexcloth::control {

/// Joint name → position [rad or m].
using JointPose = std::map<std::string, double>;
/// Pose name → pose.
using PoseLibrary = std::map<std::string, JointPose>;

/// Reads a pose file `{"open": {"index_pip": 0.0, ...}, ...}` (an optional top-level
/// "description" string is skipped). Reports every problem into `errors` with the file and JSON
/// pointer; returns what could be read.
PoseLibrary load_poses(const std::string& path, ErrorList& errors);

}  // namespace dexcloth::control
