#include "mesh_builders.hpp"

#include <cmath>
#include <numbers>

namespace dexcloth::collision::testing {

CollisionMesh make_sheet(int nx, int ny, double size_x, double size_y, const Vec3& origin,
                         double vertex_mass) {
  CollisionMesh m;
  const int nv = (nx + 1) * (ny + 1);
  m.x0.resize(nv, 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.x0.row(j * (nx + 1) + i) =
          (origin + Vec3(size_x * i / nx, size_y * j / ny, 0.0)).transpose();
  m.faces.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      // Alternate the diagonal so the sheet has no preferred direction.
      if ((i + j) % 2 == 0) {
        m.faces.row(f++) << v00, v10, v11;
        m.faces.row(f++) << v00, v11, v01;
      } else {
        m.faces.row(f++) << v00, v10, v01;
        m.faces.row(f++) << v10, v11, v01;
      }
    }
  }
  m.x1 = m.x0;
  m.mass = Eigen::VectorXd::Constant(nv, vertex_mass);
  m.frozen.assign(static_cast<std::size_t>(nv), 0);
  return m;
}

CollisionMesh join_obstacles(const CollisionMesh& a, const CollisionMesh& b) {
  CollisionMesh m = a;
  const auto na = a.x0.rows();
  m.x0.resize(na + b.x0.rows(), 3);
  m.x0 << a.x0, b.x0;
  m.x1.resize(m.x0.rows(), 3);
  m.x1 << a.x1, b.x1;
  m.faces.resize(a.faces.rows() + b.faces.rows(), 3);
  m.faces << a.faces, (b.faces.array() + static_cast<int>(na)).matrix();
  m.mass = Eigen::VectorXd::Ones(m.x0.rows());
  m.obstacle = true;
  return m;
}

CollisionMesh make_box(const Vec3& lo, const Vec3& hi) {
  CollisionMesh m;
  m.obstacle = true;
  m.x0.resize(8, 3);
  for (int k = 0; k < 8; ++k)
    m.x0.row(k) << ((k & 1) ? hi.x() : lo.x()), ((k & 2) ? hi.y() : lo.y()),
        ((k & 4) ? hi.z() : lo.z());
  m.faces.resize(12, 3);
  m.faces << 0, 2, 3, 0, 3, 1,  // z = lo
      4, 5, 7, 4, 7, 6,         // z = hi
      0, 1, 5, 0, 5, 4,         // y = lo
      2, 6, 7, 2, 7, 3,         // y = hi
      0, 4, 6, 0, 6, 2,         // x = lo
      1, 3, 7, 1, 7, 5;         // x = hi
  m.x1 = m.x0;
  m.mass = Eigen::VectorXd::Ones(8);
  return m;
}

CollisionMesh make_sphere(const Vec3& centre, double radius, int rings, int segments) {
  CollisionMesh m;
  m.obstacle = true;
  const int nv = 2 + (rings - 1) * segments;
  m.x0.resize(nv, 3);
  m.x0.row(0) = (centre + Vec3(0, 0, radius)).transpose();
  m.x0.row(nv - 1) = (centre - Vec3(0, 0, radius)).transpose();
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      m.x0.row(1 + (r - 1) * segments + s) =
          (centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                  std::cos(theta)))
              .transpose();
    }
  }
  auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  m.faces.resize(2 * segments * (rings - 1), 3);
  int f = 0;
  for (int s = 0; s < segments; ++s) {
    m.faces.row(f++) << 0, ring(1, s), ring(1, s + 1);
    m.faces.row(f++) << nv - 1, ring(rings - 1, s + 1), ring(rings - 1, s);
  }
  for (int r = 1; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      m.faces.row(f++) << ring(r, s), ring(r + 1, s), ring(r + 1, s + 1);
      m.faces.row(f++) << ring(r, s), ring(r + 1, s + 1), ring(r, s + 1);
    }
  }
  m.x1 = m.x0;
  m.mass = Eigen::VectorXd::Ones(nv);
  return m;
}

}  // namespace dexcloth::collision::testing
