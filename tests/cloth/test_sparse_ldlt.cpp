// The allocation-free sparse LDLᵀ against a dense solve.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "cloth/sparse_ldlt.hpp"

using namespace dexcloth::cloth;

namespace {

/// Upper triangle of dense A in compressed-column form, keeping entries with pattern[i,j].
struct Upper {
  std::vector<int> col_start{0}, row;
  std::vector<double> value;
};

Upper compress_upper(const Eigen::MatrixXd& A, const Eigen::MatrixXi& pattern) {
  Upper u;
  for (int j = 0; j < A.cols(); ++j) {
    for (int i = 0; i <= j; ++i) {
      if (pattern(i, j)) {
        u.row.push_back(i);
        u.value.push_back(A(i, j));
      }
    }
    u.col_start.push_back(static_cast<int>(u.row.size()));
  }
  return u;
}

}  // namespace

TEST(SparseLdlt, SolvesRandomSparseSpdSystemsAndRefactorises) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const int n = 60;
  // Random symmetric pattern with ~8 % density plus the diagonal.
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Identity(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (uni(rng) > 0.84) pattern(i, j) = pattern(j, i) = 1;
    }
  }
  SparseLdlt ldlt;
  bool analysed = false;
  for (int trial = 0; trial < 3; ++trial) {
    // Values on the pattern, made SPD by diagonal dominance.
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        if (pattern(i, j)) A(i, j) = A(j, i) = uni(rng);
      }
    }
    for (int i = 0; i < n; ++i) A(i, i) = A.row(i).cwiseAbs().sum() + 0.1 + std::abs(uni(rng));
    const Upper u = compress_upper(A, pattern);
    if (!analysed) {
      ldlt.analyze(n, u.col_start, u.row);
      analysed = true;
    }
    ASSERT_EQ(ldlt.factorize(u.value), -1);
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return uni(rng); });
    const Eigen::VectorXd expected = A.ldlt().solve(b);
    ldlt.solve_in_place(std::span<double>(b.data(), static_cast<std::size_t>(n)));
    // Both solves are backward stable on a well-conditioned (diagonally dominant) matrix.
    EXPECT_LE((b - expected).norm(), 1e-12 * expected.norm());
  }
}

TEST(SparseLdlt, ReportsTheFirstNonPositivePivot) {
  // [[1, 2], [2, 1]] is indefinite: D = (1, −3).
  SparseLdlt ldlt;
  const std::vector<int> col_start{0, 1, 3}, row{0, 0, 1};
  ldlt.analyze(2, col_start, row);
  EXPECT_EQ(ldlt.factorize(std::vector<double>{1.0, 2.0, 1.0}), 1);
  EXPECT_EQ(ldlt.factorize(std::vector<double>{1.0, 0.5, 1.0}), -1);
  EXPECT_EQ(ldlt.factorize(std::vector<double>{std::nan(""), 0.5, 1.0}), 0);
}

TEST(SparseLdlt, TrailingFactorGivesTheSchurComplementAndTheSplitSolveTheSolution) {
  // A random sparse SPD system split into 50 leading and 10 trailing unknowns: L₂₂·D₂·L₂₂ᵀ must
  // be A₂₂ − A₂₁·A₁₁⁻¹·A₁₂; solving it for the tail and back-substituting the rest must give
  // the full solution.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const int n = 60, tail = 10, lead = n - tail;
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Identity(n, n);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (uni(rng) > 0.85) {
        pattern(i, j) = pattern(j, i) = 1;
        A(i, j) = A(j, i) = uni(rng);
      }
    }
  }
  for (int i = 0; i < n; ++i) A(i, i) = A.row(i).cwiseAbs().sum() + 0.1;
  const Upper u = compress_upper(A, pattern);
  SparseLdlt ldlt;
  ldlt.analyze(n, u.col_start, u.row);
  ASSERT_EQ(ldlt.factorize(u.value), -1);

  Eigen::MatrixXd L22;
  Eigen::VectorXd D2;
  ldlt.trailing_factor(tail, L22, D2);
  const Eigen::MatrixXd schur =
      A.bottomRightCorner(tail, tail) -
      A.bottomLeftCorner(tail, lead) *
          A.topLeftCorner(lead, lead).ldlt().solve(A.topRightCorner(lead, tail));
  EXPECT_LT((L22 * D2.asDiagonal() * L22.transpose() - schur).cwiseAbs().maxCoeff(), 1e-12);

  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = uni(rng);
  const Eigen::VectorXd expected = A.ldlt().solve(b);
  std::vector<double> x(b.data(), b.data() + n);
  ldlt.forward_in_place(x);
  const Eigen::VectorXd z_tail = Eigen::Map<const Eigen::VectorXd>(x.data() + lead, tail);
  const Eigen::VectorXd x_tail =
      (L22 * D2.asDiagonal() * L22.transpose()).ldlt().solve(L22 * z_tail);
  for (int i = 0; i < tail; ++i) x[static_cast<std::size_t>(lead + i)] = x_tail[i];
  ldlt.backward_in_place(x, tail);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(x[static_cast<std::size_t>(i)], expected[i], 1e-12) << i;
}

TEST(SparseLdlt, BlockAnalysisMatchesTheScalarOne) {
  // A random sparse SPD matrix of dense 3×3 blocks (20 vertices): analysed by blocks, the factor
  // has the scalar analysis's nonzeros and the same solution.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const int nv = 20, n = 3 * nv;
  Eigen::MatrixXi vertex_pattern = Eigen::MatrixXi::Identity(nv, nv);
  for (int i = 0; i < nv; ++i)
    for (int j = i + 1; j < nv; ++j)
      if (uni(rng) > 0.8) vertex_pattern(i, j) = vertex_pattern(j, i) = 1;
  Eigen::MatrixXi pattern(n, n);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      pattern(i, j) = vertex_pattern(i / 3, j / 3);
      if (i < j && pattern(i, j)) A(i, j) = A(j, i) = uni(rng);
    }
  }
  for (int i = 0; i < n; ++i) A(i, i) = A.row(i).cwiseAbs().sum() + 0.1;
  const Upper u = compress_upper(A, pattern);
  SparseLdlt scalar, block;
  scalar.analyze(n, u.col_start, u.row);
  block.analyze(n, u.col_start, u.row, 3);
  ASSERT_EQ(scalar.factorize(u.value), -1);
  ASSERT_EQ(block.factorize(u.value), -1);
  EXPECT_EQ(block.factor_nonzeros(), scalar.factor_nonzeros());
  std::vector<double> x(static_cast<std::size_t>(n)), y(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    x[static_cast<std::size_t>(i)] = y[static_cast<std::size_t>(i)] = uni(rng);
  scalar.solve_in_place(x);
  block.solve_in_place(y);
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(x[static_cast<std::size_t>(i)], y[static_cast<std::size_t>(i)]) << i;
}
