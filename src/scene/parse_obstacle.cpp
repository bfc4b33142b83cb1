#include "scene/parse_parts.hpp"

namespace dexcloth::scene {

namespace {

// Reads one shape alternative `kind` (value `v` at `at`) into `s`.
void parse_shape_kind(Checker& c, const std::string& kind, const Json& v, const Pointer& at,
                      ShapeSpec& s) {
  using Kind = ShapeSpec::Kind;
  if (kind == "obj") {
    s.kind = Kind::obj;
    if (const auto path = c.require_file(v, at)) s.obj_path = *path;
    return;
  }
  if (!c.require_object(v, at)) return;
  if (kind == "box") {
    s.kind = Kind::box;
    c.check_keys(v, at, {"size"});
    if (const Json* size = c.member(v, at, "size", Need::required)) {
      if (const auto a = c.require_numbers<3>(*size, at / "size", Rule::positive())) {
        s.box_size = Vec3((*a)[0], (*a)[1], (*a)[2]);
      }
    }
  } else if (kind == "sphere") {
    s.kind = Kind::sphere;
    c.check_keys(v, at, {"radius"});
    c.number_field(v, at, "radius", Rule::positive(), s.radius, Need::required);
  } else if (kind == "capsule") {
    s.kind = Kind::capsule;
    c.check_keys(v, at, {"radius", "length"});
    c.number_field(v, at, "radius", Rule::positive(), s.radius, Need::required);
    c.number_field(v, at, "length", Rule::non_negative(), s.length, Need::required);
  } else {
    s.kind = Kind::plane;
    c.check_keys(v, at, {});
  }
}

// Exactly one of box, sphere, capsule, plane, obj.
ShapeSpec parse_shape(Checker& c, const Json& v, const Pointer& at) {
  ShapeSpec s;
  if (!c.require_object(v, at)) return s;
  const std::vector<std::string_view> kinds = {"box", "sphere", "capsule", "plane", "obj"};
  c.check_keys(v, at, kinds);
  for (const auto& kind : one_of(c, v, at, kinds)) {
    parse_shape_kind(c, kind, v[kind], at / kind, s);
  }
  return s;
}

}  // namespace

ObstacleSpec parse_obstacle(Checker& c, const Json& v, const Pointer& at) {
  ObstacleSpec o;
  if (!c.require_object(v, at)) return o;
  c.check_keys(v, at, {"name", "shape", "transform", "motion", "friction", "mass"});
  c.string_field(v, at, "name", o.name, Need::required);
  if (const Json* s = c.member(v, at, "shape", Need::required)) {
    o.shape = parse_shape(c, *s, at / "shape");
  }
  if (const Json* t = c.member(v, at, "transform", Need::optional)) {
    o.transform = parse_transform(c, *t, at / "transform");
  }
  if (const Json* m = c.member(v, at, "motion", Need::optional)) {
    o.motion = parse_motion(c, *m, at / "motion", true);
  }
  c.number_field(v, at, "friction", Rule::non_negative(), o.friction);
  c.number_field(v, at, "mass", Rule::non_negative(), o.mass);
  if (o.mass > 0.0 && !o.motion.empty()) c.fail(at / "mass", "a dynamic obstacle (mass > 0) cannot also have a scripted motion");
  if (o.mass > 0.0 && o.shape.kind == ShapeSpec::Kind::plane) c.fail(at / "mass", "a plane cannot be dynamic");
  return o;
}

}  // namespace dexcloth::scene
