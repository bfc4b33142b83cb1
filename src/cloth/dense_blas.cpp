#include "cloth/dense_blas.hpp"

#include <algorithm>

#include "cloth/blas.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

int size(Eigen::Index n) { return static_cast<int>(n); }
/// A leading dimension: at least 1, as BLAS requires even of empty matrices.
int lead(Eigen::Index n) { return n > 0 ? static_cast<int>(n) : 1; }

/// The lower triangle of the square `a` copied over its upper one.
void mirror_lower(Eigen::MatrixXd& a) { a.triangularView<Eigen::StrictlyUpper>() = a.transpose(); }

}  // namespace

void lower_times_transpose(const Eigen::MatrixXd& l, Eigen::MatrixXd& s) {
  DEXCLOTH_DEMAND(l.rows() == l.cols());
  // LAPACK's dlauum forms U·Uᵀ of an upper-triangular U in a third of a general product's flops.
  // With J the reversal of the unknowns, U = J·L·J is upper triangular and J·S·J = U·Uᵀ.
  // Reversing both the rows and the columns of a column-major matrix reverses its storage.
  const Eigen::Index n = l.rows();
  s.resize(n, n);
  std::reverse_copy(l.data(), l.data() + l.size(), s.data());
  s.triangularView<Eigen::StrictlyLower>().setZero();
  int info = 0;
  const int nn = size(n), ld = lead(n);
  if (n > 0) dlauum_("U", &nn, s.data(), &ld, &info, 1);
  DEXCLOTH_ASSERT(info == 0);
  s.triangularView<Eigen::StrictlyLower>() = s.transpose();
  std::reverse(s.data(), s.data() + s.size());
}

bool cholesky_lower(Eigen::MatrixXd& a) {
  DEXCLOTH_DEMAND(a.rows() == a.cols());
  if (a.rows() == 0) return true;
  int info = 0;
  const int n = size(a.rows()), ld = lead(a.rows());
  dpotrf_("L", &n, a.data(), &ld, &info, 1);
  return info == 0;
}

void cholesky_solve(const Eigen::MatrixXd& l, Eigen::VectorXd& b) {
  DEXCLOTH_DEMAND(l.rows() == l.cols() && b.size() == l.rows());
  if (b.size() == 0) return;
  int info = 0;
  const int n = size(l.rows()), ld = lead(l.rows()), one = 1;
  dpotrs_("L", &n, &one, l.data(), &ld, b.data(), &ld, &info, 1);
  DEXCLOTH_ASSERT(info == 0);
}

void solve_lower(const Eigen::MatrixXd& l, Eigen::MatrixXd& b) {
  DEXCLOTH_DEMAND(l.rows() == l.cols() && b.rows() == l.rows());
  if (b.size() == 0) return;
  const int n = size(l.rows()), k = size(b.cols()), ld = lead(l.rows());
  const double one = 1.0;
  dtrsm_("L", "L", "N", "N", &n, &k, &one, l.data(), &ld, b.data(), &ld, 1, 1, 1, 1);
}

void solve_lower(const Eigen::MatrixXd& l, Eigen::VectorXd& b) {
  DEXCLOTH_DEMAND(l.rows() == l.cols() && b.size() == l.rows());
  if (b.size() == 0) return;
  const int n = size(l.rows()), ld = lead(l.rows()), inc = 1;
  dtrsv_("L", "N", "N", &n, l.data(), &ld, b.data(), &inc, 1, 1, 1);
}

void solve_lower_transposed(const Eigen::MatrixXd& l, Eigen::VectorXd& b) {
  DEXCLOTH_DEMAND(l.rows() == l.cols() && b.size() == l.rows());
  if (b.size() == 0) return;
  const int n = size(l.rows()), ld = lead(l.rows()), inc = 1;
  dtrsv_("L", "T", "N", &n, l.data(), &ld, b.data(), &inc, 1, 1, 1);
}

void subtract_gram(const Eigen::MatrixXd& w, Eigen::MatrixXd& c) {
  DEXCLOTH_DEMAND(c.rows() == c.cols() && w.cols() == c.rows());
  if (c.size() == 0 || w.rows() == 0) return;
  const int n = size(c.rows()), k = size(w.rows()), ldw = lead(w.rows()), ldc = lead(c.rows());
  const double minus_one = -1.0, one = 1.0;
  dsyrk_("L", "T", &n, &k, &minus_one, w.data(), &ldw, &one, c.data(), &ldc, 1, 1);
  mirror_lower(c);
}

}  // namespace dexcloth::cloth
