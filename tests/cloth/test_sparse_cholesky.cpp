// The supernodal sparse Cholesky factorisation against dense solves.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "cloth/sparse_cholesky.hpp"

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

TEST(SparseCholesky, SolvesRandomSparseSpdSystemsAndRefactorises) {
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
  SparseCholesky chol;
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
      chol.analyze(n, u.col_start, u.row);
      analysed = true;
    }
    ASSERT_EQ(chol.factorize(u.value), -1);
    Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return uni(rng); });
    const Eigen::VectorXd expected = A.ldlt().solve(b);
    chol.solve_in_place(std::span<double>(b.data(), static_cast<std::size_t>(n)));
    // Both solves are backward stable on a well-conditioned (diagonally dominant) matrix.
    EXPECT_LE((b - expected).norm(), 1e-12 * expected.norm());
  }
}

TEST(SparseCholesky, ReportsTheFirstNonPositivePivot) {
  // [[1, 2], [2, 1]] is indefinite: its second pivot is 1 − 4 < 0.
  SparseCholesky chol;
  const std::vector<int> col_start{0, 1, 3}, row{0, 0, 1};
  chol.analyze(2, col_start, row);
  EXPECT_EQ(chol.factorize(std::vector<double>{1.0, 2.0, 1.0}), 1);
  EXPECT_EQ(chol.factorize(std::vector<double>{1.0, 0.5, 1.0}), -1);
  EXPECT_EQ(chol.factorize(std::vector<double>{std::nan(""), 0.5, 1.0}), 0);
}

TEST(SparseCholesky, TrailingFactorGivesTheSchurComplementAndTheSplitSolveTheSolution) {
  // A random sparse SPD system split into 50 leading and 10 trailing unknowns: L₂₂·L₂₂ᵀ must
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
  SparseCholesky chol;
  chol.analyze(n, u.col_start, u.row);
  ASSERT_EQ(chol.factorize(u.value), -1);

  Eigen::MatrixXd L22;
  chol.trailing_factor(tail, L22);
  const Eigen::MatrixXd schur =
      A.bottomRightCorner(tail, tail) -
      A.bottomLeftCorner(tail, lead) *
          A.topLeftCorner(lead, lead).ldlt().solve(A.topRightCorner(lead, tail));
  EXPECT_LT((L22 * L22.transpose() - schur).cwiseAbs().maxCoeff(), 1e-12);

  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = uni(rng);
  const Eigen::VectorXd expected = A.ldlt().solve(b);
  std::vector<double> x(b.data(), b.data() + n);
  chol.forward_in_place(x);
  const Eigen::VectorXd z_tail = Eigen::Map<const Eigen::VectorXd>(x.data() + lead, tail);
  const Eigen::VectorXd x_tail = (L22 * L22.transpose()).ldlt().solve(L22 * z_tail);
  for (int i = 0; i < tail; ++i) x[static_cast<std::size_t>(lead + i)] = x_tail[i];
  chol.backward_in_place(x, tail);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(x[static_cast<std::size_t>(i)], expected[i], 1e-12) << i;
}

TEST(SparseCholesky, KeepsTheGivenOrderOfTheUnknowns) {
  // An arrow matrix with its hub first fills in completely in that order (a fill-reducing
  // permutation would move the hub last): the factor must have all n(n+1)/2 entries.
  const int n = 12;
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) * 4.0;
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Identity(n, n);
  for (int j = 1; j < n; ++j) {
    A(0, j) = A(j, 0) = 0.5;
    pattern(0, j) = pattern(j, 0) = 1;
  }
  const Upper u = compress_upper(A, pattern);
  SparseCholesky chol;
  chol.analyze(n, u.col_start, u.row);
  ASSERT_EQ(chol.factorize(u.value), -1);
  EXPECT_EQ(chol.factor_nonzeros(), static_cast<std::size_t>(n * (n + 1) / 2));
  Eigen::MatrixXd L22;
  chol.trailing_factor(n, L22);
  EXPECT_LT((L22 * L22.transpose() - A).cwiseAbs().maxCoeff(), 1e-12);
}
