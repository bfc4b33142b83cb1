#include "scene/compile.hpp"

#include <limits>

#include <filesystem>

#include "cloth/mesh.hpp"
#include "core/errors.hpp"
#include "core/transform.hpp"

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

Eigen::Isometry3d to_pose(const Vec3& translation, const Mat3& rotation) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rotation;
  X.translation() = translation;
  return X;
}

/// Handle keyframes: translation offsets from the rest position.
std::vector<rigid::PoseKeyframe> handle_track(const std::vector<KeyframeSpec>& motion) {
  std::vector<rigid::PoseKeyframe> keys;
  for (const KeyframeSpec& k : motion) keys.push_back({k.t, to_pose(k.translation, Mat3::Identity())});
  return keys;
}

/// A scene obstacle as a DART prop. Motion keys are offsets from `transform`: the obstacle turns
/// about its own origin by the key's rotation and moves by the key's translation.
rigid::PropSpec to_prop(const ObstacleSpec& o) {
  rigid::PropSpec prop;
  prop.name = o.name;
  switch (o.shape.kind) {
    case ShapeSpec::Kind::box: prop.shape = rigid::PropSpec::Shape::box; break;
    case ShapeSpec::Kind::sphere: prop.shape = rigid::PropSpec::Shape::sphere; break;
    case ShapeSpec::Kind::capsule: prop.shape = rigid::PropSpec::Shape::capsule; break;
    case ShapeSpec::Kind::plane: prop.shape = rigid::PropSpec::Shape::plane; break;
    case ShapeSpec::Kind::obj: prop.shape = rigid::PropSpec::Shape::mesh; break;
  }
  prop.size = o.shape.kind == ShapeSpec::Kind::plane ? Vec3(20.0, 20.0, 0.0) : o.shape.box_size;
  prop.radius = o.shape.radius;
  prop.length = o.shape.length;
  prop.mesh_path = o.shape.obj_path;
  const Mat3 R = rotation_xyz_deg(o.transform.rotation_deg);
  prop.X_WP = to_pose(o.transform.translation, R);
  for (const KeyframeSpec& k : o.motion)
    prop.motion.push_back(
        {k.t, to_pose(o.transform.translation + k.translation, rotation_xyz_deg(k.rotation_deg) * R)});
  prop.friction = o.friction;
  prop.mass = o.mass;
  return prop;
}

/// The rigid world: props, then skeletons with their controllers, and which body each exported
/// collision mesh stands for.
coupling::RigidSide build_rigid(const SceneSpec& spec, ErrorList& errors) {
  coupling::RigidSide side;
  rigid::RigidWorldOptions options;
  options.time_step = spec.dt;
  options.gravity_W = spec.gravity;
  options.substeps = spec.coupling.rigid_substeps;
  side.world = std::make_unique<rigid::RigidWorld>(options);
  // Skeletons the cloth pushes back on (paper §5's rigid patches): the hands and grippers of
  // `bodies`, and dynamic obstacles (a box on a tablecloth, an object in a sling).
  std::vector<int> coupled_skeletons;
  for (const ObstacleSpec& o : spec.obstacles) {
    const rigid::SkeletonId s = side.world->add_prop(to_prop(o));
    if (o.mass > 0.0) coupled_skeletons.push_back(s.index);
  }
  const std::string scene_dir = std::filesystem::path(spec.file).parent_path().string();
  std::vector<control::BodySpec> body_specs;
  for (std::size_t b = 0; b < spec.bodies.size(); ++b)
    body_specs.push_back(control::parse_body_spec(spec.bodies[b], spec.file,
                                                  "/bodies/" + std::to_string(b), scene_dir, errors));
  if (!errors.empty()) return side;
  for (const control::BodySpec& body : body_specs) {
    try {
      side.bodies.push_back(control::build_body(*side.world, body, spec.file));
      coupled_skeletons.push_back(side.bodies.back().skeleton.index);
    } catch (const InputRejected& e) {
      for (const InputError& err : e.errors().errors()) errors.add(err.file, err.pointer, err.message);
    }
  }
  side.world->export_obstacle_meshes(side.meshes);
  for (const rigid::ObstacleMesh& mesh : side.meshes) {
    const rigid::BodyId body = side.world->body(mesh.name);
    side.mesh_body.push_back(body);
    const int skeleton = side.world->body_skeleton(body).index;
    side.mesh_coupled.push_back(std::find(coupled_skeletons.begin(), coupled_skeletons.end(),
                                           skeleton) != coupled_skeletons.end());
  }
  return side;
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
  handle.motion = handle_track(spec.motion);
  if (spec.release) handle.release = *spec.release;
  if (spec.slide) handle.slide = *spec.slide;
  return handle;
}

}  // namespace

CompiledScene compile_scene(const SceneSpec& spec) {
  ErrorList errors;
  CompiledScene out;
  out.model.dt = spec.dt;
  out.model.gravity = spec.gravity;
  out.model.mode = spec.coupling.mode == "kinematic" ? coupling::CouplingMode::kinematic
                                                     : coupling::CouplingMode::bai_liu;
  out.model.thickness = spec.collision.thickness;
  out.model.self_collision = spec.collision.self_collision;
  out.model.clusters = {spec.coupling.cluster_distance, spec.coupling.cluster_normal_deg,
                        spec.coupling.cluster_offset};

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
      if (spec.solver.factor_precision == "single")
        body.model.solver.factor_precision = cloth::Precision::single_precision;
      body.model.solver.refine_tolerance = spec.solver.refine_tolerance;
    } catch (const InputRejected& e) {
      for (const InputError& err : e.errors().errors())
        errors.add(spec.file, pointer + "/mesh", err.message);
      continue;
    }
    body.x_rest = mesh.x;
    body.strain_limits = cs.material.strain_limits;
    for (std::size_t k = 0; k < cs.handles.size(); ++k)
      body.handles.push_back(compile_handle(cs.handles[k], mesh,
                                            pointer + "/handles/" + std::to_string(k), errors,
                                            spec.file));
    out.model.cloths.push_back(std::move(body));
  }

  // The rigid side: DART props and skeletons.
  coupling::RigidSide rigid = build_rigid(spec, errors);

  // Probes: on a cloth, the vertex nearest the given rest-pose world point; on a body, a point.
  for (std::size_t p = 0; p < spec.probes.size(); ++p) {
    const ProbeSpec& ps = spec.probes[p];
    if (ps.cloth.empty()) {
      if (rigid.world && !rigid.world->find_body(ps.body))
        errors.add(spec.file, "/probes/" + std::to_string(p) + "/body",
                   "no body \"" + ps.body + "\" in the scene");
      else
        out.probes.push_back({ps.name, -1, -1, ps.body, ps.point});
      continue;
    }
    CompiledProbe probe{ps.name, -1, -1, "", Vec3::Zero()};
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
  out.data = coupling::make_data(out.model, std::move(rigid));
  return out;
}

}  // namespace dexcloth::scene
