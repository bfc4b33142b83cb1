#include "cloth/collision/strain_limit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <Eigen/SVD>

#include "core/assert.hpp"

namespace dexcloth::collision {

StrainLimitReport limit_strain(Points& x, const Triangles& faces, const std::vector<Mat2>& dm_inv,
                               const Eigen::VectorXd& mass, const std::vector<std::uint8_t>& frozen,
                               const StrainLimitOptions& options) {
  DEXCLOTH_DEMAND(dm_inv.size() == static_cast<std::size_t>(faces.rows()));
  DEXCLOTH_DEMAND(mass.size() == x.rows());
  DEXCLOTH_DEMAND(frozen.empty() || frozen.size() == static_cast<std::size_t>(x.rows()));
  DEXCLOTH_DEMAND(options.min_stretch <= options.max_stretch);
  DEXCLOTH_DEMAND(options.relaxation >= 1.0 && options.relaxation < 2.0);
  const double omega = options.relaxation;
  const double margin = std::min(0.25 * options.tolerance, 0.25 * (options.max_stretch - options.min_stretch));
  auto is_frozen = [&](int v) { return !frozen.empty() && frozen[static_cast<std::size_t>(v)] != 0; };

  // One Gauss–Seidel sweep (or, with `correct` false, a measurement); returns the largest
  // violation seen before each triangle's correction.
  // Sweep order: outward from the frozen vertices (hop distance), so their influence crosses the
  // mesh in one sweep instead of diffusing.
  const int nf = static_cast<int>(faces.rows());
  std::vector<int> hops(static_cast<std::size_t>(x.rows()), std::numeric_limits<int>::max());
  for (int v = 0; v < x.rows(); ++v)
    if (is_frozen(v)) hops[static_cast<std::size_t>(v)] = 0;
  for (bool changed = !frozen.empty(); changed;) {
    changed = false;
    for (int f = 0; f < nf; ++f) {
      int near = std::numeric_limits<int>::max();
      for (int k = 0; k < 3; ++k) near = std::min(near, hops[static_cast<std::size_t>(faces(f, k))]);
      if (near == std::numeric_limits<int>::max()) continue;
      for (int k = 0; k < 3; ++k) {
        int& h = hops[static_cast<std::size_t>(faces(f, k))];
        if (h > near + 1) {
          h = near + 1;
          changed = true;
        }
      }
    }
  }
  std::vector<std::pair<int, int>> order(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    int near = std::numeric_limits<int>::max();
    for (int k = 0; k < 3; ++k) near = std::min(near, hops[static_cast<std::size_t>(faces(f, k))]);
    order[static_cast<std::size_t>(f)] = {near, f};
  }
  std::stable_sort(order.begin(), order.end());

  auto sweep = [&](bool correct) {
    double worst = 0.0;
    for (const auto& [key, f] : order) {
      const int v[3] = {faces(f, 0), faces(f, 1), faces(f, 2)};
      const Vec3 p[3] = {x.row(v[0]).transpose(), x.row(v[1]).transpose(), x.row(v[2]).transpose()};
      Mat32 ds;
      ds.col(0) = p[1] - p[0];
      ds.col(1) = p[2] - p[0];
      const Mat2& dmi = dm_inv[static_cast<std::size_t>(f)];
      const Mat32 def = ds * dmi;
      // Singular values in closed form from FᵀF; the SVD only for triangles out of bounds.
      const Mat2 c = def.transpose() * def;
      const double half_trace = 0.5 * (c(0, 0) + c(1, 1));
      const double root = std::sqrt(std::max(0.25 * (c(0, 0) - c(1, 1)) * (c(0, 0) - c(1, 1)) + c(0, 1) * c(0, 1), 0.0));
      const double s_max = std::sqrt(half_trace + root);
      const double s_min = std::sqrt(std::max(half_trace - root, 0.0));
      // Inside the bounds by a margin that covers the closed form's round-off.
      constexpr double kSafe = 1e-9;
      if (s_min >= options.min_stretch + kSafe && s_max <= options.max_stretch - kSafe) continue;
      const Eigen::JacobiSVD<Mat32> svd(def, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Vec2 s = svd.singularValues();
      const Vec2 clamped = s.cwiseMax(options.min_stretch).cwiseMin(options.max_stretch);
      const double violation = (s - clamped).cwiseAbs().maxCoeff();
      worst = std::max(worst, violation);
      if (!correct || violation == 0.0) continue;
      const Vec2 goal = s.cwiseMax(options.min_stretch + margin).cwiseMin(options.max_stretch - margin);
      // Over-relax only as far as the admissible band: never past the opposite bound (or a flip).
      const double band = options.max_stretch - options.min_stretch - 2.0 * margin;
      const double step = (goal - s).cwiseAbs().maxCoeff();
      const double omega_f = 1.0 + std::min(omega - 1.0, band / step);

      // Target shape with clamped stretches: edges r_k relative to corner 0.
      const Mat32 target_def = svd.matrixU().leftCols<2>() * goal.asDiagonal() * svd.matrixV().transpose();
      const Mat32 target_ds = target_def * dmi.inverse();
      const Vec3 r[3] = {Vec3::Zero(), target_ds.col(0), target_ds.col(1)};

      // Placement p: mass-weighted least squares, or pinned by the frozen corners.
      int n_frozen = 0;
      Vec3 anchor = Vec3::Zero();
      double total = 0.0;
      Vec3 centre = Vec3::Zero();
      for (int k = 0; k < 3; ++k) {
        if (is_frozen(v[k])) {
          ++n_frozen;
          anchor += p[k] - r[k];
        } else {
          total += mass[v[k]];
          centre += mass[v[k]] * (p[k] - r[k]);
        }
      }
      if (n_frozen == 3) continue;
      const Vec3 place = n_frozen > 0 ? Vec3(anchor / n_frozen) : Vec3(centre / total);
      for (int k = 0; k < 3; ++k)
        if (!is_frozen(v[k])) x.row(v[k]) += omega_f * ((place + r[k]) - p[k]).transpose();
    }
    return worst;
  };

  // Sweep until a sweep starts well inside the tolerance, then measure the result.
  StrainLimitReport report;
  while (report.iterations < options.max_iterations) {
    ++report.iterations;
    if (sweep(true) <= 0.5 * options.tolerance) break;
  }
  report.violation = sweep(false);
  report.converged = report.violation <= options.tolerance;
  return report;
}

}  // namespace dexcloth::collision
