#include "cloth/collision/unfolded_subtrees.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "cloth/collision/rest_neighbours.hpp"
#include "core/assert.hpp"

namespace dexcloth::collision {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The pool that shares out the root's two subtrees, one on each thread, where the tree is
/// worth it; else none.
WorkerPool* halves_pool(const Bvh& bvh, WorkerPool* pool) {
  return pool != nullptr && pool->threads() > 1 && bvh.num_faces() >= kParallelQueryFaces ? pool
                                                                                          : nullptr;
}

// Smallest singular value of the 3×2 matrix f.
double sigma_min(const double (&f)[3][2]) {
  double p = 0.0, q = 0.0, s = 0.0;
  for (int j = 0; j < 3; ++j) {
    p += f[j][0] * f[j][0];
    q += f[j][0] * f[j][1];
    s += f[j][1] * f[j][1];
  }
  const double lambda = 0.5 * (p + s) - std::hypot(0.5 * (p - s), q);
  return std::sqrt(std::max(0.0, lambda));
}

// Frobenius norm of f − g (at least its spectral norm).
double difference_norm(const double (&f)[3][2], const double (&g)[3][2]) {
  double sq = 0.0;
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 2; ++k) sq += (f[j][k] - g[j][k]) * (f[j][k] - g[j][k]);
  return std::sqrt(sq);
}

}  // namespace

void UnfoldedSubtrees::build(const Points& rest, const Triangles& faces, const Bvh& bvh) {
  DEXCLOTH_DEMAND(rest.rows() > 0 && faces.rows() == bvh.num_faces());
  // The rest plane: through the centroid, normal to the rest vertices' least spread.
  const Vec3 centre = rest.colwise().mean().transpose();
  Mat3 spread = Mat3::Zero();
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Vec3 d = rest.row(v).transpose() - centre;
    spread += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(spread);
  const Vec3 normal = eigen.eigenvectors().col(0);
  const Vec3 e0 = eigen.eigenvectors().col(2), e1 = eigen.eigenvectors().col(1);
  m_uv.resize(static_cast<std::size_t>(2 * rest.rows()));
  m_flatness = 0.0;
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Vec3 d = rest.row(v).transpose() - centre;
    m_uv[static_cast<std::size_t>(2 * v)] = d.dot(e0);
    m_uv[static_cast<std::size_t>(2 * v + 1)] = d.dot(e1);
    m_flatness = std::max(m_flatness, std::abs(d.dot(normal)));
  }
  m_separation = -1.0;
  // Rest boxes, children before parents.
  m_nodes = bvh.num_nodes();
  m_box.assign(static_cast<std::size_t>(4 * m_nodes), 0.0);
  for (int i = m_nodes - 1; i >= 0; --i) {
    double* box = &m_box[static_cast<std::size_t>(4 * i)];
    const int face = bvh.leaf_face(i);
    if (face >= 0) {
      box[0] = box[1] = kInfinity;
      box[2] = box[3] = -kInfinity;
      for (int k = 0; k < 3; ++k) {
        const auto v = static_cast<std::size_t>(faces(face, k));
        for (int a = 0; a < 2; ++a) {
          box[a] = std::min(box[a], m_uv[2 * v + static_cast<std::size_t>(a)]);
          box[2 + a] = std::max(box[2 + a], m_uv[2 * v + static_cast<std::size_t>(a)]);
        }
      }
      continue;
    }
    const double* l = &m_box[static_cast<std::size_t>(4 * (i + 1))];
    const double* r = &m_box[static_cast<std::size_t>(4 * bvh.right_child(i))];
    for (int a = 0; a < 2; ++a) {
      box[a] = std::min(l[a], r[a]);
      box[2 + a] = std::max(l[2 + a], r[2 + a]);
    }
  }
  // Each base subtree's vertices, once, and the rest moments of every node over them.
  m_vertex_begin.assign(static_cast<std::size_t>(m_nodes), 0);
  m_vertex_end.assign(static_cast<std::size_t>(m_nodes), 0);
  m_vertices.clear();
  m_rest.assign(static_cast<std::size_t>(m_nodes), RestMoments());
  // Base subtrees: of at most kBaseFaces faces, under a bigger parent (nodes within are unused).
  std::vector<std::uint8_t> within(static_cast<std::size_t>(m_nodes), 0);
  for (int i = 0; i < m_nodes; ++i)
    if (bvh.leaf_face(i) < 0 &&
        (within[static_cast<std::size_t>(i)] != 0 || bvh.subtree_faces(i) <= kBaseFaces)) {
      within[static_cast<std::size_t>(i + 1)] = 1;
      within[static_cast<std::size_t>(bvh.right_child(i))] = 1;
    }
  for (int i = m_nodes - 1; i >= 0; --i) {
    const auto node = static_cast<std::size_t>(i);
    if (within[node] != 0) continue;
    RestMoments& rm = m_rest[node];
    const int n = bvh.subtree_faces(i);
    if (n <= kBaseFaces) {
      const auto start = m_vertices.size();
      for (int j = i; j < i + 2 * n - 1; ++j) {
        const int face = bvh.leaf_face(j);
        if (face < 0) continue;
        for (int k = 0; k < 3; ++k) {
          const int v = faces(face, k);
          if (std::find(m_vertices.begin() + static_cast<std::ptrdiff_t>(start), m_vertices.end(),
                        v) == m_vertices.end())
            m_vertices.push_back(v);
        }
      }
      m_vertex_begin[node] = static_cast<int>(start);
      m_vertex_end[node] = static_cast<int>(m_vertices.size());
      for (auto k = start; k < m_vertices.size(); ++k) {
        const auto v = static_cast<std::size_t>(m_vertices[k]);
        const double u0 = m_uv[2 * v], u1 = m_uv[2 * v + 1];
        rm.w += 1.0;
        rm.su[0] += u0;
        rm.su[1] += u1;
        rm.suu[0] += u0 * u0;
        rm.suu[1] += u0 * u1;
        rm.suu[2] += u1 * u1;
      }
    } else {
      // Children after their parent and listed in reverse: the right child's vertices first.
      const auto l = node + 1, r = static_cast<std::size_t>(bvh.right_child(i));
      m_vertex_begin[node] = m_vertex_begin[r];
      m_vertex_end[node] = m_vertex_end[l];
      DEXCLOTH_DEMAND(m_vertex_end[r] == m_vertex_begin[l]);
      rm.w = m_rest[l].w + m_rest[r].w;
      for (int a = 0; a < 2; ++a) rm.su[a] = m_rest[l].su[a] + m_rest[r].su[a];
      for (int a = 0; a < 3; ++a) rm.suu[a] = m_rest[l].suu[a] + m_rest[r].suu[a];
    }
    finish(rm);
  }
  m_fitted.assign(static_cast<std::size_t>(m_nodes), -1);
  int fitted = 0;
  for (int i = 0; i < m_nodes; ++i)
    if (within[static_cast<std::size_t>(i)] == 0 && bvh.leaf_face(i) < 0)
      m_fitted[static_cast<std::size_t>(i)] = fitted++;
  // The signature (FNV-1a) of what the fits depend on besides the positions: the tree's shape
  // and leaves, the base subtrees' vertices and the rest plane.
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&](const void* data, std::size_t bytes) {
    for (std::size_t k = 0; k < bytes; ++k) {
      hash ^= static_cast<const unsigned char*>(data)[k];
      hash *= 1099511628211ull;
    }
  };
  for (int i = 0; i < m_nodes; ++i) {
    const int node[2] = {bvh.right_child(i), bvh.leaf_face(i)};
    mix(node, sizeof node);
  }
  mix(m_vertices.data(), m_vertices.size() * sizeof(int));
  mix(m_uv.data(), m_uv.size() * sizeof(double));
  m_signature = hash;
  m_fitted_count = fitted;
  m_shared = nullptr;
  clear(m_own);
  m_flags.assign(static_cast<std::size_t>(m_nodes), 0);
}

void UnfoldedSubtrees::clear(KeptFits& kept) const {
  kept.tree = m_signature;
  for (Fits& f : kept.sets) {
    f.fit.assign(static_cast<std::size_t>(m_fitted_count), Fit());
    f.valid = false;
  }
  kept.recent = 0;
}

void UnfoldedSubtrees::keep_fits_in(KeptFits* kept) {
  if (kept == m_shared || kept == nullptr) return;
  if (kept->tree == 0) clear(*kept);
  if (kept->tree == m_signature) m_shared = kept;
}

double UnfoldedSubtrees::least_separation(const Triangles& faces,
                                          const MeshTopology& topology) const {
  // Every face pair whose rest boxes, inflated by half the longest edge h, overlap; faces
  // farther apart are more than h apart.
  Points plane = Points::Zero(static_cast<Eigen::Index>(m_uv.size() / 2), 3);
  for (Eigen::Index v = 0; v < plane.rows(); ++v) {
    plane(v, 0) = m_uv[static_cast<std::size_t>(2 * v)];
    plane(v, 1) = m_uv[static_cast<std::size_t>(2 * v + 1)];
  }
  double longest = 0.0;
  for (const std::array<int, 2>& e : topology.edges)
    longest = std::max(longest, (plane.row(e[0]) - plane.row(e[1])).norm());
  Bvh tree;
  tree.build(faces, plane, plane, 0.5 * longest);
  std::vector<FacePair> pairs;
  self_overlapping_faces(tree, faces, false, pairs);
  double least = longest;
  const auto corners = [&](int f) {
    return std::array<int, 3>{faces(f, 0), faces(f, 1), faces(f, 2)};
  };
  for (const FacePair& p : pairs) {
    for (const auto& [f, g] : {std::pair{p.a, p.b}, std::pair{p.b, p.a}}) {
      const std::array<int, 3> face = corners(g);
      for (int k = 0; k < 3; ++k) {
        const int v = faces(f, k);
        if (v == face[0] || v == face[1] || v == face[2]) continue;
        least = std::min(least, rest_vertex_face_distance(plane, v, face));
      }
    }
    for (const int ea : topology.face_edges[static_cast<std::size_t>(p.a)])
      for (const int eb : topology.face_edges[static_cast<std::size_t>(p.b)]) {
        const std::array<int, 2>& a = topology.edges[static_cast<std::size_t>(ea)];
        const std::array<int, 2>& b = topology.edges[static_cast<std::size_t>(eb)];
        if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
        least = std::min(least, rest_edge_edge_distance(plane, a, b));
      }
  }
  return least;
}

double UnfoldedSubtrees::separation(const Triangles& faces, const MeshTopology& topology) {
  if (m_separation < 0.0) m_separation = least_separation(faces, topology);
  return m_separation;
}

void UnfoldedSubtrees::finish(RestMoments& rest) {
  rest.u[0] = rest.su[0] / rest.w;
  rest.u[1] = rest.su[1] / rest.w;
  const double a = rest.suu[0] / rest.w - rest.u[0] * rest.u[0];
  const double b = rest.suu[1] / rest.w - rest.u[0] * rest.u[1];
  const double c = rest.suu[2] / rest.w - rest.u[1] * rest.u[1];
  const double det = a * c - b * b;
  if (!(det > 1e-12 * (a + c) * (a + c))) return;  // degenerate (collinear): no fit
  rest.inverse[0] = c / det;
  rest.inverse[1] = -b / det;
  rest.inverse[2] = a / det;
}

UnfoldedSubtrees::Fit UnfoldedSubtrees::fit(const Moments& mo, const RestMoments& rest) {
  Fit ft;
  if (rest.inverse[0] == 0.0 && rest.inverse[2] == 0.0) {
    ft.rho = kInfinity;
    return ft;
  }
  for (int j = 0; j < 3; ++j) {
    ft.x[j] = mo.sx[j] / rest.w;
    // Covariance of x with u, times the inverse of u's.
    const double c0 = mo.sxu[j][0] / rest.w - ft.x[j] * rest.u[0];
    const double c1 = mo.sxu[j][1] / rest.w - ft.x[j] * rest.u[1];
    ft.f[j][0] = c0 * rest.inverse[0] + c1 * rest.inverse[1];
    ft.f[j][1] = c0 * rest.inverse[1] + c1 * rest.inverse[2];
  }
  return ft;
}

double UnfoldedSubtrees::deviation(const Fit& c, const double* uc, const Fit& n, const double* un,
                                   const double* box) {
  // G_c(u) − G_n(u) = d0 + D u with D = F_c − F_n.
  double d0[3], d[3][2];
  for (int j = 0; j < 3; ++j) {
    d[j][0] = c.f[j][0] - n.f[j][0];
    d[j][1] = c.f[j][1] - n.f[j][1];
    d0[j] = c.x[j] - n.x[j] - c.f[j][0] * uc[0] - c.f[j][1] * uc[1] + n.f[j][0] * un[0] +
            n.f[j][1] * un[1];
  }
  double worst = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    const double u0 = box[(corner & 1) ? 2 : 0], u1 = box[(corner & 2) ? 3 : 1];
    double sq = 0.0;
    for (int j = 0; j < 3; ++j) {
      const double e = d0[j] + d[j][0] * u0 + d[j][1] * u1;
      sq += e * e;
    }
    worst = std::max(worst, sq);
  }
  return std::sqrt(worst);
}

double UnfoldedSubtrees::residual(int i, const Points& x, const Fit& ft,
                                  const RestMoments& rest) const {
  const int* begin = m_vertices.data() + m_vertex_begin[static_cast<std::size_t>(i)];
  const int* end = m_vertices.data() + m_vertex_end[static_cast<std::size_t>(i)];
  double worst = 0.0;
  for (const int* v = begin; v != end; ++v) {
    const double du0 = m_uv[static_cast<std::size_t>(2 * *v)] - rest.u[0];
    const double du1 = m_uv[static_cast<std::size_t>(2 * *v + 1)] - rest.u[1];
    double sq = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double e = x(*v, d) - ft.x[d] - ft.f[d][0] * du0 - ft.f[d][1] * du1;
      sq += e * e;
    }
    worst = std::max(worst, sq);
  }
  return std::sqrt(worst);
}

UnfoldedSubtrees::Moments UnfoldedSubtrees::fit_base(int i, const Points& x,
                                                     std::vector<Fit>& fits) const {
  Moments mo;
  const RestMoments& rest = m_rest[static_cast<std::size_t>(i)];
  const int* begin = m_vertices.data() + m_vertex_begin[static_cast<std::size_t>(i)];
  const int* end = m_vertices.data() + m_vertex_end[static_cast<std::size_t>(i)];
  for (const int* v = begin; v != end; ++v) {
    const double u0 = m_uv[static_cast<std::size_t>(2 * *v)];
    const double u1 = m_uv[static_cast<std::size_t>(2 * *v + 1)];
    for (int d = 0; d < 3; ++d) {
      const double xd = x(*v, d);
      mo.sx[d] += xd;
      mo.sxu[d][0] += xd * u0;
      mo.sxu[d][1] += xd * u1;
    }
  }
  Fit& ft = fits[static_cast<std::size_t>(m_fitted[static_cast<std::size_t>(i)])];
  ft = fit(mo, rest);
  if (ft.rho < kInfinity) ft.rho = residual(i, x, ft, rest);
  return mo;
}

UnfoldedSubtrees::Moments UnfoldedSubtrees::fit_inner(const Bvh& bvh, int i, const Moments& left,
                                                      const Moments& right, const Points& x,
                                                      std::vector<Fit>& fits) const {
  const int l = i + 1, r = bvh.right_child(i);
  Moments mo;
  for (int d = 0; d < 3; ++d) {
    mo.sx[d] = left.sx[d] + right.sx[d];
    mo.sxu[d][0] = left.sxu[d][0] + right.sxu[d][0];
    mo.sxu[d][1] = left.sxu[d][1] + right.sxu[d][1];
  }
  const RestMoments& rest = m_rest[static_cast<std::size_t>(i)];
  Fit& ft = fits[static_cast<std::size_t>(m_fitted[static_cast<std::size_t>(i)])];
  ft = fit(mo, rest);
  if (ft.rho == kInfinity) return mo;
  if (bvh.subtree_faces(i) <= kMeasuredFaces) {
    ft.rho = residual(i, x, ft, rest);
    return mo;
  }
  const Fit& fl = fits[static_cast<std::size_t>(m_fitted[static_cast<std::size_t>(l)])];
  const Fit& fr = fits[static_cast<std::size_t>(m_fitted[static_cast<std::size_t>(r)])];
  ft.rho = std::max(fl.rho + deviation(fl, m_rest[static_cast<std::size_t>(l)].u, ft, rest.u,
                                       &m_box[static_cast<std::size_t>(4 * l)]),
                    fr.rho + deviation(fr, m_rest[static_cast<std::size_t>(r)].u, ft, rest.u,
                                       &m_box[static_cast<std::size_t>(4 * r)]));
  return mo;
}

UnfoldedSubtrees::Moments UnfoldedSubtrees::fit_subtree(const Bvh& bvh, int i, const Points& x,
                                                        std::vector<Fit>& fits) const {
  if (bvh.subtree_faces(i) <= kBaseFaces) return fit_base(i, x, fits);
  const Moments left = fit_subtree(bvh, i + 1, x, fits);
  const Moments right = fit_subtree(bvh, bvh.right_child(i), x, fits);
  return fit_inner(bvh, i, left, right, x, fits);
}

void UnfoldedSubtrees::flag(int begin, int end, const Fits& at0, const Fits* at1) {
  for (int i = begin; i < end; ++i) {
    const int k = m_fitted[static_cast<std::size_t>(i)];
    if (k < 0) continue;
    const Fit& f0 = at0.fit[static_cast<std::size_t>(k)];
    double sigma = sigma_min(f0.f), rho = f0.rho;
    if (at1 != nullptr) {
      const Fit& f1 = at1->fit[static_cast<std::size_t>(k)];
      sigma = std::min(sigma, sigma_min(f1.f)) - 0.5 * difference_norm(f0.f, f1.f);
      rho = std::max(rho, f1.rho);
    }
    m_flags[static_cast<std::size_t>(i)] = sigma * m_distance - 2.0 * rho >= m_needed;
  }
}

const UnfoldedSubtrees::Fits& UnfoldedSubtrees::fits_at(const Bvh& bvh, const Points& x,
                                                        const Fits* busy, WorkerPool* pool) {
  KeptFits& kept = this->kept();
  const auto bytes = static_cast<std::size_t>(x.size()) * sizeof(double);
  for (int k = 0; k < 2; ++k) {
    const Fits& f = kept.sets[k];
    if (f.valid && f.x.rows() == x.rows() && std::memcmp(f.x.data(), x.data(), bytes) == 0) {
      kept.recent = k;
      return f;
    }
  }
  // Into the set used less recently, unless the update holds it.
  const int target = &kept.sets[1 - kept.recent] == busy ? kept.recent : 1 - kept.recent;
  Fits& f = kept.sets[target];
  kept.recent = target;
  ++m_fitted_sets;
  f.x = x;
  // The root's two subtrees each on a thread of its own.
  const int l = 1, r = bvh.right_child(0);
  Moments children[2];
  for_each_index(halves_pool(bvh, pool), 2,
                 [&](std::size_t k) { children[k] = fit_subtree(bvh, k == 0 ? l : r, x, f.fit); });
  fit_inner(bvh, 0, children[0], children[1], x, f.fit);
  f.valid = true;
  return f;
}

void UnfoldedSubtrees::run(const Bvh& bvh, WorkerPool* pool) {
  std::fill(m_flags.begin(), m_flags.end(), 0);
  if (!(m_distance > m_needed) || bvh.subtree_faces(0) <= kBaseFaces) return;
  const Fits& at0 = fits_at(bvh, *m_x[0], nullptr, pool);
  const Fits* at1 = m_x[1] != nullptr ? &fits_at(bvh, *m_x[1], &at0, pool) : nullptr;
  // The flags of the root's two subtrees on two threads, then the root's.
  const int r = bvh.right_child(0);
  for_each_index(halves_pool(bvh, pool), 2,
                 [&](std::size_t k) { flag(k == 0 ? 1 : r, k == 0 ? r : m_nodes, at0, at1); });
  flag(0, 1, at0, at1);
}

void UnfoldedSubtrees::update(const Bvh& bvh, const Points& x, double rest_distance, double reach,
                              WorkerPool* pool) {
  DEXCLOTH_DEMAND(built_for(bvh));
  m_x[0] = &x;
  m_x[1] = nullptr;
  // Rest distances measured in the rest plane are short of the true ones by the flatness at
  // most at each end.
  m_distance = rest_distance - 2.0 * m_flatness;
  m_needed = reach * (1.0 + 1e-9) + 1e-12;  // a margin for rounding
  run(bvh, pool);
}

void UnfoldedSubtrees::update_swept(const Bvh& bvh, const Triangles& faces,
                                    const MeshTopology& topology, const Points& x0,
                                    const Points& x1, double reach, WorkerPool* pool) {
  DEXCLOTH_DEMAND(built_for(bvh) && faces.rows() == bvh.num_faces());
  m_x[0] = &x0;
  m_x[1] = &x1;
  m_distance = separation(faces, topology);  // measured in the rest plane
  m_needed = reach * (1.0 + 1e-9) + 1e-12;
  run(bvh, pool);
}

}  // namespace dexcloth::collision
