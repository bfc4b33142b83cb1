#pragma once
/// Cloth triangle meshes: positions, faces and material-space (rest) coordinates; grid
/// generation, OBJ loading and rigid placement.
#include <string>

#include "core/types.hpp"

namespace dexcloth::cloth {

/// |F|×6 material-space corner coordinates of each face: (u0 v0 u1 v1 u2 v2) [m].
using FaceUV = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// A cloth triangle mesh.
struct ClothMesh {
  Points x;         ///< |V|×3 world positions [m]
  Triangles faces;  ///< |F|×3 vertex indices, counter-clockwise seen from the front side
  /// |F|×6 material-space coordinates [m] of each face's 3 corners (u0 v0 u1 v1 u2 v2), or 0 rows:
  /// then each triangle's rest shape is its own 3D shape in `x`.
  FaceUV face_uv;
};

/// A `width`×`height` [m] sheet of `nx`×`ny` vertices in the local x–y plane (z = 0), centred on
/// the origin, x along the width. Vertex (i, j) has index j·nx + i. Cells are split along
/// alternating diagonals (checkerboard), faces wound counter-clockwise (normal +z). face_uv holds
/// the local (x, y) of each corner. Throws InputRejected unless width, height > 0 and nx, ny ≥ 2.
ClothMesh make_grid(double width, double height, int nx, int ny);

/// Reads a Wavefront OBJ file: `v`, `vt` and `f` records (f corners as v, v/vt, v/vt/vn or v//vn,
/// 1-based or negative relative indices); polygons are fan-triangulated; other records are
/// ignored. When every face corner has a `vt`, those are taken as face_uv in metres; otherwise
/// face_uv is empty. Throws InputRejected naming the file and line for an unreadable file, a bad
/// number, an index out of range, a face of fewer than 3 corners, or a file without faces.
ClothMesh load_obj(const std::string& path);

/// Places `mesh` rigidly: rotates positions by rotation_xyz_deg(`rotation_deg`) [deg] about the
/// origin, then adds `translation` [m]. face_uv (material space) is left unchanged.
void transform_mesh(ClothMesh& mesh, const Vec3& translation, const Vec3& rotation_deg);

}  // namespace dexcloth::cloth
