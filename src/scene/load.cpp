#include "scene/load.hpp"

#include <filesystem>

#include "core/errors.hpp"
#include "scene/json_text.hpp"
#include "scene/overrides.hpp"
#include "scene/parse_parts.hpp"
#include "scene/suggest.hpp"

namespace dexcloth::scene {

namespace {

// A string that must be one of two `choices`, with a suggestion when it is close to one.
void check_choice(Checker& c, const Pointer& at, const std::string& value,
                  const std::vector<std::string_view>& choices) {
  if (value == choices[0] || value == choices[1]) return;
  std::string message = "must be \"" + std::string(choices[0]) + "\" or \"" +
                        std::string(choices[1]) + "\", got \"" + value + "\"";
  if (const auto guess = closest_match(value, choices))
    message += "; did you mean \"" + *guess + "\"?";
  c.fail(at, message);
}

// `coupling` (mode string) and `coupling_params` (paper §5 clustering thresholds, rigid substeps).
CouplingSpec parse_coupling(Checker& c, const Json& doc, const Pointer& root) {
  CouplingSpec s;
  if (c.string_field(doc, root, "coupling", s.mode))
    check_choice(c, root / "coupling", s.mode, {"bai-liu", "kinematic"});
  const Json* p = c.member(doc, root, "coupling_params", Need::optional);
  const Pointer at = root / "coupling_params";
  if (!p || !c.require_object(*p, at)) return s;
  c.check_keys(*p, at,
               {"cluster_distance", "cluster_normal_deg", "cluster_offset", "rigid_substeps"});
  c.number_field(*p, at, "cluster_distance", Rule::positive(), s.cluster_distance);
  c.number_field(*p, at, "cluster_normal_deg", Rule::between(0.0, true, 180.0, false),
                 s.cluster_normal_deg);
  c.number_field(*p, at, "cluster_offset", Rule::positive(), s.cluster_offset);
  if (const Json* n = c.member(*p, at, "rigid_substeps", Need::optional))
    if (const auto k =
            c.require_int(*n, at / "rigid_substeps", Rule::between(1.0, false, 64.0, false)))
      s.rigid_substeps = *k;
  return s;
}

// `collision`: repulsion thickness and self-collision switch.
CollisionSpec parse_collision(Checker& c, const Json& doc, const Pointer& root) {
  CollisionSpec s;
  const Json* v = c.member(doc, root, "collision", Need::optional);
  const Pointer at = root / "collision";
  if (!v || !c.require_object(*v, at)) return s;
  c.check_keys(*v, at, {"thickness", "self_collision"});
  c.number_field(*v, at, "thickness", Rule::positive(), s.thickness);
  c.bool_field(*v, at, "self_collision", s.self_collision);
  return s;
}

// `solver`: the precision of the cloths' Cholesky factor and the residual its solves are refined
// to (at most the implicit step's accepted 1e-5).
SolverSpec parse_solver(Checker& c, const Json& doc, const Pointer& root) {
  SolverSpec s;
  const Json* v = c.member(doc, root, "solver", Need::optional);
  const Pointer at = root / "solver";
  if (!v || !c.require_object(*v, at)) return s;
  c.check_keys(*v, at, {"factor_precision", "refine_tolerance"});
  if (c.string_field(*v, at, "factor_precision", s.factor_precision))
    check_choice(c, at / "factor_precision", s.factor_precision, {"double", "single"});
  c.number_field(*v, at, "refine_tolerance", Rule::between(0.0, true, 1e-5, false),
                 s.refine_tolerance);
  return s;
}

// `bodies`: kept as JSON for the rigid module; here only an array of objects with a name.
Json parse_bodies(Checker& c, const Json& v, const Pointer& at) {
  if (!c.require_array(v, at)) return Json::array();
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!c.require_object(v[i], at / i)) continue;
    std::string name;
    c.string_field(v[i], at / i, "name", name, Need::required);
  }
  return v;
}

// Calls `each(item, pointer)` for every entry of the array `key` (required or optional).
template <class F>
void for_each_entry(Checker& c, const Json& doc, const Pointer& root, const char* key, Need need,
                    F each) {
  const Json* v = c.member(doc, root, key, need);
  const Pointer at = root / key;
  if (!v || !c.require_array(*v, at)) return;
  for (std::size_t i = 0; i < v->size(); ++i) each((*v)[i], at / i);
}

// The whole document: top-level scalars, then cloths, obstacles, probes (which refer to
// cloths by name), bodies.
SceneSpec validate_scene(Checker& c, const Json& doc) {
  SceneSpec s;
  const Pointer root;
  if (!c.require_object(doc, root)) return s;
  c.check_keys(
      doc, root,
      {"name", "description", "dt", "duration", "frame_rate", "gravity", "coupling",
       "coupling_params", "collision", "solver", "cloths", "obstacles", "probes", "bodies"});
  c.string_field(doc, root, "name", s.name, Need::required);
  c.string_field(doc, root, "description", s.description, Need::optional, true);
  c.number_field(doc, root, "dt", Rule::between(0.0, true, 0.05, false), s.dt);
  c.number_field(doc, root, "duration", Rule::positive(), s.duration);
  c.number_field(doc, root, "frame_rate", Rule::positive(), s.frame_rate);
  c.vec3_field(doc, root, "gravity", s.gravity);
  s.coupling = parse_coupling(c, doc, root);
  s.collision = parse_collision(c, doc, root);
  s.solver = parse_solver(c, doc, root);

  std::vector<NamedAt> cloth_names, obstacle_names, probe_names;
  for_each_entry(c, doc, root, "cloths", Need::required, [&](const Json& v, const Pointer& at) {
    s.cloths.push_back(parse_cloth(c, v, at));
    cloth_names.push_back({s.cloths.back().name, at});
  });
  for_each_entry(c, doc, root, "obstacles", Need::optional, [&](const Json& v, const Pointer& at) {
    s.obstacles.push_back(parse_obstacle(c, v, at));
    obstacle_names.push_back({s.obstacles.back().name, at});
  });
  std::vector<std::string> known_cloths;
  for (const auto& cloth : s.cloths) known_cloths.push_back(cloth.name);
  for_each_entry(c, doc, root, "probes", Need::optional, [&](const Json& v, const Pointer& at) {
    s.probes.push_back(parse_probe(c, v, at, known_cloths));
    probe_names.push_back({s.probes.back().name, at});
  });
  if (const Json* b = c.member(doc, root, "bodies", Need::optional)) {
    s.bodies = parse_bodies(c, *b, root / "bodies");
  }
  check_unique_names(c, cloth_names, "cloth");
  check_unique_names(c, obstacle_names, "obstacle");
  check_unique_names(c, probe_names, "probe");
  return s;
}

// Copies `errors`, noting on each problem at or under an overridden pointer which --set caused it.
ErrorList blame_overrides(const ErrorList& errors, const std::string& file,
                          const std::vector<std::string>& overrides) {
  std::vector<Override> applied;
  ErrorList ignored;
  for (const auto& text : overrides) {
    if (auto o = parse_override(text, ignored)) applied.push_back(std::move(*o));
  }
  ErrorList out;
  for (const auto& e : errors.errors()) {
    std::string message = e.message;
    for (const auto& o : applied) {
      const std::string p = o.pointer.to_string();
      const bool under = e.pointer == p || e.pointer.rfind(p + "/", 0) == 0;
      if (e.file == file && under) message += " (from --set " + o.text + ")";
    }
    out.add(e.file, e.pointer, message);
  }
  return out;
}

}  // namespace

SceneSpec parse_scene(const nlohmann::json& doc, const std::string& file,
                      const std::string& base_dir) {
  ErrorList errors;
  Checker c(errors, file, base_dir);
  SceneSpec spec = validate_scene(c, doc);
  if (!errors.empty()) throw InputRejected(std::move(errors));
  spec.file = file;
  return spec;
}

SceneSpec load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  ErrorList errors;
  const auto doc = read_json_file(path, errors);
  if (!doc) {
    // The file is unusable; still report malformed overrides in the same go.
    for (const auto& text : overrides) parse_override(text, errors);
    throw InputRejected(std::move(errors));
  }
  const Json merged = apply_overrides(*doc, overrides, errors);
  Checker c(errors, path, std::filesystem::path(path).parent_path().string());
  SceneSpec spec = validate_scene(c, merged);
  if (!errors.empty()) throw InputRejected(blame_overrides(errors, path, overrides));
  spec.file = path;
  return spec;
}

}  // namespace dexcloth::scene
