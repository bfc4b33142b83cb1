// The dense symmetric kernels through OpenBLAS against Eigen's own algebra.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "cloth/dense_blas.hpp"

using namespace dexcloth::cloth;

namespace {

/// A random n×n lower-triangular matrix with a dominant positive diagonal, and garbage above
/// the diagonal that the kernels must not read.
Eigen::MatrixXd random_lower(int n, unsigned seed) {
  std::srand(seed);
  Eigen::MatrixXd l = Eigen::MatrixXd::Random(n, n);
  l.diagonal().array() = l.diagonal().array().abs() + 2.0;
  l.triangularView<Eigen::StrictlyUpper>().setConstant(1e30);
  return l;
}

Eigen::MatrixXd lower_of(const Eigen::MatrixXd& l) {
  return l.triangularView<Eigen::Lower>().toDenseMatrix();
}

}  // namespace

TEST(DenseBlas, LowerTimesTransposeIsTheFullSymmetricProduct) {
  for (const int n : {0, 1, 2, 7, 130}) {
    const Eigen::MatrixXd l = random_lower(n, 3u + static_cast<unsigned>(n));
    Eigen::MatrixXd s;
    lower_times_transpose(l, s);
    const Eigen::MatrixXd expected = lower_of(l) * lower_of(l).transpose();
    ASSERT_EQ(s.rows(), n);
    ASSERT_EQ(s.cols(), n);
    if (n > 0) {
      EXPECT_LT((s - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.norm()) << n;
    }
    EXPECT_EQ(s, s.transpose()) << n;
  }
}

TEST(DenseBlas, CholeskyFactorsSolvesAndRejectsAnIndefiniteMatrix) {
  const int n = 90;
  const Eigen::MatrixXd l = random_lower(n, 11u);
  const Eigen::MatrixXd a = lower_of(l) * lower_of(l).transpose();
  Eigen::MatrixXd f = a;
  ASSERT_TRUE(cholesky_lower(f));
  EXPECT_LT((lower_of(f) * lower_of(f).transpose() - a).norm(), 1e-12 * a.norm());
  EXPECT_EQ(f.triangularView<Eigen::StrictlyUpper>().toDenseMatrix(),
            a.triangularView<Eigen::StrictlyUpper>().toDenseMatrix());  // left as it was

  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x = b;
  cholesky_solve(f, x);
  EXPECT_LT((a * x - b).norm(), 1e-12 * b.norm());

  Eigen::MatrixXd indefinite = a;
  indefinite(n / 2, n / 2) = -1.0;
  EXPECT_FALSE(cholesky_lower(indefinite));
}

TEST(DenseBlas, TriangularSolvesAndGramUpdate) {
  const int n = 40, k = 25;
  const Eigen::MatrixXd l = random_lower(n, 5u);
  const Eigen::MatrixXd lo = lower_of(l);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(n, k);

  Eigen::MatrixXd x = b;
  solve_lower(l, x);
  EXPECT_LT((lo * x - b).norm(), 1e-12 * b.norm());
  Eigen::VectorXd v = b.col(0);
  solve_lower(l, v);
  EXPECT_LT((lo * v - b.col(0)).norm(), 1e-12 * b.norm());
  v = b.col(1);
  solve_lower_transposed(l, v);
  EXPECT_LT((lo.transpose() * v - b.col(1)).norm(), 1e-12 * b.norm());

  // c −= wᵀw, full and symmetric.
  const Eigen::MatrixXd w = Eigen::MatrixXd::Random(n, k);
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(k, k) * 3.0;
  subtract_gram(w, c);
  const Eigen::MatrixXd expected = Eigen::MatrixXd::Identity(k, k) * 3.0 - w.transpose() * w;
  EXPECT_LT((c - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.norm());
  EXPECT_EQ(c, c.transpose());
}
