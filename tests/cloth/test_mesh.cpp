// Grid generation, rigid placement and the OBJ reader (including rejection of bad files).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "cloth/mesh.hpp"
#include "core/errors.hpp"
#include "core/transform.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

namespace {

/// Writes `text` to a fresh file under the build tree's test outputs and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  const std::filesystem::path dir =
      std::filesystem::path(DEXCLOTH_BINARY_DIR) / "test_output" / "cloth" / "mesh";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

/// The message of the InputRejected thrown by load_obj(path), or "" if none was thrown.
std::string rejection(const std::string& path) {
  try {
    load_obj(path);
  } catch (const InputRejected& e) {
    return e.what();
  }
  return "";
}

/// Whether face f has the undirected edge (a, b).
bool has_edge(const Triangles& faces, int f, int a, int b) {
  for (int c = 0; c < 3; ++c) {
    const int p = faces(f, c), q = faces(f, (c + 1) % 3);
    if ((p == a && q == b) || (p == b && q == a)) return true;
  }
  return false;
}

}  // namespace

TEST(Grid, CountsPositionsAndWinding) {
  const ClothMesh m = make_grid(2.0, 1.0, 5, 3);
  ASSERT_EQ(m.x.rows(), 15);
  ASSERT_EQ(m.faces.rows(), 2 * 4 * 2);
  ASSERT_EQ(m.face_uv.rows(), m.faces.rows());
  // Vertex (i, j) = j·nx + i, centred, z = 0.
  EXPECT_EQ(m.x.row(0), Eigen::RowVector3d(-1.0, -0.5, 0.0));
  EXPECT_EQ(m.x.row(14), Eigen::RowVector3d(1.0, 0.5, 0.0));
  EXPECT_EQ(m.x.row(1 * 5 + 2), Eigen::RowVector3d(0.0, 0.0, 0.0));
  // Every face counter-clockwise (normal +z) with the cell's area / 2, uv = local x, y.
  for (int f = 0; f < m.faces.rows(); ++f) {
    const Vec3 a = m.x.row(m.faces(f, 0)), b = m.x.row(m.faces(f, 1)), c = m.x.row(m.faces(f, 2));
    EXPECT_NEAR((b - a).cross(c - a).z(), 2.0 * 0.5 * 0.5 * 0.5, 1e-15);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m.face_uv(f, 2 * k), m.x(m.faces(f, k), 0));
      EXPECT_EQ(m.face_uv(f, 2 * k + 1), m.x(m.faces(f, k), 1));
    }
  }
}

TEST(Grid, DiagonalsAlternateLikeACheckerboard) {
  const int nx = 4, ny = 3;
  const ClothMesh m = make_grid(1.0, 1.0, nx, ny);
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int cell = j * (nx - 1) + i;
      const int v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      const bool main_diagonal = (i + j) % 2 == 0;
      for (int f : {2 * cell, 2 * cell + 1}) {
        EXPECT_EQ(has_edge(m.faces, f, v00, v11), main_diagonal) << "cell " << i << "," << j;
        EXPECT_EQ(has_edge(m.faces, f, v10, v01), !main_diagonal) << "cell " << i << "," << j;
      }
    }
  }
}

TEST(Grid, RejectsBadSizes) {
  EXPECT_THROW(make_grid(0.0, 1.0, 3, 3), InputRejected);
  EXPECT_THROW(make_grid(1.0, -1.0, 3, 3), InputRejected);
  EXPECT_THROW(make_grid(1.0, 1.0, 1, 3), InputRejected);
  try {
    make_grid(-1.0, 1.0, 1, 3);
    FAIL() << "no throw";
  } catch (const InputRejected& e) {
    EXPECT_EQ(e.errors().size(), 2u);  // every problem reported
  }
}

TEST(Transform, RotationAppliesXThenYThenZ) {
  // Rx(90°) takes y to z, then Ry(90°) takes z to x.
  const Mat3 R = rotation_xyz_deg(Vec3(90, 90, 0));
  EXPECT_LE((R * Vec3::UnitY() - Vec3::UnitX()).norm(), 1e-15);
  const Mat3 Rz = rotation_xyz_deg(Vec3(0, 0, 90));
  EXPECT_LE((Rz * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-15);
  const Mat3 G = rotation_xyz_deg(Vec3(10, -20, 30));
  EXPECT_LE((G * G.transpose() - Mat3::Identity()).norm(), 1e-15);
  EXPECT_NEAR(G.determinant(), 1.0, 1e-15);
}

TEST(Transform, MeshIsRotatedThenTranslated) {
  ClothMesh m = make_grid(2.0, 1.0, 3, 2);
  const FaceUV uv = m.face_uv;
  transform_mesh(m, Vec3(1, 2, 3), Vec3(90, 0, 0));
  // (1, 0.5, 0) → Rx(90°) → (1, 0, 0.5) → + t.
  EXPECT_LE((Vec3(m.x.row(5)) - Vec3(2, 2, 3.5)).norm(), 1e-15);
  EXPECT_EQ(m.face_uv, uv);
}

TEST(Obj, ReadsTrianglesQuadsTexturesAndNegativeIndices) {
  const std::string path = write_temp("quad.obj",
                                      "# a unit quad and a triangle\n"
                                      "o sheet\n"
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\r\n"
                                      "vt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\n"
                                      "vn 0 0 1\n"
                                      "s off\n"
                                      "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                                      "v 2 0 0\nvt 4 0\n"
                                      "f -4/-4 -1/-1 3/3   # relative indices\n");
  const ClothMesh m = load_obj(path);
  ASSERT_EQ(m.x.rows(), 5);
  ASSERT_EQ(m.faces.rows(), 3);
  EXPECT_EQ(m.faces.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.faces.row(2), Eigen::RowVector3i(1, 4, 2));
  ASSERT_EQ(m.face_uv.rows(), 3);
  EXPECT_EQ(m.face_uv.row(1), (Eigen::Matrix<double, 1, 6>() << 0, 0, 2, 2, 0, 2).finished());
  EXPECT_EQ(m.face_uv.row(2), (Eigen::Matrix<double, 1, 6>() << 2, 0, 4, 0, 2, 2).finished());
  EXPECT_EQ(m.x.row(4), Eigen::RowVector3d(2, 0, 0));
}

TEST(Obj, FaceUvIsEmptyUnlessEveryCornerHasTexture) {
  const std::string path = write_temp("mixed.obj",
                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                      "f 1/1 2/2 3/3\nf 2//1 4//1 3//1\n");
  const ClothMesh m = load_obj(path);
  EXPECT_EQ(m.faces.rows(), 2);
  EXPECT_EQ(m.face_uv.rows(), 0);
  EXPECT_EQ(m.faces.row(1), Eigen::RowVector3i(1, 3, 2));
}

TEST(Obj, RejectsBadFilesNamingFileAndLine) {
  const std::string missing = write_temp("exists.obj", "") + ".missing";
  EXPECT_NE(rejection(missing).find(missing + ": cannot open"), std::string::npos);

  const std::string bad_number =
      write_temp("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 1 x 0\nf 1 2 3\n");
  EXPECT_NE(rejection(bad_number).find(bad_number + ": line 3: bad 'v' record"), std::string::npos)
      << rejection(bad_number);

  for (const char* number : {"nan", "inf", "-inf", "1e999"}) {
    const std::string path = write_temp(
        "non_finite.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 ") + number + " 0\nf 1 2 3\n");
    EXPECT_NE(rejection(path).find(path + ": line 3: bad 'v' record: expected 3 finite numbers"),
              std::string::npos)
        << number << ": " << rejection(path);
  }

  const std::string range = write_temp("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
  EXPECT_NE(rejection(range).find(range + ": line 5: vertex index 4 out of range"),
            std::string::npos)
      << rejection(range);

  const std::string negative = write_temp("negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
  EXPECT_NE(rejection(negative).find(negative + ": line 3: index out of range"), std::string::npos)
      << rejection(negative);

  const std::string two = write_temp("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
  EXPECT_NE(rejection(two).find(two + ": line 4: face needs at least 3 corners"),
            std::string::npos);

  const std::string zero = write_temp("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_NE(rejection(zero).find(zero + ": line 4: bad face corner '0'"), std::string::npos)
      << rejection(zero);

  const std::string vt_range =
      write_temp("vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n");
  EXPECT_NE(rejection(vt_range).find(vt_range + ": line 5: texture index 2 out of range"),
            std::string::npos)
      << rejection(vt_range);

  const std::string twice =
      write_temp("twice.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 3 1 2\n");
  EXPECT_NE(rejection(twice).find(twice + ": line 7: triangle repeats the one on line 5"),
            std::string::npos)
      << rejection(twice);

  const std::string no_faces = write_temp("empty.obj", "v 0 0 0\n# nothing else\n");
  EXPECT_NE(rejection(no_faces).find(no_faces + ": no faces"), std::string::npos);
}
