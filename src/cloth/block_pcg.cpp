#include "cloth/block_pcg.hpp"

#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::cloth {

void block_multiply(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& x,
                    Eigen::VectorXd& y) {
  DEXCLOTH_ASSERT(x.size() == 3 * p.num_vertices && y.size() == 3 * p.num_vertices);
  // A is symmetric: row i of y gathers block (i, j)·x_j, stored as the transpose of (j, i).
  for (int i = 0; i < p.num_vertices; ++i) {
    Vec3 yi = Vec3::Zero();
    for (int b = p.col_start[static_cast<std::size_t>(i)];
         b < p.col_start[static_cast<std::size_t>(i) + 1]; ++b) {
      yi.noalias() += blocks[static_cast<std::size_t>(b)].transpose() *
                      x.segment<3>(3 * p.row[static_cast<std::size_t>(b)]);
    }
    y.segment<3>(3 * i) = yi;
  }
}

void BlockPcg::resize(int num_vertices) {
  m_inv_diag.resize(static_cast<std::size_t>(num_vertices));
  for (Eigen::VectorXd* v : {&m_r, &m_z, &m_p, &m_q}) v->resize(3 * num_vertices);
}

PcgResult BlockPcg::solve(const SystemPattern& p, std::span<const Mat3> blocks,
                          const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                          int max_iterations) {
  DEXCLOTH_DEMAND(m_r.size() == 3 * p.num_vertices);
  const int nv = p.num_vertices;
  // Block-Jacobi preconditioner.
  for (int i = 0; i < nv; ++i) {
    m_inv_diag[static_cast<std::size_t>(i)] =
        blocks[static_cast<std::size_t>(p.diagonal[static_cast<std::size_t>(i)])].inverse();
  }
  const auto precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    for (int i = 0; i < nv; ++i) {
      z.segment<3>(3 * i).noalias() = m_inv_diag[static_cast<std::size_t>(i)] * r.segment<3>(3 * i);
    }
  };

  // r = b − A·x, z = M⁻¹r, p = z.
  PcgResult out;
  const double b_norm = b.norm();
  const double scale = b_norm > 0.0 ? b_norm : 1.0;
  block_multiply(p, blocks, x, m_q);
  m_r = b - m_q;
  out.residual = m_r.norm() / scale;
  if (out.residual <= tolerance) {
    out.converged = true;
    return out;
  }
  precondition(m_r, m_z);
  m_p = m_z;
  double rz = m_r.dot(m_z);
  for (int it = 1; it <= max_iterations; ++it) {
    block_multiply(p, blocks, m_p, m_q);
    const double pq = m_p.dot(m_q);
    if (!(pq > 0.0) || !std::isfinite(pq)) break;  // not SPD (or NaN): stop, not converged
    const double alpha = rz / pq;
    x.noalias() += alpha * m_p;
    m_r.noalias() -= alpha * m_q;
    out.iterations = it;
    out.residual = m_r.norm() / scale;
    if (out.residual <= tolerance) {
      out.converged = true;
      return out;
    }
    precondition(m_r, m_z);
    const double rz_next = m_r.dot(m_z);
    m_p = m_z + (rz_next / rz) * m_p;
    rz = rz_next;
  }
  return out;
}

}  // namespace dexcloth::cloth
