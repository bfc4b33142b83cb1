// Writes a short synthetic recording for the viewer tests: a sheet hanging from its top edge
// and swinging, a box on the ground and a capsule moving beside the sheet, 20 frames.
//   make_test_recording OUTDIR
#include <cmath>
#include <iostream>
#include <numbers>

#include "io/recording.hpp"

using namespace dexcloth;
using namespace dexcloth::io;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_test_recording OUTDIR\n";
    return 2;
  }
  constexpr int nx = 25, nz = 25, frames = 20;
  constexpr double width = 0.6, height = 0.6, top = 0.95, frame_rate = 25.0;

  // Header: one cloth (with material-space uvs), a box and a capsule.
  RecordingHeader h;
  h.scene = "viewer test: swinging sheet";
  h.dt = 0.005;
  h.frame_rate = frame_rate;
  ClothInfo sheet;
  sheet.name = "sheet";
  sheet.vertex_count = nx * nz;
  sheet.colour = Vec3(0.80, 0.22, 0.18);
  sheet.faces.resize(2 * (nx - 1) * (nz - 1), 3);
  sheet.face_uvs.resize(sheet.faces.rows(), 6);
  int f = 0;
  for (int j = 0; j + 1 < nz; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      for (const auto& tri : {Eigen::Vector3i(a, b, d), Eigen::Vector3i(a, d, c)}) {
        sheet.faces.row(f) = tri.transpose();
        for (int k = 0; k < 3; ++k)
          sheet.face_uvs.block<1, 2>(f, 2 * k) << width * (tri[k] % nx) / (nx - 1),
              height * (tri[k] / nx) / (nz - 1);
        ++f;
      }
    }
  }
  h.cloths.push_back(sheet);
  RigidShapeInfo box;
  box.name = "crate";
  box.body = "crate";
  box.type = ShapeType::box;
  box.size = Vec3(0.2, 0.2, 0.2);
  RigidShapeInfo capsule;
  capsule.name = "finger";
  capsule.body = "hand/finger";
  capsule.type = ShapeType::capsule;
  capsule.radius = 0.03;
  capsule.length = 0.12;
  capsule.colour = Vec3(0.85, 0.72, 0.6);
  h.rigid_shapes = {box, capsule};

  try {
    RecordingWriter writer(argv[1], h);
    for (int k = 0; k < frames; ++k) {
      const double t = k / frame_rate;
      const double swing = 0.45 * std::sin(2.0 * std::numbers::pi * t / (frames / frame_rate));
      RecordingFrame frame;
      frame.t = t;
      frame.step_ms = 2.5 + 0.1 * k;
      // The sheet hangs in the x–z plane from z = top and swings about its top edge, with a wave.
      Points x(nx * nz, 3);
      for (int v = 0; v < nx * nz; ++v) {
        const double u = width * (v % nx) / (nx - 1) - 0.5 * width;
        const double s = height * (v / nx) / (nz - 1);  // distance below the top edge
        const double wave = 0.035 * std::sin(16.0 * u + 8.0 * t) * (0.3 + s / height);
        x.row(v) << u, std::sin(swing) * s + wave, top - std::cos(swing) * s;
      }
      frame.cloth_positions.push_back(x);
      frame.rigid_poses.push_back({Vec3(0.55, 0.1, 0.1), Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3::UnitZ()))});
      frame.rigid_poses.push_back(
          {Vec3(-0.45, -0.15 + 0.01 * k, 0.6),
           Eigen::Quaterniond(Eigen::AngleAxisd(0.3 + 0.05 * k, Vec3::UnitX()))});
      // A contact and a patch where the capsule would touch the sheet, in the later frames.
      if (k >= 10) {
        frame.contacts.push_back({Vec3(-0.3, 0.0, 0.6), Vec3(0, 1, 0), Vec3(0, 0.5, 0.2)});
        frame.patches.push_back({Vec3(-0.3, 0.0, 0.6), Eigen::Quaterniond::Identity(), Vec3(0.04, 0.001, 0.03)});
      }
      writer.write_frame(frame);
    }
    writer.close();
  } catch (const std::exception& e) {
    std::cerr << "make_test_recording: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote " << argv[1] << " (" << frames << " frames)\n";
  return 0;
}
