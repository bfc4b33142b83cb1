// The single-precision substitution kernels of the sparse Cholesky against double-precision
// dense solves of the same panels.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "cloth/substitution_kernels.hpp"

using namespace dexcloth::cloth;

namespace {

/// A front's panel: f rows × w columns, leading dimension f + 3 (a stride that is not the row
/// count), its top w rows lower triangular with a dominant diagonal, the rest random.
struct RandomPanel {
  int f, w, ld;
  std::vector<float> L;
  Eigen::MatrixXd dense;  // the same values, f × w

  RandomPanel(int rows, int columns, std::mt19937& rng)
      : f(rows),
        w(columns),
        ld(rows + 3),
        L(static_cast<std::size_t>(ld * columns), 99.0F),
        dense(Eigen::MatrixXd::Zero(rows, columns)) {
    std::uniform_real_distribution<float> uni(-1.0F, 1.0F);
    for (int j = 0; j < w; ++j)
      for (int i = j; i < f; ++i) {
        const float v = i == j ? 2.0F + std::abs(uni(rng)) : uni(rng);
        L[static_cast<std::size_t>(j * ld + i)] = v;
        dense(i, j) = v;
      }
  }
};

std::vector<float> random_vector(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> uni(-1.0F, 1.0F);
  std::vector<float> v(static_cast<std::size_t>(n));
  for (float& x : v) x = uni(rng);
  return v;
}

Eigen::VectorXd to_double(const std::vector<float>& v, int from, int count) {
  Eigen::VectorXd d(count);
  for (int k = 0; k < count; ++k) d[k] = v[static_cast<std::size_t>(from + k)];
  return d;
}

/// Widths around the four-column blocks and row counts around the eight-lane vectors.
// Tolerance of the comparisons, relative: single precision rounds each of the up to ~140 terms
// of a row by ε_f = 6e-8, and the diagonals (≥ 2 against off-diagonals within ±1) keep the
// triangle well conditioned, so the error stays within 140·ε_f ≈ 1e-5.
const int kWidths[] = {1, 2, 3, 4, 5, 7, 8, 9, 13, 40};
const int kBelow[] = {0, 1, 7, 8, 9, 31, 100};

}  // namespace

TEST(SubstitutionKernels, ForwardSolvesTheTriangleAndMultipliesTheRowsBelow) {
  std::mt19937 rng(11);
  using Forward = void (*)(int, int, const float*, int, float*, float*);
  for (const Forward forward :
       {Forward{kernels::forward_panel}, Forward{kernels::forward_panel_plain}})
    for (int w : kWidths)
      for (int below : kBelow) {
        const RandomPanel p(w + below, w, rng);
        std::vector<float> x = random_vector(w, rng);
        std::vector<float> y(static_cast<std::size_t>(below) + 1, 77.0F);  // one past: untouched
        const Eigen::VectorXd x1 =
            p.dense.topRows(w).triangularView<Eigen::Lower>().solve(to_double(x, 0, w));
        const Eigen::VectorXd y1 = p.dense.bottomRows(below) * x1;
        forward(p.f, p.w, p.L.data(), p.ld, x.data(), y.data());
        EXPECT_LE((to_double(x, 0, w) - x1).norm(), 1e-5 * x1.norm()) << w << " " << below;
        if (below > 0) {
          EXPECT_LE((to_double(y, 0, below) - y1).norm(), 1e-5 * (1.0 + y1.norm()))
              << w << " " << below;
        }
        EXPECT_EQ(y[static_cast<std::size_t>(below)], 77.0F);
      }
}

TEST(SubstitutionKernels, BackwardSolvesTheTransposedTriangleWithTheKnownRows) {
  std::mt19937 rng(12);
  using Backward = void (*)(int, int, const float*, int, float*, const float*);
  for (const Backward backward :
       {Backward{kernels::backward_panel}, Backward{kernels::backward_panel_plain}})
    for (int u : kWidths)
      for (int known : kBelow) {
        const RandomPanel p(u + known, u, rng);
        std::vector<float> x = random_vector(u + 1, rng);  // one past: untouched
        const float past = x[static_cast<std::size_t>(u)];
        const std::vector<float> g = random_vector(known, rng);
        Eigen::VectorXd rhs = to_double(x, 0, u);
        if (known > 0) rhs -= p.dense.bottomRows(known).transpose() * to_double(g, 0, known);
        const Eigen::VectorXd expected =
            p.dense.topRows(u).triangularView<Eigen::Lower>().transpose().solve(rhs);
        backward(p.f, u, p.L.data(), p.ld, x.data(), g.data());
        EXPECT_LE((to_double(x, 0, u) - expected).norm(), 1e-5 * (1.0 + expected.norm()))
            << u << " " << known;
        EXPECT_EQ(x[static_cast<std::size_t>(u)], past);
      }
}

TEST(SubstitutionKernels, AvailableVectorKernelsAgreeWithThePlainOnesToRounding) {
  if (!kernels::vector_kernels()) GTEST_SKIP() << "no AVX2 and FMA on this CPU";
  std::mt19937 rng(13);
  const RandomPanel p(90, 21, rng);
  std::vector<float> x = random_vector(21, rng), x_plain = x;
  std::vector<float> y(69), y_plain(69);
  kernels::forward_panel(p.f, p.w, p.L.data(), p.ld, x.data(), y.data());
  kernels::forward_panel_plain(p.f, p.w, p.L.data(), p.ld, x_plain.data(), y_plain.data());
  for (int k = 0; k < 21; ++k) EXPECT_NEAR(x[k], x_plain[k], 1e-5F * (1.0F + std::abs(x[k])));
  for (int k = 0; k < 69; ++k) EXPECT_NEAR(y[k], y_plain[k], 1e-5F * (1.0F + std::abs(y[k])));
  // Not bitwise: the vector kernels fuse their multiply–adds.
  bool differ = false;
  for (int k = 0; k < 69; ++k) differ = differ || y[k] != y_plain[k];
  EXPECT_TRUE(differ);
}
