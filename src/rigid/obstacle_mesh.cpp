#include "rigid/obstacle_mesh.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include "core/assert.hpp"

namespace dexcloth::rigid {
namespace {

/// Surface of revolution about z through the profile points (r_k, z_k), k = 0..K−1, from the
/// bottom pole (r_0 = 0) to the top pole (r_{K−1} = 0); the poles become single vertices.
LocalMesh revolve(const std::vector<std::pair<double, double>>& profile, int slices) {
  DEXCLOTH_DEMAND(slices >= 3 && profile.size() >= 3);
  const int rings = static_cast<int>(profile.size()) - 2;  // rings between the poles
  LocalMesh m;
  m.x.resize(2 + rings * slices, 3);
  m.x.row(0) = Vec3(0, 0, profile.front().second).transpose();
  for (int k = 0; k < rings; ++k) {
    const auto [r, z] = profile[static_cast<std::size_t>(k) + 1];
    for (int s = 0; s < slices; ++s) {
      const double a = 2.0 * std::numbers::pi * s / slices;
      m.x.row(1 + k * slices + s) = Vec3(r * std::cos(a), r * std::sin(a), z).transpose();
    }
  }
  const int top = 1 + rings * slices;
  m.x.row(top) = Vec3(0, 0, profile.back().second).transpose();
  // Bottom fan, ring quads, top fan; counter-clockwise seen from outside.
  m.faces.resize(2 * slices + 2 * slices * (rings - 1), 3);
  int f = 0;
  auto ring = [slices](int k, int s) { return 1 + k * slices + (s % slices); };
  for (int s = 0; s < slices; ++s) m.faces.row(f++) << 0, ring(0, s + 1), ring(0, s);
  for (int k = 0; k + 1 < rings; ++k) {
    for (int s = 0; s < slices; ++s) {
      m.faces.row(f++) << ring(k, s), ring(k, s + 1), ring(k + 1, s + 1);
      m.faces.row(f++) << ring(k, s), ring(k + 1, s + 1), ring(k + 1, s);
    }
  }
  for (int s = 0; s < slices; ++s) m.faces.row(f++) << top, ring(rings - 1, s), ring(rings - 1, s + 1);
  return m;
}

}  // namespace

LocalMesh box_mesh(const Vec3& size) {
  LocalMesh m;
  m.x.resize(8, 3);
  const Vec3 h = 0.5 * size;
  for (int i = 0; i < 8; ++i) {
    m.x.row(i) << ((i & 1) ? h.x() : -h.x()), ((i & 2) ? h.y() : -h.y()), ((i & 4) ? h.z() : -h.z());
  }
  m.faces.resize(12, 3);
  m.faces << 0, 2, 3, 0, 3, 1,   // -z
      4, 5, 7, 4, 7, 6,          // +z
      0, 1, 5, 0, 5, 4,          // -y
      2, 6, 7, 2, 7, 3,          // +y
      0, 4, 6, 0, 6, 2,          // -x
      1, 3, 7, 1, 7, 5;          // +x
  return m;
}

LocalMesh sphere_mesh(double radius, int slices, int stacks) {
  DEXCLOTH_DEMAND(stacks >= 2);
  std::vector<std::pair<double, double>> profile;
  for (int k = 0; k <= stacks; ++k) {
    const double phi = std::numbers::pi * k / stacks;  // from the bottom pole
    profile.emplace_back(radius * std::sin(phi), -radius * std::cos(phi));
  }
  return revolve(profile, slices);
}

LocalMesh capsule_mesh(double radius, double length, int slices, int cap_stacks) {
  DEXCLOTH_DEMAND(cap_stacks >= 1);
  std::vector<std::pair<double, double>> profile;
  const double half = 0.5 * length;
  // Bottom hemisphere from the pole to the equator, then the top hemisphere.
  for (int k = 0; k <= cap_stacks; ++k) {
    const double phi = 0.5 * std::numbers::pi * k / cap_stacks;
    profile.emplace_back(radius * std::sin(phi), -half - radius * std::cos(phi));
  }
  for (int k = 0; k <= cap_stacks; ++k) {
    const double phi = 0.5 * std::numbers::pi * k / cap_stacks;
    profile.emplace_back(radius * std::cos(phi), half + radius * std::sin(phi));
  }
  return revolve(profile, slices);
}

LocalMesh cylinder_mesh(double radius, double length, int slices) {
  const double half = 0.5 * length;
  return revolve({{0.0, -half}, {radius, -half}, {radius, half}, {0.0, half}}, slices);
}

void append_mesh(LocalMesh& mesh, const LocalMesh& part, const Eigen::Isometry3d& X_BS) {
  const auto n0 = mesh.x.rows();
  const auto f0 = mesh.faces.rows();
  mesh.x.conservativeResize(n0 + part.x.rows(), 3);
  mesh.faces.conservativeResize(f0 + part.faces.rows(), 3);
  for (Eigen::Index i = 0; i < part.x.rows(); ++i) {
    mesh.x.row(n0 + i) = (X_BS * Vec3(part.x.row(i).transpose())).transpose();
  }
  mesh.faces.bottomRows(part.faces.rows()) = part.faces.array() + static_cast<int>(n0);
}

}  // namespace dexcloth::rigid
