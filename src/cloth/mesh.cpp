#include "cloth/mesh.hpp"

#include <string>

#include "core/errors.hpp"
#include "core/transform.hpp"

namespace dexcloth::cloth {

ClothMesh make_grid(double width, double height, int nx, int ny) {
  // Validate the grid description, reporting every problem at once.
  ErrorList errors;
  if (!(width > 0.0)) errors.add("grid", "size[0]", "must be > 0, got " + std::to_string(width));
  if (!(height > 0.0)) errors.add("grid", "size[1]", "must be > 0, got " + std::to_string(height));
  if (nx < 2) errors.add("grid", "resolution[0]", "must be >= 2, got " + std::to_string(nx));
  if (ny < 2) errors.add("grid", "resolution[1]", "must be >= 2, got " + std::to_string(ny));
  if (!errors.empty()) throw InputRejected(std::move(errors));

  ClothMesh mesh;
  // Vertices: row-major in (j, i), centred on the origin.
  mesh.x.resize(static_cast<Eigen::Index>(nx) * ny, 3);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double px = -0.5 * width + width * i / (nx - 1);
      const double py = -0.5 * height + height * j / (ny - 1);
      mesh.x.row(j * nx + i) << px, py, 0.0;
    }
  }

  // Faces: two per cell, diagonal alternating like a checkerboard.
  const Eigen::Index num_faces = 2 * static_cast<Eigen::Index>(nx - 1) * (ny - 1);
  mesh.faces.resize(num_faces, 3);
  Eigen::Index f = 0;
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        mesh.faces.row(f++) << v00, v10, v11;  // diagonal v00–v11
        mesh.faces.row(f++) << v00, v11, v01;
      } else {
        mesh.faces.row(f++) << v00, v10, v01;  // diagonal v10–v01
        mesh.faces.row(f++) << v10, v11, v01;
      }
    }
  }

  // Material coordinates: the flat local layout itself.
  mesh.face_uv.resize(num_faces, 6);
  for (Eigen::Index k = 0; k < num_faces; ++k) {
    for (int c = 0; c < 3; ++c) {
      mesh.face_uv(k, 2 * c) = mesh.x(mesh.faces(k, c), 0);
      mesh.face_uv(k, 2 * c + 1) = mesh.x(mesh.faces(k, c), 1);
    }
  }
  return mesh;
}

void transform_mesh(ClothMesh& mesh, const Vec3& translation, const Vec3& rotation_deg) {
  const Mat3 R = rotation_xyz_deg(rotation_deg);
  // Rows are points: x ← x·Rᵀ + t.
  mesh.x = (mesh.x * R.transpose()).rowwise() + translation.transpose();
}

}  // namespace dexcloth::cloth
