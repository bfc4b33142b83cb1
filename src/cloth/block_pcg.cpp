#include "cloth/block_pcg.hpp"

#include <algorithm>
#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

/// Reductions kept per chunk.
constexpr int kPartials = 3;
/// Systems smaller than this many vertices run on one thread (the fork costs more than it saves).
constexpr int kParallelMinVertices = 8 * kPcgChunkVertices;

int num_chunks(int num_vertices) {
  return (num_vertices + kPcgChunkVertices - 1) / kPcgChunkVertices;
}

/// Calls body(first, last, chunk) for each chunk of vertices [first, last), on `threads` OpenMP
/// threads when the system is large. Chunks are fixed by |V| alone, never by the thread count.
template <class Body>
void for_each_chunk(int num_vertices, int threads, const Body& body) {
  const int chunks = num_chunks(num_vertices);
#pragma omp parallel for schedule(static) num_threads(threads) \
    if (threads > 1 && num_vertices >= kParallelMinVertices)
  for (int c = 0; c < chunks; ++c) {
    const int first = c * kPcgChunkVertices;
    body(first, std::min(first + kPcgChunkVertices, num_vertices), c);
  }
}

/// Sum of reduction k over all chunks, in chunk order (deterministic).
double sum_partials(const std::vector<double>& partial, int chunks, int k) {
  double sum = 0.0;
  for (int c = 0; c < chunks; ++c) sum += partial[static_cast<std::size_t>(kPartials * c + k)];
  return sum;
}

/// Block row i of A·x: Σ_j A_ij·x_j, with block (i, j) stored as the transpose of (j, i).
Vec3 row_product(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& x,
                 int i) {
  Vec3 yi = Vec3::Zero();
  for (int b = p.col_start[static_cast<std::size_t>(i)];
       b < p.col_start[static_cast<std::size_t>(i) + 1]; ++b) {
    yi.noalias() += blocks[static_cast<std::size_t>(b)].transpose() *
                    x.segment<3>(3 * p.row[static_cast<std::size_t>(b)]);
  }
  return yi;
}

}  // namespace

void block_multiply(const SystemPattern& p, std::span<const Mat3> blocks, const Eigen::VectorXd& x,
                    Eigen::VectorXd& y, WorkerPool* pool) {
  DEXCLOTH_ASSERT(x.size() == 3 * p.num_vertices && y.size() == 3 * p.num_vertices);
  const int nv = p.num_vertices;
  for_each_index(nv >= kParallelMinVertices ? pool : nullptr,
                 static_cast<std::size_t>(num_chunks(nv)), [&](std::size_t chunk) {
                   const int first = static_cast<int>(chunk) * kPcgChunkVertices;
                   const int last = std::min(first + kPcgChunkVertices, nv);
                   for (int i = first; i < last; ++i)
                     y.segment<3>(3 * i) = row_product(p, blocks, x, i);
                 });
}

void BlockPcg::resize(int num_vertices) {
  m_inv_diag.resize(static_cast<std::size_t>(num_vertices));
  for (Eigen::VectorXd* v : {&m_r, &m_z, &m_p, &m_q}) v->resize(3 * num_vertices);
  m_partial.resize(static_cast<std::size_t>(kPartials * num_chunks(num_vertices)));
}

PcgResult BlockPcg::solve(const SystemPattern& p, std::span<const Mat3> blocks,
                          const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                          int max_iterations, int threads) {
  DEXCLOTH_DEMAND(m_r.size() == 3 * p.num_vertices);
  const int nv = p.num_vertices;
  const int chunks = num_chunks(nv);
  const auto partial = [&](int chunk, int k) -> double& {
    return m_partial[static_cast<std::size_t>(kPartials * chunk + k)];
  };

  // Block-Jacobi preconditioner M⁻¹, r = b − A·x, z = M⁻¹r, p = z; sums of b·b, r·r, r·z.
  for_each_chunk(nv, threads, [&](int first, int last, int chunk) {
    double bb = 0.0, rr = 0.0, rz = 0.0;
    for (int i = first; i < last; ++i) {
      const auto iu = static_cast<std::size_t>(i);
      m_inv_diag[iu] = blocks[static_cast<std::size_t>(p.diagonal[iu])].inverse();
      const Vec3 bi = b.segment<3>(3 * i);
      const Vec3 ri = bi - row_product(p, blocks, x, i);
      const Vec3 zi = m_inv_diag[iu] * ri;
      m_r.segment<3>(3 * i) = ri;
      m_z.segment<3>(3 * i) = zi;
      m_p.segment<3>(3 * i) = zi;
      bb += bi.squaredNorm();
      rr += ri.squaredNorm();
      rz += ri.dot(zi);
    }
    partial(chunk, 0) = bb;
    partial(chunk, 1) = rr;
    partial(chunk, 2) = rz;
  });
  PcgResult out;
  const double b_norm = std::sqrt(sum_partials(m_partial, chunks, 0));
  const double scale = b_norm > 0.0 ? b_norm : 1.0;
  out.residual = std::sqrt(sum_partials(m_partial, chunks, 1)) / scale;
  if (out.residual <= tolerance) {
    out.converged = true;
    return out;
  }
  double rz = sum_partials(m_partial, chunks, 2);

  for (int it = 1; it <= max_iterations; ++it) {
    // q = A·p and p·q.
    for_each_chunk(nv, threads, [&](int first, int last, int chunk) {
      double pq = 0.0;
      for (int i = first; i < last; ++i) {
        const Vec3 qi = row_product(p, blocks, m_p, i);
        m_q.segment<3>(3 * i) = qi;
        pq += m_p.segment<3>(3 * i).dot(qi);
      }
      partial(chunk, 0) = pq;
    });
    const double pq = sum_partials(m_partial, chunks, 0);
    if (!(pq > 0.0) || !std::isfinite(pq)) break;  // not SPD (or NaN): stop, not converged
    const double alpha = rz / pq;

    // x += α·p, r −= α·q, z = M⁻¹r; r·r and r·z.
    for_each_chunk(nv, threads, [&](int first, int last, int chunk) {
      double rr = 0.0, rz_chunk = 0.0;
      for (int i = first; i < last; ++i) {
        x.segment<3>(3 * i) += alpha * m_p.segment<3>(3 * i);
        const Vec3 ri = m_r.segment<3>(3 * i) - alpha * m_q.segment<3>(3 * i);
        const Vec3 zi = m_inv_diag[static_cast<std::size_t>(i)] * ri;
        m_r.segment<3>(3 * i) = ri;
        m_z.segment<3>(3 * i) = zi;
        rr += ri.squaredNorm();
        rz_chunk += ri.dot(zi);
      }
      partial(chunk, 1) = rr;
      partial(chunk, 2) = rz_chunk;
    });
    out.iterations = it;
    out.residual = std::sqrt(sum_partials(m_partial, chunks, 1)) / scale;
    if (out.residual <= tolerance) {
      out.converged = true;
      return out;
    }
    const double rz_next = sum_partials(m_partial, chunks, 2);
    const double beta = rz_next / rz;
    rz = rz_next;

    // p = z + β·p.
    for_each_chunk(nv, threads, [&](int first, int last, int /*chunk*/) {
      const int n = 3 * (last - first);
      m_p.segment(3 * first, n) = m_z.segment(3 * first, n) + beta * m_p.segment(3 * first, n);
    });
  }
  return out;
}

}  // namespace dexcloth::cloth
