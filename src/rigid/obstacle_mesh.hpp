#pragma once
/// Rigid collision geometry as world-space triangle meshes, for the cloth side (plain Eigen).
#include <string>

#include "core/types.hpp"

namespace dexcloth::rigid {

/// One rigid body's collision shapes as a closed triangle mesh in world coordinates.
struct ObstacleMesh {
  std::string name;          ///< "skeleton/body_node"
  Points x;                  ///< |V|×3 vertex positions in world [m]
  Points v;                  ///< |V|×3 vertex velocities in world [m/s]
  Triangles faces;           ///< |F|×3 vertex indices, counter-clockwise seen from outside
  double friction{};         ///< Coulomb μ of the body's shapes [-]
};

/// A triangle mesh in some local frame (|V|×3 points, |F|×3 faces, outward orientation).
struct LocalMesh {
  Points x;
  Triangles faces;
};

/// Box of full extents `size` [m], centred at the origin: 8 vertices, 12 triangles.
LocalMesh box_mesh(const Vec3& size);
/// Sphere of `radius` [m] at the origin, UV-tessellated with `slices` ≥ 3 around z and
/// `stacks` ≥ 2 from pole to pole.
LocalMesh sphere_mesh(double radius, int slices = 16, int stacks = 8);
/// Capsule along z: cylinder part of `length` [m] centred at the origin plus hemispheres of
/// `radius` [m]; `slices` ≥ 3 around z, `cap_stacks` ≥ 1 per hemisphere.
LocalMesh capsule_mesh(double radius, double length, int slices = 12, int cap_stacks = 3);
/// Closed cylinder along z of `radius` and `length` [m], centred at the origin.
LocalMesh cylinder_mesh(double radius, double length, int slices = 16);

/// Appends `part` transformed by `X_BS` (shape frame in body frame) to `mesh`.
void append_mesh(LocalMesh& mesh, const LocalMesh& part, const Eigen::Isometry3d& X_BS);

}  // namespace dexcloth::rigid
