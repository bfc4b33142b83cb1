#pragma once
/// Test fixtures for recordings: a header with every kind of cloth and shape, seeded frames,
/// and a fresh output folder per test.
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "io/recording.hpp"

namespace dexcloth::io::testing {

/// An empty folder under the build tree named after the running test.
inline std::filesystem::path fresh_dir(const std::string& tag = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(DEXCLOTH_BINARY_DIR) / "test_output" /
                                    "io" / (std::string(info->test_suite_name()) + "." +
                                             info->name() + tag);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// nx×ny grid of triangles in the x–y plane, size w×h [m], with material-space uvs.
inline ClothInfo grid_cloth(const std::string& name, int nx, int ny, double w, double h,
                            bool with_uv) {
  ClothInfo c;
  c.name = name;
  c.vertex_count = nx * ny;
  c.faces.resize(2 * (nx - 1) * (ny - 1), 3);
  if (with_uv) c.face_uvs.resize(c.faces.rows(), 6);
  int f = 0;
  const auto uv = [&](int v) { return Vec2(w * (v % nx) / (nx - 1), h * (v / nx) / (ny - 1)); };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = a + 1, c2 = a + nx, d = c2 + 1;
      for (const auto& tri : {Eigen::Vector3i(a, b, d), Eigen::Vector3i(a, d, c2)}) {
        c.faces.row(f) = tri.transpose();
        if (with_uv)
          for (int k = 0; k < 3; ++k) c.face_uvs.block<1, 2>(f, 2 * k) = uv(tri[k]).transpose();
        ++f;
      }
    }
  }
  return c;
}

/// Positions of a `grid_cloth` lying flat at height z.
inline Points grid_positions(int nx, int ny, double w, double h, double z) {
  Points x(nx * ny, 3);
  for (int v = 0; v < nx * ny; ++v)
    x.row(v) << w * (v % nx) / (nx - 1) - 0.5 * w, h * (v / nx) / (ny - 1) - 0.5 * h, z;
  return x;
}

/// A rigid shape of `type` named `name` on a body of the same name, default dimensions.
inline RigidShapeInfo shape(const std::string& name, ShapeType type) {
  RigidShapeInfo s;
  s.name = name;
  s.body = name;
  s.type = type;
  return s;
}

/// A header with two cloths (one with uvs) and one rigid shape of every type.
inline RecordingHeader sample_header() {
  RecordingHeader h;
  h.scene = "unit test";
  h.dt = 0.005;
  h.frame_rate = 50.0;
  h.cloths.push_back(grid_cloth("sheet", 9, 7, 0.4, 0.3, true));
  h.cloths.push_back(grid_cloth("scrap/2", 3, 3, 0.1, 0.1, false));
  h.cloths.back().colour = Vec3(0.2, 0.4, 0.9);

  RigidShapeInfo box = shape("table", ShapeType::box);
  box.size = Vec3(1.0, 0.6, 0.04);
  RigidShapeInfo sphere = shape("ball", ShapeType::sphere);
  sphere.radius = 0.05;
  RigidShapeInfo capsule = shape("index 2", ShapeType::capsule);
  capsule.body = "hand/index_2";
  capsule.radius = 0.009;
  capsule.length = 0.025;
  RigidShapeInfo plane = shape("floor", ShapeType::plane);
  plane.body = "world";
  plane.size = Vec3(4.0, 3.0, 0.0);
  RigidShapeInfo mesh = shape("wedge", ShapeType::mesh);
  mesh.mesh_vertices.resize(4, 3);
  mesh.mesh_vertices << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1;
  mesh.mesh_faces.resize(4, 3);
  mesh.mesh_faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  h.rigid_shapes = {box, sphere, capsule, plane, mesh};
  h.metadata = {{"coupling", "bai-liu"}};
  return h;
}

/// Frame k of `header` with seeded random positions (not float-representable), k % 3 contacts
/// and k % 2 patches.
inline RecordingFrame sample_frame(const RecordingHeader& header, int k) {
  std::mt19937 rng(1234u + static_cast<unsigned>(k));
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const auto quat = [&] { return Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized(); };
  RecordingFrame f;
  f.t = 0.02 * k + 1e-13;
  f.step_ms = 3.25 + u(rng);
  for (const ClothInfo& c : header.cloths) {
    Points x(c.vertex_count, 3);
    for (int i = 0; i < c.vertex_count; ++i) x.row(i) = vec().transpose();
    f.cloth_positions.push_back(x);
  }
  for (std::size_t s = 0; s < header.rigid_shapes.size(); ++s) f.rigid_poses.push_back({vec(), quat()});
  for (int i = 0; i < k % 3; ++i) f.contacts.push_back({vec(), vec().normalized(), vec()});
  for (int i = 0; i < k % 2; ++i) f.patches.push_back({vec(), quat(), vec().cwiseAbs()});
  return f;
}

}  // namespace dexcloth::io::testing
