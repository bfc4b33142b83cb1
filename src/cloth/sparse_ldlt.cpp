#include "cloth/sparse_ldlt.hpp"

#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::cloth {

namespace {

/// Elimination tree and column counts of L for n nodes of `block`×`block` dense blocks of the
/// upper-triangle pattern (col_start, row): row k of L is the set of nodes reachable in the
/// tree from the nonzeros A(i, k), i < k. A node's last column holds each of its block rows;
/// its first row (a multiple of `block`) stands for the block.
void etree_and_counts(int n, const int* col_start, const int* row, int block,
                      std::vector<int>& parent, std::vector<int>& count, std::vector<int>& flag) {
  const auto un = static_cast<std::size_t>(n);
  parent.assign(un, -1);
  count.assign(un, 0);
  flag.assign(un, -1);
  for (int k = 0; k < n; ++k) {
    flag[static_cast<std::size_t>(k)] = k;
    const int column = block * k + block - 1;
    for (int p = col_start[column]; p < col_start[column + 1]; ++p) {
      if (row[p] % block != 0) continue;
      int i = row[p] / block;
      DEXCLOTH_DEMAND(i >= 0 && i <= k);
      for (; flag[static_cast<std::size_t>(i)] != k; i = parent[static_cast<std::size_t>(i)]) {
        if (parent[static_cast<std::size_t>(i)] == -1) parent[static_cast<std::size_t>(i)] = k;
        ++count[static_cast<std::size_t>(i)];
        flag[static_cast<std::size_t>(i)] = k;
      }
    }
  }
}

}  // namespace

void SparseLdlt::analyze(int n, std::span<const int> col_start, std::span<const int> row,
                         int block) {
  DEXCLOTH_DEMAND(n >= 0 && col_start.size() == static_cast<std::size_t>(n) + 1);
  DEXCLOTH_DEMAND(row.size() == static_cast<std::size_t>(col_start[static_cast<std::size_t>(n)]));
  DEXCLOTH_DEMAND((block == 1 || block == 3) && n % block == 0);
  const auto un = static_cast<std::size_t>(n);
  m_n = n;
  m_Ap.assign(col_start.begin(), col_start.end());
  m_Ai.assign(row.begin(), row.end());
  m_Lp.assign(un + 1, 0);
  if (block == 1) {
    etree_and_counts(n, m_Ap.data(), m_Ai.data(), 1, m_parent, m_Lnz, m_flag);
  } else {
    // The last column of a vertex holds every block row of its block column once per row of
    // the block; the rows 3q stand for block q. Within a vertex the unknowns chain (3v → 3v+1
    // → 3v+2), and 3v+2 hangs under the first unknown of the vertex's block parent.
    std::vector<int> block_parent, block_count;
    etree_and_counts(n / 3, m_Ap.data(), m_Ai.data(), 3, block_parent, block_count, m_flag);
    m_parent.assign(un, -1);
    m_Lnz.assign(un, 0);
    for (int v = 0; v < n / 3; ++v) {
      const int P = block_parent[static_cast<std::size_t>(v)];
      for (int c = 0; c < 3; ++c) {
        const auto k = static_cast<std::size_t>(3 * v + c);
        m_parent[k] = c < 2 ? 3 * v + c + 1 : (P < 0 ? -1 : 3 * P);
        m_Lnz[k] = (2 - c) + 3 * block_count[static_cast<std::size_t>(v)];
      }
    }
    m_flag.assign(un, -1);
  }
  for (std::size_t k = 0; k < un; ++k) m_Lp[k + 1] = m_Lp[k] + m_Lnz[k];

  // Numeric buffers (factorize writes every entry of L before reading it).
  m_Li.resize(static_cast<std::size_t>(m_Lp[un]));
  m_Lx.resize(static_cast<std::size_t>(m_Lp[un]));
  m_D.assign(un, 0.0);
  m_y.assign(un, 0.0);
  m_pattern.assign(un, 0);
}

int SparseLdlt::factorize(std::span<const double> values) {
  DEXCLOTH_DEMAND(values.size() == m_Ai.size());
  const int n = m_n;
  int* const flag = m_flag.data();
  int* const parent = m_parent.data();
  int* const Lnz = m_Lnz.data();
  int* const Lp = m_Lp.data();
  int* const Li = m_Li.data();
  int* const pattern = m_pattern.data();
  double* const Lx = m_Lx.data();
  double* const D = m_D.data();
  double* const y = m_y.data();

  for (int k = 0; k < n; ++k) {
    // Scatter column k of A into y and find the pattern of row k of L (topological order).
    y[k] = 0.0;
    int top = n;
    flag[k] = k;
    Lnz[k] = 0;
    for (int p = m_Ap[k]; p < m_Ap[k + 1]; ++p) {
      int i = m_Ai[p];
      y[i] += values[p];
      int len = 0;
      for (; flag[i] != k; i = parent[i]) {
        pattern[len++] = i;
        flag[i] = k;
      }
      while (len > 0) pattern[--top] = pattern[--len];
    }
    // Sparse triangular solve for row k of L, accumulating the pivot D(k).
    D[k] = y[k];
    y[k] = 0.0;
    for (; top < n; ++top) {
      const int i = pattern[top];
      const double yi = y[i];
      y[i] = 0.0;
      const int end = Lp[i] + Lnz[i];
      for (int p = Lp[i]; p < end; ++p) y[Li[p]] -= Lx[p] * yi;
      const double l_ki = yi / D[i];
      D[k] -= l_ki * yi;
      Li[end] = k;
      Lx[end] = l_ki;
      ++Lnz[i];
    }
    if (!(D[k] > 0.0) || !std::isfinite(D[k])) return k;
  }
  return -1;
}

void SparseLdlt::solve_in_place(std::span<double> b) const {
  forward_in_place(b);
  backward_in_place(b, 0);
}

void SparseLdlt::forward_in_place(std::span<double> b) const {
  DEXCLOTH_DEMAND(b.size() == static_cast<std::size_t>(m_n));
  const int* const Lp = m_Lp.data();
  const int* const Li = m_Li.data();
  const double* const Lx = m_Lx.data();
  double* const x = b.data();
  for (int j = 0; j < m_n; ++j) {
    const double xj = x[j];
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) x[Li[p]] -= Lx[p] * xj;
  }
}

void SparseLdlt::backward_in_place(std::span<double> b, int tail) const {
  DEXCLOTH_DEMAND(b.size() == static_cast<std::size_t>(m_n) && tail >= 0 && tail <= m_n);
  const int* const Lp = m_Lp.data();
  const int* const Li = m_Li.data();
  const double* const Lx = m_Lx.data();
  double* const x = b.data();
  const int lead = m_n - tail;
  // D·w = z, then Lᵀ·x = w, for the leading unknowns (the tail holds its solution already).
  for (int j = 0; j < lead; ++j) x[j] /= m_D[static_cast<std::size_t>(j)];
  for (int j = lead - 1; j >= 0; --j) {
    double xj = x[j];
    for (int p = Lp[j]; p < Lp[j + 1]; ++p) xj -= Lx[p] * x[Li[p]];
    x[j] = xj;
  }
}

void SparseLdlt::trailing_factor(int tail, Eigen::MatrixXd& L22, Eigen::VectorXd& D2) const {
  DEXCLOTH_DEMAND(tail >= 0 && tail <= m_n);
  const int lead = m_n - tail;
  L22.setIdentity(tail, tail);
  D2.resize(tail);
  for (int j = lead; j < m_n; ++j) {
    D2[j - lead] = m_D[static_cast<std::size_t>(j)];
    for (int p = m_Lp[static_cast<std::size_t>(j)]; p < m_Lp[static_cast<std::size_t>(j) + 1]; ++p)
      L22(m_Li[static_cast<std::size_t>(p)] - lead, j - lead) = m_Lx[static_cast<std::size_t>(p)];
  }
}

}  // namespace dexcloth::cloth
