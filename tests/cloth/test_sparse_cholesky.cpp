// The supernodal sparse Cholesky factorisation against dense solves.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
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

TEST(SparseCholesky, AFactorisationGatheringItsValuesIsBitwiseTheSame) {
  // The values of A read through an index into a larger, shuffled array (as the cloth's
  // blocks are) must give bitwise the factor of the gathered values, on one or two threads,
  // and a failed pivot at the same column.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const int n = 80;
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Identity(n, n);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (uni(rng) > 0.9) {
        pattern(i, j) = pattern(j, i) = 1;
        A(i, j) = A(j, i) = uni(rng);
      }
  for (int i = 0; i < n; ++i) A(i, i) = A.row(i).cwiseAbs().sum() + 0.1;
  Upper u = compress_upper(A, pattern);
  std::vector<int> source(u.value.size());
  for (std::size_t k = 0; k < source.size(); ++k) source[k] = static_cast<int>(k);
  std::shuffle(source.begin(), source.end(), rng);
  std::vector<double> base(2 * u.value.size(), std::nan(""));  // unread entries are NaN
  for (std::size_t k = 0; k < source.size(); ++k)
    base[static_cast<std::size_t>(source[k])] = u.value[k];
  const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(n, [&] { return uni(rng); });
  for (int threads : {1, 2}) {
    SparseCholesky gathered, direct;
    gathered.analyze(n, u.col_start, u.row, threads);
    direct.analyze(n, u.col_start, u.row, threads);
    ASSERT_EQ(gathered.factorize(base, source), -1);
    ASSERT_EQ(direct.factorize(u.value), -1);
    Eigen::VectorXd x = b, y = b;
    gathered.solve_in_place(std::span<double>(x.data(), static_cast<std::size_t>(n)));
    direct.solve_in_place(std::span<double>(y.data(), static_cast<std::size_t>(n)));
    EXPECT_TRUE(x == y) << threads << " threads";
    EXPECT_LE((A * x - b).norm(), 1e-12 * b.norm());
    // An indefinite matrix fails at the same column either way.
    const int last = static_cast<int>(u.value.size()) - 1;  // A(n−1, n−1)
    const double kept = base[static_cast<std::size_t>(source[static_cast<std::size_t>(last)])];
    base[static_cast<std::size_t>(source[static_cast<std::size_t>(last)])] = -1.0;
    u.value[static_cast<std::size_t>(last)] = -1.0;
    EXPECT_EQ(gathered.factorize(base, source), n - 1);
    EXPECT_EQ(direct.factorize(u.value), n - 1);
    base[static_cast<std::size_t>(source[static_cast<std::size_t>(last)])] = kept;
    u.value[static_cast<std::size_t>(last)] = kept;
  }
}

namespace {

/// A block pattern like a cloth's: a grid of vertices joined to their eight neighbours, each
/// with 1 to 3 unknowns, every fifth split in two groups (as a friction vertex's unknowns are:
/// the slip coordinates after every other one), the groups in a shuffled order. Holds the
/// scalar pattern and values (SPD), and the same by blocks: each block's values in a 3×3
/// column-major slot of `block_values`.
struct BlockSystem {
  int n = 0;
  Upper u;
  Eigen::MatrixXd A;
  std::vector<int> groups{0}, block_start{0}, block_row, block_source;
  std::vector<double> block_values;
};

BlockSystem block_system(int side, std::mt19937& rng) {
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::uniform_int_distribution<int> width(1, 3);
  const int nv = side * side;
  std::vector<std::pair<int, int>> parts;  // (vertex, unknowns)
  for (int v = 0; v < nv; ++v) {
    const int w = width(rng);
    if (v % 5 == 0 && w > 1) {
      parts.emplace_back(v, 1);
      parts.emplace_back(v, w - 1);
    } else {
      parts.emplace_back(v, w);
    }
  }
  std::shuffle(parts.begin(), parts.end(), rng);
  BlockSystem s;
  std::vector<int> vertex_of;  // per unknown
  for (const auto& [v, w] : parts) {
    for (int k = 0; k < w; ++k) vertex_of.push_back(v);
    s.groups.push_back(static_cast<int>(vertex_of.size()));
  }
  s.n = static_cast<int>(vertex_of.size());
  const auto coupled = [&](int i, int j) {
    const int a = vertex_of[static_cast<std::size_t>(i)],
              b = vertex_of[static_cast<std::size_t>(j)];
    return std::abs(a % side - b % side) <= 1 && std::abs(a / side - b / side) <= 1;
  };
  Eigen::MatrixXi pattern = Eigen::MatrixXi::Zero(s.n, s.n);
  s.A = Eigen::MatrixXd::Zero(s.n, s.n);
  for (int i = 0; i < s.n; ++i)
    for (int j = i + 1; j < s.n; ++j)
      if (coupled(i, j)) {
        pattern(i, j) = pattern(j, i) = 1;
        s.A(i, j) = s.A(j, i) = uni(rng);
      }
  for (int i = 0; i < s.n; ++i) {
    pattern(i, i) = 1;
    s.A(i, i) = s.A.row(i).cwiseAbs().sum() + 0.1;
  }
  s.u = compress_upper(s.A, pattern);
  const int ng = static_cast<int>(parts.size());
  for (int g = 0; g < ng; ++g) {
    const int g0 = s.groups[static_cast<std::size_t>(g)];
    for (int h = 0; h <= g; ++h) {
      const int h0 = s.groups[static_cast<std::size_t>(h)];
      if (!coupled(h0, g0)) continue;
      s.block_row.push_back(h);
      s.block_source.push_back(static_cast<int>(s.block_values.size()));
      s.block_values.resize(s.block_values.size() + 9, std::nan(""));  // unread entries NaN
      for (int k = g0; k < s.groups[static_cast<std::size_t>(g) + 1]; ++k)
        for (int a = h0; a < s.groups[static_cast<std::size_t>(h) + 1]; ++a)
          s.block_values[static_cast<std::size_t>(s.block_source.back() + (a - h0) +
                                                  3 * (k - g0))] = s.A(a, k);
    }
    s.block_start.push_back(static_cast<int>(s.block_row.size()));
  }
  return s;
}

}  // namespace

TEST(SparseCholesky, AnalysedByBlocksOfAlikeUnknownsTheFactorIsBitwiseTheSame) {
  // The analysis of the groups' pattern and the gather by blocks must give the supernodes,
  // fronts and schedule of the scalar analysis: the same factor and solution, bitwise, on one
  // or two threads, in both precisions.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    const BlockSystem s = block_system(14, rng);
    ASSERT_LT(s.groups.size(), static_cast<std::size_t>(s.n));  // some groups hold several
    const Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(s.n, [&] { return uni(rng); });
    for (int threads : {1, 2})
      for (Precision precision : {Precision::double_precision, Precision::single_precision}) {
        SparseCholesky scalar, blocks;
        scalar.analyze(s.n, s.u.col_start, s.u.row, threads, precision);
        blocks.analyze_blocks(s.groups, s.block_start, s.block_row, s.block_source, 3, threads,
                              precision);
        EXPECT_EQ(blocks.supernodes(), scalar.supernodes());
        EXPECT_EQ(blocks.factor_nonzeros(), scalar.factor_nonzeros());
        EXPECT_EQ(blocks.factor_flops(), scalar.factor_flops());
        EXPECT_EQ(blocks.parallel_share(), scalar.parallel_share());
        ASSERT_EQ(scalar.factorize(s.u.value), -1);
        ASSERT_EQ(blocks.factorize(s.block_values), -1);
        Eigen::VectorXd x = b, y = b;
        scalar.solve_in_place(std::span<double>(x.data(), static_cast<std::size_t>(s.n)));
        blocks.solve_in_place(std::span<double>(y.data(), static_cast<std::size_t>(s.n)));
        EXPECT_TRUE(x == y) << "trial " << trial << ", " << threads << " threads";
        EXPECT_LE((s.A * y - b).norm(),
                  (precision == Precision::double_precision ? 1e-12 : 1e-4) * b.norm());
      }
  }
}

TEST(SparseCholeskyDeathTest, ABlockPatternWithoutItsDiagonalOrWithABlockTwiceIsRefused) {
  // Groups {0, 1} and {2}: the second column's blocks are (0, 1) and its diagonal.
  const std::vector<int> groups{0, 2, 3}, start{0, 1, 3}, source{0, 9, 18};
  SparseCholesky chol;
  chol.analyze_blocks(groups, start, std::vector<int>{0, 0, 1}, source, 3);
  EXPECT_EQ(chol.supernodes(), 1);
  EXPECT_DEATH(chol.analyze_blocks(groups, start, std::vector<int>{0, 0, 0}, source, 3),
               "internal error");  // no diagonal block in the second column, (0, 1) twice
  EXPECT_DEATH(chol.analyze_blocks(groups, std::vector<int>{0, 0, 2}, std::vector<int>{0, 1},
                                   std::vector<int>{0, 9}, 3),
               "internal error");  // no diagonal block in the first column
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

namespace {

/// Appends the cells of the k×k grid's rectangle [x0, x1)×[y0, y1) in nested-dissection order:
/// the two halves across the longer side, then the line between them.
void dissect(int k, int x0, int x1, int y0, int y1, std::vector<int>& order) {
  if ((x1 - x0) * (y1 - y0) <= 6 || x1 - x0 < 3 || y1 - y0 < 3) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) order.push_back(y * k + x);
    return;
  }
  if (x1 - x0 >= y1 - y0) {
    const int m = (x0 + x1) / 2;
    dissect(k, x0, m, y0, y1, order);
    dissect(k, m + 1, x1, y0, y1, order);
    dissect(k, m, m + 1, y0, y1, order);
  } else {
    const int m = (y0 + y1) / 2;
    dissect(k, x0, x1, y0, m, order);
    dissect(k, x0, x1, m + 1, y1, order);
    dissect(k, x0, x1, m, m + 1, order);
  }
}

}  // namespace

TEST(SparseCholesky, SolvesOnThreadsAreBitwiseTheSameAsOnOne) {
  // A 110×110 grid's 9-point stiffness (plus random diagonal) in nested-dissection order, large
  // enough for the threaded solves: on two and three threads the halves go to the threads and
  // the separators to the top, whose rows the forward solve updates late. The full solve and
  // the split solve around a tail of 40 unknowns must agree bitwise with one thread's and
  // solve the system.
  const int k = 110, n = k * k, tail = 40;
  std::vector<int> order;
  dissect(k, 0, k, 0, k, order);
  ASSERT_EQ(static_cast<int>(order.size()), n);
  std::vector<int> position(static_cast<std::size_t>(n));
  for (int p = 0; p < n; ++p)
    position[static_cast<std::size_t>(order[static_cast<std::size_t>(p)])] = p;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  // A by columns (upper triangle kept for the factorisation), off-diagonal entries in (−1, −½].
  std::vector<std::vector<std::pair<int, double>>> column(static_cast<std::size_t>(n));
  std::vector<double> diagonal(static_cast<std::size_t>(n), 0.0);
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int i = position[static_cast<std::size_t>(y * k + x)];
          if (x + dx < 0 || x + dx >= k || y + dy < 0 || y + dy >= k || (dx == 0 && dy == 0))
            continue;
          const int j = position[static_cast<std::size_t>((y + dy) * k + x + dx)];
          if (i > j) continue;  // each pair once
          const double a = -0.5 - 0.5 * uni(rng);
          column[static_cast<std::size_t>(j)].emplace_back(i, a);
          column[static_cast<std::size_t>(i)].emplace_back(j, a);
          diagonal[static_cast<std::size_t>(i)] -= a;
          diagonal[static_cast<std::size_t>(j)] -= a;
        }
  Upper u;
  for (int j = 0; j < n; ++j) {
    for (const auto& [i, a] : column[static_cast<std::size_t>(j)])
      if (i < j) {
        u.row.push_back(i);
        u.value.push_back(a);
      }
    diagonal[static_cast<std::size_t>(j)] += uni(rng);
    u.row.push_back(j);
    u.value.push_back(diagonal[static_cast<std::size_t>(j)]);
    u.col_start.push_back(static_cast<int>(u.row.size()));
  }
  std::vector<double> b(static_cast<std::size_t>(n));
  for (double& v : b) v = uni(rng) - 0.5;
  // ‖A·x − b‖ / ‖b‖.
  const auto residual = [&](const std::vector<double>& x) {
    double r2 = 0.0, b2 = 0.0;
    for (int j = 0; j < n; ++j) {
      double ax = diagonal[static_cast<std::size_t>(j)] * x[static_cast<std::size_t>(j)];
      for (const auto& [i, a] : column[static_cast<std::size_t>(j)])
        ax += a * x[static_cast<std::size_t>(i)];
      r2 += (ax - b[static_cast<std::size_t>(j)]) * (ax - b[static_cast<std::size_t>(j)]);
      b2 += b[static_cast<std::size_t>(j)] * b[static_cast<std::size_t>(j)];
    }
    return std::sqrt(r2 / b2);
  };

  // Both precisions: a single-precision factor solves to float's accuracy (its refinement is
  // the caller's), the same on any number of threads.
  for (const Precision precision : {Precision::double_precision, Precision::single_precision}) {
    const double accuracy = precision == Precision::double_precision ? 1e-12 : 1e-5;
    std::vector<double> one_full, one_split;
    for (int threads : {1, 2, 3}) {
      SparseCholesky chol;
      chol.analyze(n, u.col_start, u.row, threads, precision);
      ASSERT_GT(chol.factor_nonzeros(), 400'000u);  // solved on the threads
      if (threads > 1) {
        EXPECT_LT(chol.parallel_share(), 1.0);  // a top, solved after them
      }
      ASSERT_EQ(chol.factorize(u.value), -1);
      std::vector<double> full = b;
      chol.solve_in_place(full);
      // The split solve, with the tail set to the full solve's.
      std::vector<double> split = b;
      chol.forward_in_place(split);
      std::copy(full.end() - tail, full.end(), split.end() - tail);
      chol.backward_in_place(split, tail);
      if (threads == 1) {
        one_full = full;
        one_split = split;
        EXPECT_LT(residual(full), accuracy);
        EXPECT_LT(residual(split), accuracy);
        if (precision == Precision::single_precision) {
          EXPECT_GT(residual(full), 1e-10);  // it is float's
        }
      } else {
        EXPECT_EQ(full, one_full) << threads << " threads";
        EXPECT_EQ(split, one_split) << threads << " threads";
        // On a lent pool of the analysed size, which the factorisation and the solves then
        // run on, bitwise the same; one of another size is left for the factor's own threads.
        for (const int lent_threads : {threads, threads + 1}) {
          dexcloth::WorkerPool lent(lent_threads);
          chol.lend_pool(&lent);
          ASSERT_EQ(chol.factorize(u.value), -1);
          std::vector<double> again = b;
          chol.solve_in_place(again);
          chol.lend_pool(nullptr);
          EXPECT_EQ(again, one_full) << threads << " threads, lent " << lent_threads;
          // The factorisation, the forward and the backward solve: a dispatch each.
          EXPECT_EQ(lent.dispatched(), lent_threads == threads ? 3 : 0)
              << threads << " threads, lent " << lent_threads;
        }
      }
    }
  }
}
