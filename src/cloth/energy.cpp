#include "cloth/energy.hpp"

#include "cloth/bending.hpp"
#include "cloth/stretching.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {

double stretching_energy(const ClothModel& model, const Points& x) {
  DEXCLOTH_DEMAND(x.rows() == model.num_vertices());
  double e = 0.0;
  for (int f = 0; f < model.faces.rows(); ++f) {
    e += stretch_energy(x.row(model.faces(f, 0)).transpose(), x.row(model.faces(f, 1)).transpose(),
                        x.row(model.faces(f, 2)).transpose(),
                        model.Dm_inv[static_cast<std::size_t>(f)],
                        model.rest_area[static_cast<std::size_t>(f)], model.stretch);
  }
  return e;
}

double total_bending_energy(const ClothModel& model, const Points& x) {
  DEXCLOTH_DEMAND(x.rows() == model.num_vertices());
  double e = 0.0;
  for (const Hinge& h : model.hinges) {
    e += bending_energy(x.row(h.v[0]).transpose(), x.row(h.v[1]).transpose(),
                        x.row(h.v[2]).transpose(), x.row(h.v[3]).transpose(), h.rest_angle,
                        h.weight, model.bending_k);
  }
  return e;
}

double elastic_energy(const ClothModel& model, const Points& x) {
  return stretching_energy(model, x) + total_bending_energy(model, x);
}

double kinetic_energy(const ClothModel& model, const Points& v) {
  DEXCLOTH_DEMAND(v.rows() == model.num_vertices());
  return 0.5 * (model.mass.array() * v.rowwise().squaredNorm().array()).sum();
}

Vec3 linear_momentum(const ClothModel& model, const Points& v) {
  DEXCLOTH_DEMAND(v.rows() == model.num_vertices());
  return (v.transpose() * model.mass);
}

Vec3 angular_momentum(const ClothModel& model, const Points& x, const Points& v) {
  DEXCLOTH_DEMAND(x.rows() == model.num_vertices() && v.rows() == model.num_vertices());
  Vec3 l = Vec3::Zero();
  for (int i = 0; i < model.num_vertices(); ++i) {
    l += model.mass[i] * Vec3(x.row(i).transpose()).cross(Vec3(v.row(i).transpose()));
  }
  return l;
}

}  // namespace dexcloth::cloth
