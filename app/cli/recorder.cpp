#include "recorder.hpp"

#include "io/obj_export.hpp"

namespace dexcloth::app {
namespace {

io::Pose to_pose(const Eigen::Isometry3d& X) {
  return {X.translation(), Eigen::Quaterniond(X.linear())};
}

}  // namespace

Recorder::Recorder(const std::filesystem::path& out, const scene::SceneSpec& spec,
                   const scene::CompiledScene& compiled, bool export_obj) {
  m_header.scene = spec.name;
  m_header.dt = spec.dt;
  m_header.frame_rate = spec.frame_rate;
  m_header.gravity = spec.gravity;
  m_header.metadata = {{"coupling", spec.coupling.mode}, {"scene_file", spec.file}};
  for (const coupling::ClothBody& body : compiled.model.cloths) {
    io::ClothInfo info;
    info.name = body.name;
    info.vertex_count = static_cast<int>(body.x_rest.rows());
    info.faces = body.model.faces;
    m_header.cloths.push_back(std::move(info));
  }
  // Rigid bodies: their collision meshes, expressed in the body frame at the start.
  const coupling::RigidSide& rigid = compiled.data.rigid;
  for (std::size_t m = 0; m < rigid.meshes.size(); ++m) {
    io::RigidShapeInfo shape;
    shape.name = rigid.meshes[m].name;
    shape.body = rigid.meshes[m].name;
    shape.type = io::ShapeType::mesh;
    const Eigen::Isometry3d X_BW = rigid.world->pose_W(rigid.mesh_body[m]).inverse();
    shape.mesh_vertices = (rigid.meshes[m].x * X_BW.linear().transpose()).rowwise() +
                          X_BW.translation().transpose();
    shape.mesh_faces = rigid.meshes[m].faces;
    // Hands and grippers in skin colour; obstacles keep the viewer's default.
    const int skeleton = rigid.world->body_skeleton(rigid.mesh_body[m]).index;
    for (const control::BuiltBody& b : rigid.bodies)
      if (b.skeleton.index == skeleton) shape.colour = Vec3(0.87, 0.72, 0.60);
    m_header.rigid_shapes.push_back(std::move(shape));
  }
  m_writer.open(out / "recording", m_header);
  if (export_obj) {
    m_obj_dir = out / "obj";
    std::filesystem::create_directories(m_obj_dir);
  }
}

void Recorder::write(const scene::CompiledScene& compiled) {
  const coupling::WorldData& data = compiled.data;
  const coupling::RigidSide& rigid = data.rigid;
  m_frame.t = data.time;
  m_frame.step_ms = data.last_step_ms;
  m_frame.cloth_positions.resize(data.cloths.size());
  for (std::size_t c = 0; c < data.cloths.size(); ++c) m_frame.cloth_positions[c] = data.cloths[c].x;
  m_frame.rigid_poses.clear();
  for (const rigid::BodyId b : rigid.mesh_body) m_frame.rigid_poses.push_back(to_pose(rigid.world->pose_W(b)));
  // Patches and the contacts DART found on them (how the fingers feel the cloth).
  m_frame.patches.clear();
  m_frame.contacts.clear();
  const rigid::PatchPool& pool = rigid.world->patches();
  for (int p = 0; p < pool.capacity(); ++p) {
    if (!pool.active(p)) continue;
    const Eigen::Isometry3d X = rigid.world->pose_W(pool.body(p));
    const coupling::RigidPatch* patch = static_cast<std::size_t>(p) < data.patches.size()
                                            ? &data.patches[static_cast<std::size_t>(p)]
                                            : nullptr;
    m_frame.patches.push_back({X.translation(), Eigen::Quaterniond(X.linear()),
                               patch ? patch->size : Vec3(0.01, 0.01, 0.001)});
    for (const rigid::ContactPoint& c : pool.contacts(p))
      m_frame.contacts.push_back({c.p_W, c.n_W, c.f_W});
  }
  m_writer.write_frame(m_frame);
  if (!m_obj_dir.empty()) io::export_frame_obj(m_header, m_frame, m_frames, m_obj_dir);
  ++m_frames;
}

void Recorder::close() { m_writer.close(); }

}  // namespace dexcloth::app
