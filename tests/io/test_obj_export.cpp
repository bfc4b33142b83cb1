#include <gtest/gtest.h>

#include <fstream>
#include <numbers>

#include "io/obj_export.hpp"
#include "recording_fixtures.hpp"

using namespace dexcloth;
using namespace dexcloth::io;
using namespace dexcloth::io::testing;
namespace fs = std::filesystem;

namespace {

// Signed volume of a closed triangle mesh: positive when faces wind counter-clockwise outward.
double signed_volume(const ObjMesh& m) {
  double v = 0.0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const Vec3 a = m.vertices.row(m.faces(f, 0)).transpose();
    const Vec3 b = m.vertices.row(m.faces(f, 1)).transpose();
    const Vec3 c = m.vertices.row(m.faces(f, 2)).transpose();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// Every face's stored normals point the same way as its winding.
void expect_normals_follow_winding(const ObjMesh& m) {
  ASSERT_EQ(m.face_normals.rows(), m.faces.rows());
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const Vec3 a = m.vertices.row(m.faces(f, 0)).transpose();
    const Vec3 b = m.vertices.row(m.faces(f, 1)).transpose();
    const Vec3 c = m.vertices.row(m.faces(f, 2)).transpose();
    const Vec3 n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(n.normalized().dot(m.normals.row(m.face_normals(f, k)).transpose()), 0.5)
          << "face " << f;
  }
}

}  // namespace

TEST(ObjExport, NormalsAreAreaWeighted) {
  // Vertex 0 is shared by a large triangle facing +z (area 50) and a small one facing -y
  // (area 0.5): its normal is (0, -0.5, 50) normalised.
  Points x(5, 3);
  x << 0, 0, 0, 10, 0, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1;
  Triangles f(2, 3);
  f << 0, 1, 2, 0, 3, 4;
  const Points n = area_weighted_normals(x, f);
  const Vec3 expected = Vec3(0, -0.5, 50).normalized();
  EXPECT_LT((n.row(0).transpose() - expected).norm(), 1e-14);
  EXPECT_LT((n.row(1).transpose() - Vec3::UnitZ()).norm(), 1e-14);
  EXPECT_LT((n.row(3).transpose() + Vec3::UnitY()).norm(), 1e-14);
}

TEST(ObjExport, ClothFrameReadsBackToTheSamePositions) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  const RecordingFrame frame = sample_frame(h, 7);
  const auto files = export_frame_obj(h, frame, 7, dir / "obj");

  // Sequence names Blender can import: <stem>_<frame:06>.obj, cloths first.
  ASSERT_EQ(files.size(), 7u);
  EXPECT_EQ(files[0].filename(), "sheet_000007.obj");
  EXPECT_EQ(files[1].filename(), "scrap_2_000007.obj");
  EXPECT_EQ(files[4].filename(), "index_2_000007.obj");

  // Positions: the file holds the shortest decimal of each float32, so parsing it back gives the
  // same float32 bit for bit. Against the double input the error is at most one float32 ulp
  // (half from rounding to float, up to half from the shortest decimal): 2^-23 relative.
  const ObjMesh m = read_obj(files[0]);
  const Points& x = frame.cloth_positions[0];
  ASSERT_EQ(m.vertices.rows(), x.rows());
  ASSERT_EQ(m.faces, h.cloths[0].faces);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(static_cast<float>(m.vertices(i, d)), static_cast<float>(x(i, d)));
      EXPECT_LE(std::abs(m.vertices(i, d) - x(i, d)), std::abs(x(i, d)) * 0x1p-23);
    }
  }

  // Normals: one per vertex, the area-weighted ones (to float precision).
  const Points n = area_weighted_normals(x, h.cloths[0].faces);
  ASSERT_EQ(m.normals.rows(), x.rows());
  EXPECT_EQ(m.face_normals, m.faces);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    EXPECT_LT((m.normals.row(i) - n.row(i)).norm(), 1e-6) << i;

  // Material-space uvs: a seamless grid has one vt per vertex, equal to its rest position.
  ASSERT_EQ(m.uvs.rows(), x.rows());
  ASSERT_EQ(m.face_uvs.rows(), m.faces.rows());
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 2; ++d)
        EXPECT_EQ(static_cast<float>(m.uvs(m.face_uvs(f, k), d)),
                  static_cast<float>(h.cloths[0].face_uvs(f, 2 * k + d)));

  // The cloth without uvs has no vt.
  const ObjMesh scrap = read_obj(files[1]);
  EXPECT_EQ(scrap.uvs.rows(), 0);
  EXPECT_EQ(scrap.vertices.rows(), 9);
}

TEST(ObjExport, RigidShapesAreClosedAndPlaced) {
  const RecordingHeader h = sample_header();
  const Pose X_WS{Vec3(0.3, -0.2, 1.1),
                  Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()))};
  const Mat3 R = X_WS.orientation.toRotationMatrix();
  const auto local = [&](const ObjMesh& m, Eigen::Index i) {
    return Vec3(R.transpose() * (m.vertices.row(i).transpose() - X_WS.position));
  };

  // Box: 24 corners on the faces, exact volume, flat outward normals.
  const ObjMesh box = shape_obj(h.rigid_shapes[0], X_WS);
  EXPECT_EQ(box.vertices.rows(), 24);
  EXPECT_EQ(box.faces.rows(), 12);
  EXPECT_NEAR(signed_volume(box), 1.0 * 0.6 * 0.04, 1e-12);
  for (Eigen::Index i = 0; i < 24; ++i)
    EXPECT_LT((local(box, i).cwiseAbs() - Vec3(0.5, 0.3, 0.02)).norm(), 1e-12);
  expect_normals_follow_winding(box);

  // Sphere: vertices on the sphere; volume within 5 % of 4/3 π r³ at 24 segments.
  const double r = 0.05;
  const ObjMesh sphere = shape_obj(h.rigid_shapes[1], X_WS, 24);
  for (Eigen::Index i = 0; i < sphere.vertices.rows(); ++i)
    EXPECT_NEAR(local(sphere, i).norm(), r, 1e-12);
  EXPECT_NEAR(signed_volume(sphere), 4.0 / 3.0 * std::numbers::pi * r * r * r,
              0.05 * 4.0 / 3.0 * std::numbers::pi * r * r * r);
  expect_normals_follow_winding(sphere);

  // Capsule along local z: every vertex at distance r from the axis segment.
  const RigidShapeInfo& cap = h.rigid_shapes[2];
  const ObjMesh capsule = shape_obj(cap, X_WS, 16);
  for (Eigen::Index i = 0; i < capsule.vertices.rows(); ++i) {
    const Vec3 p = local(capsule, i);
    const double z = std::clamp(p.z(), -0.5 * cap.length, 0.5 * cap.length);
    EXPECT_NEAR((p - Vec3(0, 0, z)).norm(), cap.radius, 1e-12);
  }
  const double cap_volume = std::numbers::pi * cap.radius * cap.radius *
                            (cap.length + 4.0 / 3.0 * cap.radius);
  EXPECT_NEAR(signed_volume(capsule), cap_volume, 0.06 * cap_volume);
  expect_normals_follow_winding(capsule);

  // Plane: one quad of the display size, normal = local +z.
  const ObjMesh plane = shape_obj(h.rigid_shapes[3], X_WS);
  EXPECT_EQ(plane.faces.rows(), 2);
  EXPECT_LT((plane.normals.row(0).transpose() - R.col(2)).norm(), 1e-12);
  EXPECT_NEAR(local(plane, 2).x(), 2.0, 1e-12);
  EXPECT_NEAR(local(plane, 2).y(), 1.5, 1e-12);

  // Mesh: a closed tetrahedron wound outward.
  const ObjMesh tet = shape_obj(h.rigid_shapes[4], X_WS);
  EXPECT_NEAR(signed_volume(tet), 0.1 * 0.1 * 0.1 / 6.0, 1e-12);
  expect_normals_follow_winding(tet);
}

TEST(ObjExport, StemsAreSafeAndUnique) {
  RecordingHeader h;
  h.cloths.push_back(grid_cloth("shirt", 2, 2, 1, 1, false));
  h.cloths.push_back(grid_cloth("shirt?", 2, 2, 1, 1, false));
  h.rigid_shapes.push_back(shape("shirt", ShapeType::sphere));
  EXPECT_EQ(obj_stems(h), (std::vector<std::string>{"shirt", "shirt_", "shirt_2"}));
}

TEST(ObjExport, SequenceExportWritesEveryFrame) {
  const fs::path dir = fresh_dir();
  const RecordingHeader h = sample_header();
  {
    RecordingWriter w(dir / "rec", h);
    for (int k = 0; k < 3; ++k) w.write_frame(sample_frame(h, k));
  }
  const RecordingReader r(dir / "rec");
  EXPECT_THROW(export_obj_sequence(r, dir / "obj", {0, 3}), std::out_of_range);
  EXPECT_FALSE(fs::exists(dir / "obj"));
  EXPECT_EQ(export_obj_sequence(r, dir / "obj"), 3 * 7);
  EXPECT_TRUE(fs::exists(dir / "obj" / "wedge_000002.obj"));
  const ObjMesh m = read_obj(dir / "obj" / "sheet_000002.obj");
  EXPECT_EQ(static_cast<float>(m.vertices(5, 1)), static_cast<float>(sample_frame(h, 2).cloth_positions[0](5, 1)));
}

TEST(ObjReader, ReadsPolygonsAndNegativeIndicesAndReportsBadLines) {
  const fs::path dir = fresh_dir();
  std::ofstream(dir / "quad.obj") << "# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
                                     "f -4//1 -3//1 -2//1 -1//1\n";
  const ObjMesh m = read_obj(dir / "quad.obj");
  EXPECT_EQ(m.faces.rows(), 2);
  EXPECT_EQ(m.faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.face_normals.row(1), Eigen::RowVector3i(0, 0, 0));

  std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 zero\n";
  try {
    read_obj(dir / "bad.obj");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj:2:"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "range.obj") << "v 0 0 0\nf 1 2 3\n";
  EXPECT_THROW(read_obj(dir / "range.obj"), std::runtime_error);
}
