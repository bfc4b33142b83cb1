#include <cstdint>
#include <optional>

#include "scene/parse_parts.hpp"

namespace dexcloth::scene {

namespace {

// `{"grid": {"size": [w,h], "resolution": [nx,ny]}}` or `{"obj": "path.obj"}`.
MeshSpec parse_mesh(Checker& c, const Json& v, const Pointer& at) {
  MeshSpec mesh;
  if (!c.require_object(v, at)) return mesh;
  c.check_keys(v, at, {"grid", "obj"});
  for (const auto& kind : one_of(c, v, at, {"grid", "obj"})) {
    const Pointer at_k = at / kind;
    if (kind == "obj") {
      mesh.obj_path = c.require_file(v[kind], at_k);
      continue;
    }
    const Json& grid = v[kind];
    if (!c.require_object(grid, at_k)) continue;
    c.check_keys(grid, at_k, {"size", "resolution"});
    if (const Json* s = c.member(grid, at_k, "size", Need::required)) {
      mesh.grid_size = c.require_numbers<2>(*s, at_k / "size", Rule::positive());
    }
    if (const Json* r = c.member(grid, at_k, "resolution", Need::required)) {
      mesh.grid_resolution = c.require_ints<2>(*r, at_k / "resolution", Rule::at_least(2));
    }
  }
  return mesh;
}

// Material parameters; absent keys keep the MaterialSpec defaults.
MaterialSpec parse_material(Checker& c, const Json& v, const Pointer& at) {
  MaterialSpec m;
  if (!c.require_object(v, at)) return m;
  c.check_keys(v, at,
               {"density", "youngs_modulus", "poisson", "thickness", "bending_stiffness", "damping",
                "friction", "strain_limits"});
  c.number_field(v, at, "density", Rule::positive(), m.density);
  c.number_field(v, at, "youngs_modulus", Rule::positive(), m.youngs_modulus);
  c.number_field(v, at, "poisson", Rule::between(0.0, false, 0.5, true), m.poisson);
  c.number_field(v, at, "thickness", Rule::positive(), m.thickness);
  c.number_field(v, at, "bending_stiffness", Rule::non_negative(), m.bending_stiffness);
  c.number_field(v, at, "damping", Rule::non_negative(), m.damping);
  c.number_field(v, at, "friction", Rule::non_negative(), m.friction);
  // Strain limits bound the singular values of the deformation gradient: 0 < min <= 1 <= max.
  if (const Json* s = c.member(v, at, "strain_limits", Need::optional)) {
    const Pointer at_s = at / "strain_limits";
    if (const auto lim = c.require_numbers<2>(*s, at_s, Rule::any())) {
      if ((*lim)[0] > 0.0 && (*lim)[0] <= 1.0 && (*lim)[1] >= 1.0) {
        m.strain_limits = lim;
      } else {
        c.fail(at_s, "must satisfy 0 < min <= 1 <= max, got " + s->dump());
      }
    }
  }
  return m;
}

// `{"min": [..], "max": [..]}` with min <= max componentwise.
std::optional<std::array<Vec3, 2>> parse_box(Checker& c, const Json& v, const Pointer& at) {
  if (!c.require_object(v, at)) return std::nullopt;
  c.check_keys(v, at, {"min", "max"});
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
  // Both corners are read (and reported) before giving up on the box.
  const bool lo_ok = c.vec3_field(v, at, "min", lo, Need::required);
  const bool hi_ok = c.vec3_field(v, at, "max", hi, Need::required);
  if (!lo_ok || !hi_ok) return std::nullopt;
  bool ordered = true;
  for (int k = 0; k < 3; ++k) {
    if (lo[k] > hi[k]) {
      c.fail(at, "min must be <= max componentwise, got min[" + std::to_string(k) +
                     "] = " + Json(lo[k]).dump() + " > max[" + std::to_string(k) +
                     "] = " + Json(hi[k]).dump());
      ordered = false;
    }
  }
  if (!ordered) return std::nullopt;
  return std::array<Vec3, 2>{lo, hi};
}

// One handle; `vertex_count` is known for grid meshes and bounds the explicit indices.
HandleSpec parse_handle(Checker& c, const Json& v, const Pointer& at,
                        std::optional<std::int64_t> vertex_count) {
  HandleSpec h;
  if (!c.require_object(v, at)) return h;
  c.check_keys(v, at, {"vertices", "box", "motion", "release", "slide"});
  for (const auto& kind : one_of(c, v, at, {"vertices", "box"})) {
    const Pointer at_k = at / kind;
    if (kind == "box") {
      h.box = parse_box(c, v[kind], at_k);
      continue;
    }
    const Json& list = v[kind];
    if (!c.require_array(list, at_k)) continue;
    if (list.empty()) c.fail(at_k, "must list at least one vertex");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto idx = c.require_int(list[i], at_k / i, Rule::non_negative());
      if (!idx) continue;
      if (vertex_count && *idx >= *vertex_count) {
        c.fail(at_k / i, "vertex index " + std::to_string(*idx) + " out of range: the grid has " +
                             std::to_string(*vertex_count) + " vertices");
        continue;
      }
      h.vertices.push_back(*idx);
    }
  }
  if (const Json* m = c.member(v, at, "motion", Need::optional)) {
    h.motion = parse_motion(c, *m, at / "motion", false);
  }
  if (const Json* r = c.member(v, at, "release", Need::optional)) {
    h.release = c.require_number(*r, at / "release", Rule::non_negative());
  }
  // Rings on a rod: the vertices slide freely along this direction.
  if (const Json* s = c.member(v, at, "slide", Need::optional)) {
    if (const auto d = c.require_vec3(*s, at / "slide")) {
      if (d->norm() > 0.0)
        h.slide = d->normalized();
      else
        c.fail(at / "slide", "must be a non-zero direction, got [0, 0, 0]");
    }
  }
  return h;
}

}  // namespace

ClothSpec parse_cloth(Checker& c, const Json& v, const Pointer& at) {
  ClothSpec cloth;
  if (!c.require_object(v, at)) return cloth;
  c.check_keys(v, at, {"name", "mesh", "transform", "material", "handles"});
  c.string_field(v, at, "name", cloth.name, Need::required);
  if (const Json* m = c.member(v, at, "mesh", Need::required)) {
    cloth.mesh = parse_mesh(c, *m, at / "mesh");
  }
  if (const Json* t = c.member(v, at, "transform", Need::optional)) {
    cloth.transform = parse_transform(c, *t, at / "transform");
  }
  if (const Json* m = c.member(v, at, "material", Need::optional)) {
    cloth.material = parse_material(c, *m, at / "material");
  }
  // Grid meshes have a known vertex count (nx·ny) that bounds handle indices.
  std::optional<std::int64_t> vertex_count;
  if (cloth.mesh.grid_resolution && !cloth.mesh.obj_path) {
    vertex_count = static_cast<std::int64_t>((*cloth.mesh.grid_resolution)[0]) *
                   (*cloth.mesh.grid_resolution)[1];
  }
  if (const Json* hs = c.member(v, at, "handles", Need::optional)) {
    const Pointer at_h = at / "handles";
    if (c.require_array(*hs, at_h)) {
      for (std::size_t i = 0; i < hs->size(); ++i) {
        cloth.handles.push_back(parse_handle(c, (*hs)[i], at_h / i, vertex_count));
      }
    }
  }
  return cloth;
}

}  // namespace dexcloth::scene
