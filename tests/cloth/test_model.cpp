// Model building: masses, rest shapes, hinges, system pattern, rejection of degenerate input.
#include <gtest/gtest.h>

#include <numbers>

#include "cloth/bending.hpp"
#include "cloth/model.hpp"
#include "core/errors.hpp"

using namespace dexcloth;
using namespace dexcloth::cloth;

TEST(Model, MassesAreasAndHingesOfAGrid) {
  const int nx = 6, ny = 4;
  const ClothMesh mesh = make_grid(0.5, 0.3, nx, ny);
  Material m;
  m.density = 0.2;
  const ClothModel model = build_model(mesh, m);
  EXPECT_NEAR(model.mass.sum(), 0.2 * 0.5 * 0.3, 1e-15);
  EXPECT_GT(model.mass.minCoeff(), 0.0);
  // Edges: horizontal + vertical + one diagonal per cell; hinges: all but the boundary edges.
  const int cells = (nx - 1) * (ny - 1);
  const int edges = (nx - 1) * ny + nx * (ny - 1) + cells;
  EXPECT_EQ(static_cast<int>(model.edges.size()), edges);
  EXPECT_EQ(static_cast<int>(model.hinges.size()), edges - 2 * (nx - 1) - 2 * (ny - 1));
  for (const Hinge& h : model.hinges) {
    EXPECT_EQ(h.rest_angle, 0.0);
    EXPECT_GT(h.weight, 0.0);
  }
  for (double a : model.rest_area) EXPECT_NEAR(a, 0.5 * 0.1 * 0.1, 1e-15);
}

TEST(Model, RestShapeFromFaceUvOrFrom3dPositions) {
  // A folded pair of triangles (90° about the shared edge): without face_uv the rest angle is
  // the fold; with face_uv it is 0 and the rest shape comes from the uv.
  ClothMesh mesh;
  mesh.x.resize(4, 3);
  mesh.x << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 0, 1;
  mesh.faces.resize(2, 3);
  mesh.faces << 0, 1, 2, 1, 0, 3;
  const ClothModel folded = build_model(mesh, Material{});
  ASSERT_EQ(folded.hinges.size(), 1u);
  EXPECT_NEAR(std::abs(folded.hinges[0].rest_angle), 0.5 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(folded.hinges[0].weight, 1.0 / (0.5 + 0.5), 1e-12);

  mesh.face_uv.resize(2, 6);
  mesh.face_uv << 0, 0, 2, 0, 1, 2, 2, 0, 0, 0, 1, -2;  // twice as large in material space
  const ClothModel flat = build_model(mesh, Material{});
  EXPECT_EQ(flat.hinges[0].rest_angle, 0.0);
  EXPECT_NEAR(flat.rest_area[0], 2.0, 1e-12);
  EXPECT_NEAR(flat.hinges[0].weight, 4.0 / 4.0, 1e-12);
  EXPECT_NEAR(flat.mass.sum(), Material{}.density * 4.0, 1e-15);
}

TEST(Model, SystemPatternIsConsistent) {
  const ClothModel model = build_model(make_grid(0.3, 0.3, 5, 5), Material{});
  const SystemPattern& p = model.pattern;
  ASSERT_EQ(static_cast<int>(p.col_start.size()), model.num_vertices() + 1);
  for (int j = 0; j < model.num_vertices(); ++j) {
    EXPECT_EQ(p.row[static_cast<std::size_t>(p.diagonal[static_cast<std::size_t>(j)])], j);
    for (int b = p.col_start[static_cast<std::size_t>(j)];
         b < p.col_start[static_cast<std::size_t>(j) + 1]; ++b) {
      const int t = p.transpose[static_cast<std::size_t>(b)];
      EXPECT_EQ(p.transpose[static_cast<std::size_t>(t)], b);
      EXPECT_EQ(p.row[static_cast<std::size_t>(t)], j);
    }
  }
  // The fill order is a permutation of the vertices.
  std::vector<int> order = p.fill_order;
  std::sort(order.begin(), order.end());
  for (int i = 0; i < model.num_vertices(); ++i) EXPECT_EQ(order[static_cast<std::size_t>(i)], i);
}

TEST(Model, RejectsDegenerateTrianglesAndUnusedVertices) {
  ClothMesh mesh;
  mesh.x.resize(6, 3);
  mesh.x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 5, 5, 5, 7, 7, 7;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 2, 0, 1, 3, 1, 1, 2;  // face 1 collinear, face 2 repeats a vertex
  try {
    build_model(mesh, Material{});
    FAIL() << "no throw";
  } catch (const InputRejected& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/faces/1: degenerate rest triangle"), std::string::npos) << what;
    EXPECT_NE(what.find("/faces/2: degenerate rest triangle"), std::string::npos) << what;
    EXPECT_NE(what.find("/vertices/4: vertex belongs to no face"), std::string::npos) << what;
    EXPECT_NE(what.find("/vertices/5: vertex belongs to no face"), std::string::npos) << what;
    EXPECT_EQ(what.find("/faces/0"), std::string::npos) << what;
  }
}
