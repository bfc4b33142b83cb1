#include "scene/compile.hpp"

#include <limits>

#include "cloth/mesh.hpp"
#include "core/errors.hpp"

namespace dexcloth::scene {
namespace {

cloth::Material to_material(const MaterialSpec& m) {
  cloth::Material out;
  out.density = m.density;
  out.youngs_modulus = m.youngs_modulus;
  out.poisson = m.poisson;
  out.thickness = m.thickness;
  out.bending_stiffness = m.bending_stiffness;
  out.damping = m.damping;
  out.friction = m.friction;
  return out;
}

KeyTrack to_track(const std::vector<KeyframeSpec>& motion) {
  std::vector<Key> keys;
  keys.reserve(motion.size());
  for (const KeyframeSpec& k : motion) keys.push_back({k.t, k.translation, k.rotation_deg});
  return KeyTrack(std::move(keys));
}

/// Loads (or generates) a cloth's mesh in world space at rest.
cloth::ClothMesh load_mesh(const ClothSpec& spec, const std::string& pointer, ErrorList& errors,
                           const std::string& file) {
  cloth::ClothMesh mesh;
  if (spec.mesh.obj_path) {
    try {
      mesh = cloth::load_obj(*spec.mesh.obj_path);
    } catch (const InputRejected& e) {
      for (const InputError& err : e.errors().errors())
        errors.add(file, pointer + "/mesh/obj", err.to_string());
      return mesh;
    }
  } else {
    const auto& size = *spec.mesh.grid_size;
    const auto& res = *spec.mesh.grid_resolution;
    mesh = cloth::make_grid(size[0], size[1], res[0], res[1]);
  }
  cloth::transform_mesh(mesh, spec.transform.translation, spec.transform.rotation_deg);
  return mesh;
}

/// Resolves one handle to vertex indices and rest positions.
coupling::Handle compile_handle(const HandleSpec& spec, const cloth::ClothMesh& mesh,
                                const std::string& pointer, ErrorList& errors,
                                const std::string& file) {
  coupling::Handle handle;
  const auto n = static_cast<int>(mesh.x.rows());
  for (std::size_t k = 0; k < spec.vertices.size(); ++k) {
    const int i = spec.vertices[k];
    if (i < 0 || i >= n) {
      errors.add(file, pointer + "/vertices/" + std::to_string(k),
                 "vertex index " + std::to_string(i) + " is past the mesh (" + std::to_string(n) +
                     " vertices)");
      continue;
    }
    handle.vertices.push_back(i);
  }
  if (spec.box) {
    const Vec3& lo = (*spec.box)[0];
    const Vec3& hi = (*spec.box)[1];
    std::vector<int> inside;
    for (int i = 0; i < n; ++i) {
      const Vec3 p = mesh.x.row(i).transpose();
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) inside.push_back(i);
    }
    if (inside.empty())
      errors.add(file, pointer + "/box", "selects no vertex of the cloth at rest");
    handle.vertices.insert(handle.vertices.end(), inside.begin(), inside.end());
  }
  handle.rest.resize(static_cast<Eigen::Index>(handle.vertices.size()), 3);
  for (std::size_t k = 0; k < handle.vertices.size(); ++k)
    handle.rest.row(static_cast<Eigen::Index>(k)) = mesh.x.row(handle.vertices[k]);
  handle.motion = to_track(spec.motion);
  return handle;
}

}  // namespace

CompiledScene compile_scene(const SceneSpec& spec) {
  ErrorList errors;
  CompiledScene out;
  out.model.dt = spec.dt;
  out.model.gravity = spec.gravity;

  // Cloths: mesh, model, handles.
  for (std::size_t c = 0; c < spec.cloths.size(); ++c) {
    const ClothSpec& cs = spec.cloths[c];
    const std::string pointer = "/cloths/" + std::to_string(c);
    const cloth::ClothMesh mesh = load_mesh(cs, pointer, errors, spec.file);
    if (mesh.faces.rows() == 0) continue;
    coupling::ClothBody body;
    body.name = cs.name;
    try {
      body.model = cloth::build_model(mesh, to_material(cs.material));
    } catch (const InputRejected& e) {
      for (const InputError& err : e.errors().errors())
        errors.add(spec.file, pointer + "/mesh", err.message);
      continue;
    }
    body.x_rest = mesh.x;
    for (std::size_t k = 0; k < cs.handles.size(); ++k)
      body.handles.push_back(compile_handle(cs.handles[k], mesh,
                                            pointer + "/handles/" + std::to_string(k), errors,
                                            spec.file));
    out.model.cloths.push_back(std::move(body));
  }

  // Probes on cloths: the vertex nearest the given rest-pose world point.
  for (std::size_t p = 0; p < spec.probes.size(); ++p) {
    const ProbeSpec& ps = spec.probes[p];
    if (ps.cloth.empty()) continue;
    CompiledProbe probe{ps.name, -1, -1};
    for (std::size_t c = 0; c < out.model.cloths.size(); ++c) {
      if (out.model.cloths[c].name != ps.cloth) continue;
      const Points& x = out.model.cloths[c].x_rest;
      Eigen::Index best = 0;
      (x.rowwise() - ps.near.transpose()).rowwise().squaredNorm().minCoeff(&best);
      probe.cloth = static_cast<int>(c);
      probe.vertex = static_cast<int>(best);
    }
    if (probe.cloth >= 0) out.probes.push_back(probe);
  }

  if (!errors.empty()) throw InputRejected(std::move(errors));
  return out;
}

}  // namespace dexcloth::scene
