#pragma once
/// Central finite differences for the energy tests.
#include <Eigen/Core>

namespace dexcloth::cloth::test {

/// Central-difference gradient of scalar f at x with step `eps`.
template <int N, class F>
Eigen::Matrix<double, N, 1> fd_gradient(const F& f, const Eigen::Matrix<double, N, 1>& x,
                                        double eps) {
  Eigen::Matrix<double, N, 1> g;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> xp = x, xm = x;
    xp[i] += eps;
    xm[i] -= eps;
    g[i] = (f(xp) - f(xm)) / (2.0 * eps);
  }
  return g;
}

/// Central-difference Jacobian of vector function g at x with step `eps` (column i = ∂g/∂x_i).
template <int N, class G>
Eigen::Matrix<double, N, N> fd_jacobian(const G& g, const Eigen::Matrix<double, N, 1>& x,
                                        double eps) {
  Eigen::Matrix<double, N, N> J;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> xp = x, xm = x;
    xp[i] += eps;
    xm[i] -= eps;
    J.col(i) = (g(xp) - g(xm)) / (2.0 * eps);
  }
  return J;
}

}  // namespace dexcloth::cloth::test
