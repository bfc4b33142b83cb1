#include <algorithm>

#include "scene/parse_parts.hpp"
#include "scene/suggest.hpp"

namespace dexcloth::scene {

namespace {

// Reports unless `cloth` names one of `cloth_names`, suggesting a close name.
void check_cloth_exists(Checker& c, const std::string& cloth, const Pointer& at,
                        const std::vector<std::string>& cloth_names) {
  if (std::find(cloth_names.begin(), cloth_names.end(), cloth) != cloth_names.end()) return;
  const std::vector<std::string_view> names(cloth_names.begin(), cloth_names.end());
  std::string message = "no cloth named \"" + cloth + "\"";
  if (const auto guess = closest_match(cloth, names)) {
    message += "; did you mean \"" + *guess + "\"?";
  }
  c.fail(at, message);
}

// "skeleton/body_node": two non-empty parts separated by one '/'.
void check_body_path(Checker& c, const std::string& body, const Pointer& at) {
  const auto slash = body.find('/');
  const bool ok = slash != std::string::npos && slash > 0 && slash + 1 < body.size() &&
                  body.find('/', slash + 1) == std::string::npos;
  if (!ok) c.fail(at, "must be \"skeleton/body_node\", got \"" + body + "\"");
}

}  // namespace

ProbeSpec parse_probe(Checker& c, const Json& v, const Pointer& at,
                      const std::vector<std::string>& cloth_names) {
  ProbeSpec p;
  if (!c.require_object(v, at)) return p;
  c.check_keys(v, at, {"name", "cloth", "near", "body", "point"});
  c.string_field(v, at, "name", p.name, Need::required);
  const auto kinds = one_of(c, v, at, {"cloth", "body"});
  const bool single = kinds.size() == 1;
  for (const auto& kind : kinds) {
    if (kind == "cloth") {
      // Cloth probe: a cloth name and a rest-pose point whose nearest vertex is followed.
      if (c.string_field(v, at, "cloth", p.cloth, Need::required)) {
        check_cloth_exists(c, p.cloth, at / "cloth", cloth_names);
      }
      c.vec3_field(v, at, "near", p.near, Need::required);
      if (single && v.contains("point"))
        c.fail(at / "point", "belongs to body probes; use \"near\"");
    } else {
      // Body probe: "skeleton/body_node" and a point in the body frame (default origin).
      if (c.string_field(v, at, "body", p.body, Need::required)) {
        check_body_path(c, p.body, at / "body");
      }
      c.vec3_field(v, at, "point", p.point);
      if (single && v.contains("near"))
        c.fail(at / "near", "belongs to cloth probes; use \"point\"");
    }
  }
  return p;
}

}  // namespace dexcloth::scene
