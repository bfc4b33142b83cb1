#include "cloth/model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cloth/bending.hpp"
#include "core/assert.hpp"
#include "core/errors.hpp"

namespace dexcloth::cloth {
namespace {

/// Rest corners of face f in its own 2-D material frame (columns u0, u1, u2) [m]: face_uv when
/// present, else the 3-D rest triangle laid flat (u0 at the origin, u1 on the first axis).
Eigen::Matrix<double, 2, 3> rest_corners(const ClothMesh& rest, int f) {
  Eigen::Matrix<double, 2, 3> u;
  if (rest.face_uv.rows() > 0) {
    for (int c = 0; c < 3; ++c) u.col(c) = rest.face_uv.block<1, 2>(f, 2 * c).transpose();
    return u;
  }
  const Vec3 x0 = rest.x.row(rest.faces(f, 0)).transpose();
  const Vec3 e1 = rest.x.row(rest.faces(f, 1)).transpose() - x0;
  const Vec3 e2 = rest.x.row(rest.faces(f, 2)).transpose() - x0;
  const double l1 = e1.norm();
  const Vec3 t = l1 > 0.0 ? Vec3(e1 / l1) : Vec3::UnitX();
  const Vec3 b_raw = e2 - e2.dot(t) * t;  // in-plane, perpendicular to t
  u.col(0).setZero();
  u.col(1) << l1, 0.0;
  u.col(2) << e2.dot(t), b_raw.norm();
  return u;
}

/// Checks the programmer-side invariants of the inputs.
void demand_consistent(const ClothMesh& rest, const Material& m) {
  const Eigen::Index nv = rest.x.rows();
  DEXCLOTH_DEMAND(nv > 0 && rest.faces.rows() > 0);
  DEXCLOTH_DEMAND(rest.x.allFinite());
  DEXCLOTH_DEMAND(rest.faces.minCoeff() >= 0 && rest.faces.maxCoeff() < nv);
  DEXCLOTH_DEMAND(rest.face_uv.rows() == 0 || rest.face_uv.rows() == rest.faces.rows());
  DEXCLOTH_DEMAND(m.density > 0.0 && m.youngs_modulus > 0.0 && m.thickness > 0.0);
  DEXCLOTH_DEMAND(m.poisson >= 0.0 && m.poisson < 0.5);
  DEXCLOTH_DEMAND(m.bending_stiffness >= 0.0 && m.damping >= 0.0 && m.friction >= 0.0);
}

}  // namespace

ClothModel build_model(const ClothMesh& rest, const Material& material) {
  demand_consistent(rest, material);
  const int nv = static_cast<int>(rest.x.rows());
  const int nf = static_cast<int>(rest.faces.rows());
  const bool has_uv = rest.face_uv.rows() > 0;

  ClothModel model;
  model.faces = rest.faces;
  model.material = material;
  model.stretch = stretch_params(material);
  model.bending_k = bending_constant(material.bending_stiffness);

  // Per face: rest shape inverse and area; reject degenerate rest triangles.
  ErrorList errors;
  model.Dm_inv.resize(static_cast<std::size_t>(nf));
  model.rest_area.resize(static_cast<std::size_t>(nf));
  model.mass = Eigen::VectorXd::Zero(nv);
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Matrix<double, 2, 3> u = rest_corners(rest, f);
    Mat2 Dm;
    Dm << u.col(1) - u.col(0), u.col(2) - u.col(0);
    const double twice_area = std::abs(Dm.determinant());
    const double longest =
        std::max({(u.col(1) - u.col(0)).squaredNorm(), (u.col(2) - u.col(0)).squaredNorm(),
                  (u.col(2) - u.col(1)).squaredNorm()});
    const int a = rest.faces(f, 0), b = rest.faces(f, 1), c = rest.faces(f, 2);
    // Height below 1e-10 of the longest edge (or NaN in face_uv): unusable rest shape.
    if (a == b || b == c || a == c || !(twice_area > 1e-10 * longest)) {
      errors.add("cloth mesh", "/faces/" + std::to_string(f),
                 "degenerate rest triangle (vertices " + std::to_string(a) + ", " +
                     std::to_string(b) + ", " + std::to_string(c) + ", rest area " +
                     std::to_string(0.5 * twice_area) + " m²)");
      continue;
    }
    model.Dm_inv[static_cast<std::size_t>(f)] = Dm.inverse();
    model.rest_area[static_cast<std::size_t>(f)] = 0.5 * twice_area;
    // Lumped mass: a third of the face's mass to each corner.
    for (int k = 0; k < 3; ++k) {
      model.mass[rest.faces(f, k)] += material.density * 0.5 * twice_area / 3.0;
      used[static_cast<std::size_t>(rest.faces(f, k))] = 1;
    }
  }
  for (int i = 0; i < nv; ++i) {
    if (!used[static_cast<std::size_t>(i)] && errors.size() < 100) {
      errors.add("cloth mesh", "/vertices/" + std::to_string(i), "vertex belongs to no face");
    }
  }
  if (!errors.empty()) throw InputRejected(std::move(errors));

  // Edges and hinges with rest angle and weight |ē|²/(Ā1 + Ā2).
  Topology topo = build_topology(rest.faces);
  model.edges = std::move(topo.edges);
  model.hinges = std::move(topo.hinges);
  for (Hinge& h : model.hinges) {
    const auto f1 = static_cast<std::size_t>(h.faces[0]);
    const auto f2 = static_cast<std::size_t>(h.faces[1]);
    double edge_sq = 0.0;
    if (has_uv) {
      // Material-space edge length, averaged over the two faces (they may differ at a seam).
      for (std::size_t s = 0; s < 2; ++s) {
        const int f = h.faces[s];
        const Eigen::Matrix<double, 2, 3> u = rest_corners(rest, f);
        Vec2 p0 = Vec2::Zero(), p1 = Vec2::Zero();
        for (int k = 0; k < 3; ++k) {
          if (rest.faces(f, k) == h.v[0]) p0 = u.col(k);
          if (rest.faces(f, k) == h.v[1]) p1 = u.col(k);
        }
        edge_sq += 0.5 * (p1 - p0).squaredNorm();
      }
      h.rest_angle = 0.0;
    } else {
      const Vec3 x0 = rest.x.row(h.v[0]).transpose(), x1 = rest.x.row(h.v[1]).transpose();
      const Vec3 x2 = rest.x.row(h.v[2]).transpose(), x3 = rest.x.row(h.v[3]).transpose();
      edge_sq = (x1 - x0).squaredNorm();
      h.rest_angle = dihedral_angle(x0, x1, x2, x3);
    }
    h.weight = edge_sq / (model.rest_area[f1] + model.rest_area[f2]);
  }

  // Fixed system sparsity.
  model.pattern = build_system_pattern(nv, model.faces, model.hinges);
  return model;
}

}  // namespace dexcloth::cloth
