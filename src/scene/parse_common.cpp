#include <map>

#include "scene/parse_parts.hpp"

namespace dexcloth::scene {

TransformSpec parse_transform(Checker& c, const Json& v, const Pointer& at) {
  TransformSpec t;
  if (!c.require_object(v, at)) return t;
  c.check_keys(v, at, {"translation", "rotation_deg"});
  c.vec3_field(v, at, "translation", t.translation);
  c.vec3_field(v, at, "rotation_deg", t.rotation_deg);
  return t;
}

std::vector<KeyframeSpec> parse_motion(Checker& c, const Json& v, const Pointer& at,
                                       bool with_rotation) {
  std::vector<KeyframeSpec> motion;
  if (!c.require_array(v, at)) return motion;
  std::optional<double> previous_t;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Pointer at_i = at / i;
    const Json& k = v[i];
    if (!c.require_object(k, at_i)) continue;
    if (with_rotation) {
      c.check_keys(k, at_i, {"t", "translation", "rotation_deg"});
    } else {
      c.check_keys(k, at_i, {"t", "translation"});
    }
    KeyframeSpec key;
    const bool t_ok = c.number_field(k, at_i, "t", Rule::non_negative(), key.t, Need::required);
    c.vec3_field(k, at_i, "translation", key.translation);
    if (with_rotation) c.vec3_field(k, at_i, "rotation_deg", key.rotation_deg);
    // Keyframe times must strictly increase so interpolation is well defined.
    if (t_ok && previous_t && !(key.t > *previous_t)) {
      c.fail(at_i / "t", "must be > the previous keyframe's t (" + Json(*previous_t).dump() +
                             "), got " + Json(key.t).dump());
    }
    if (t_ok) previous_t = key.t;
    motion.push_back(key);
  }
  return motion;
}

std::vector<std::string> one_of(Checker& c, const Json& obj, const Pointer& at,
                                const std::vector<std::string_view>& options) {
  std::vector<std::string> present;
  std::string listed;
  for (const auto o : options) {
    listed += (listed.empty() ? "\"" : ", \"") + std::string(o) + "\"";
    if (obj.contains(std::string(o))) present.emplace_back(o);
  }
  if (present.size() == 1) return present;
  std::string got = present.empty() ? "none" : "";
  for (const auto& p : present) got += (got.empty() ? "\"" : " and \"") + p + "\"";
  c.fail(at, "must have exactly one of " + listed + ", got " + got);
  return present;
}

void check_unique_names(Checker& c, const std::vector<NamedAt>& items, const std::string& what) {
  std::map<std::string, Pointer> first_use;
  for (const auto& item : items) {
    if (item.name.empty()) continue;
    const auto [it, inserted] = first_use.emplace(item.name, item.at);
    if (!inserted) {
      c.fail(item.at / "name", "duplicate " + what + " name \"" + item.name + "\" (first used at " +
                                   it->second.to_string() + ")");
    }
  }
}

}  // namespace dexcloth::scene
