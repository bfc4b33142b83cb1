#include "cloth/collision/unfolded_windows.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/assert.hpp"

namespace dexcloth::collision {

namespace {

using Point2 = std::array<double, 2>;

/// Area of the part of triangle `t` inside the box {lo0, lo1, hi0, hi1} (Sutherland–Hodgman).
double clipped_area(const std::array<Point2, 3>& t, const double* box) {
  std::vector<Point2> poly(t.begin(), t.end()), next;
  for (int side = 0; side < 4 && !poly.empty(); ++side) {
    const int axis = side % 2;
    const bool upper = side >= 2;
    const double bound = box[side];
    const auto inside = [&](const Point2& p) {
      return upper ? p[axis] <= bound : p[axis] >= bound;
    };
    next.clear();
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Point2& a = poly[k];
      const Point2& b = poly[(k + 1) % poly.size()];
      if (inside(a)) next.push_back(a);
      if (inside(a) != inside(b)) {
        const double s = (bound - a[axis]) / (b[axis] - a[axis]);
        Point2 p{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])};
        p[axis] = bound;
        next.push_back(p);
      }
    }
    poly.swap(next);
  }
  double twice = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Point2& a = poly[k];
    const Point2& b = poly[(k + 1) % poly.size()];
    twice += a[0] * b[1] - a[1] * b[0];
  }
  return 0.5 * std::abs(twice);
}

/// Whether segment a–b passes through the open box {lo0, lo1, hi0, hi1} (Liang–Barsky).
bool crosses_interior(const Point2& a, const Point2& b, const double* box) {
  double t0 = 0.0, t1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double d = b[axis] - a[axis];
    for (const auto& [bound, sign] : {std::pair{box[axis], -1.0}, std::pair{box[2 + axis], 1.0}}) {
      // Inside: sign·(a + t·d − bound) < 0.
      const double p = sign * d, q = sign * (bound - a[axis]);
      if (p == 0.0) {
        if (q <= 0.0) return false;
        continue;
      }
      const double t = q / p;
      if (p < 0.0) {
        t0 = std::max(t0, t);
      } else {
        t1 = std::min(t1, t);
      }
    }
  }
  if (!(t0 < t1)) return false;
  const double t = 0.5 * (t0 + t1);
  const Point2 m{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
  return m[0] > box[0] && m[0] < box[2] && m[1] > box[1] && m[1] < box[3];
}

}  // namespace

void UnfoldedWindows::build(std::span<const double> uv, const Triangles& faces,
                            const MeshTopology& topology, std::span<const double> boxes,
                            double stride) {
  DEXCLOTH_DEMAND(stride > 0.0 && boxes.size() % 4 == 0 && faces.rows() > 0);
  const auto nf = static_cast<std::size_t>(faces.rows());
  m_nodes = static_cast<int>(boxes.size() / 4);
  m_stride = stride;
  const auto at = [&](int v) {
    return Point2{uv[2 * static_cast<std::size_t>(v)], uv[2 * static_cast<std::size_t>(v) + 1]};
  };
  // The rest bounding box D of the faces' vertices.
  const Point2 first = at(faces(0, 0));
  double domain[4] = {first[0], first[1], first[0], first[1]};
  m_corners.resize(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = faces(static_cast<Eigen::Index>(f), k);
      m_corners[3 * f + static_cast<std::size_t>(k)] = v;
      const Point2 p = at(v);
      for (int a = 0; a < 2; ++a) {
        domain[a] = std::min(domain[a], p[static_cast<std::size_t>(a)]);
        domain[2 + a] = std::max(domain[2 + a], p[static_cast<std::size_t>(a)]);
      }
    }
  m_origin[0] = domain[0];
  m_origin[1] = domain[1];
  // Cells must fit 16 bits: a cloth longer than 8,000 strides gets wider ones.
  const double size = std::max(domain[2] - domain[0], domain[3] - domain[1]);
  stride = std::max(stride, size / 8000.0);
  const double inverse_stride = 1.0 / stride;
  // Each node's cells (its box is within D, so they lie in [0, columns) × [0, rows)).
  m_cells.resize(static_cast<std::size_t>(m_nodes));
  for (std::size_t i = 0; i < m_cells.size(); ++i)
    for (int a = 0; a < 2; ++a) {
      const auto cell = [&](double u) {
        return static_cast<std::int16_t>(std::floor((u - m_origin[a]) * inverse_stride));
      };
      m_cells[i].lo[a] = cell(boxes[4 * i + static_cast<std::size_t>(a)]);
      m_cells[i].hi[a] = cell(boxes[4 * i + 2 + static_cast<std::size_t>(a)]);
    }
  // The levels: the cells of level k are the first level's halved k times (none beyond a level
  // with at most two cells a side, whose window (0, 0) spans D).
  m_levels.clear();
  const int columns = static_cast<int>((domain[2] - domain[0]) * inverse_stride) + 1;
  const int rows = static_cast<int>((domain[3] - domain[1]) * inverse_stride) + 1;
  std::size_t nw = 0;
  for (int k = 0; k < kLevels; ++k) {
    if (k > 0 && m_levels.back().columns <= 2 && m_levels.back().rows <= 2) break;
    m_levels.push_back({nw, ((columns - 1) >> k) + 1, ((rows - 1) >> k) + 1});
    nw += static_cast<std::size_t>(m_levels.back().columns) *
          static_cast<std::size_t>(m_levels.back().rows);
  }
  // Q of window (c0, c1) of level k: the window grown by a hair (for skips' rounding), clipped
  // to D.
  const auto region = [&](int k, int c0, int c1, double* q) {
    const double s = std::ldexp(stride, k), hair = 1e-9 * s;
    q[0] = std::max(domain[0], m_origin[0] + c0 * s - hair);
    q[1] = std::max(domain[1], m_origin[1] + c1 * s - hair);
    q[2] = std::min(domain[2], m_origin[0] + (c0 + 2) * s + hair);
    q[3] = std::min(domain[3], m_origin[1] + (c1 + 2) * s + hair);
  };
  // The windows of every level whose Q meets the box {lo0, lo1, hi0, hi1}: calls
  // visit(window, Q).
  const auto windows_over = [&](const double* box, auto&& visit) {
    for (std::size_t k = 0; k < m_levels.size(); ++k) {
      const Level& level = m_levels[k];
      const double s = std::ldexp(stride, static_cast<int>(k)), hair = 1e-9 * s;
      const auto first = [&](double lo, double o) {
        return std::max(0, static_cast<int>(std::floor((lo - o - hair) / s)) - 1);
      };
      const auto last = [&](double hi, double o, int count) {
        return std::min(count - 1, static_cast<int>(std::floor((hi - o + hair) / s)));
      };
      for (int c1 = first(box[1], m_origin[1]); c1 <= last(box[3], m_origin[1], level.rows); ++c1)
        for (int c0 = first(box[0], m_origin[0]); c0 <= last(box[2], m_origin[0], level.columns);
             ++c0) {
          double q[4];
          region(static_cast<int>(k), c0, c1, q);
          if (box[0] <= q[2] && q[0] <= box[2] && box[1] <= q[3] && q[1] <= box[3])
            visit(level.window(c0, c1), q);
        }
    }
  };

  // Faces of each window, the area they cover of its Q, and their orientations.
  std::vector<std::vector<int>> lists(nw);
  std::vector<double> area(nw, 0.0);
  std::vector<std::uint8_t> signs(nw, 0);  // bit 0: a face turned one way, bit 1: the other
  m_rest_inverse.assign(4 * nf, 0.0);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::array<Point2, 3> t = {at(m_corners[3 * f]), at(m_corners[3 * f + 1]),
                                     at(m_corners[3 * f + 2])};
    const double e1[2] = {t[1][0] - t[0][0], t[1][1] - t[0][1]};
    const double e2[2] = {t[2][0] - t[0][0], t[2][1] - t[0][1]};
    const double det = e1[0] * e2[1] - e1[1] * e2[0];
    // A face with (next to) no rest area spoils its windows: both signs.
    const std::uint8_t sign = std::abs(det) <= 1e-12 * size * size ? 3 : det > 0.0 ? 1 : 2;
    if (sign != 3) {
      double* inv = &m_rest_inverse[4 * f];  // column-major inverse of [e1 e2]
      inv[0] = e2[1] / det;
      inv[1] = -e1[1] / det;
      inv[2] = -e2[0] / det;
      inv[3] = e1[0] / det;
    }
    double box[4] = {t[0][0], t[0][1], t[0][0], t[0][1]};
    for (const Point2& p : t)
      for (int a = 0; a < 2; ++a) {
        box[a] = std::min(box[a], p[static_cast<std::size_t>(a)]);
        box[2 + a] = std::max(box[2 + a], p[static_cast<std::size_t>(a)]);
      }
    windows_over(box, [&](std::size_t w, const double* q) {
      lists[w].push_back(static_cast<int>(f));
      area[w] += clipped_area(t, q);
      signs[w] |= sign;
    });
  }
  // Edges of other than two faces (the mesh's boundary, or non-manifold) inside a Q, except
  // those along D's sides.
  std::vector<int> edge_faces(topology.edges.size(), 0);
  for (const std::array<int, 3>& fe : topology.face_edges)
    for (int e : fe) ++edge_faces[static_cast<std::size_t>(e)];
  std::vector<std::uint8_t> cut(nw, 0);
  const double side_tolerance = 1e-9 * size;
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    if (edge_faces[e] == 2) continue;
    const Point2 a = at(topology.edges[e][0]), b = at(topology.edges[e][1]);
    bool along_side = false;
    for (int side = 0; side < 4; ++side) {
      const auto axis = static_cast<std::size_t>(side % 2);
      along_side = along_side || (std::abs(a[axis] - domain[side]) <= side_tolerance &&
                                  std::abs(b[axis] - domain[side]) <= side_tolerance);
    }
    if (along_side && edge_faces[e] == 1) continue;
    const double box[4] = {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[0], b[0]),
                           std::max(a[1], b[1])};
    windows_over(box, [&](std::size_t w, const double* q) {
      if (crosses_interior(a, b, q)) cut[w] = 1;
    });
  }
  // Covered once: the areas add up to Q's, one orientation, no boundary inside.
  m_covered.assign(nw, 0);
  m_face_start.assign(1, 0);
  m_faces.clear();
  for (std::size_t k = 0; k < m_levels.size(); ++k)
    for (int c1 = 0; c1 < m_levels[k].rows; ++c1)
      for (int c0 = 0; c0 < m_levels[k].columns; ++c0) {
        const std::size_t w = m_levels[k].window(c0, c1);
        double q[4];
        region(static_cast<int>(k), c0, c1, q);
        const double q_area = (q[2] - q[0]) * (q[3] - q[1]);
        m_covered[w] = q_area > 0.0 && (signs[w] == 1 || signs[w] == 2) && cut[w] == 0 &&
                       std::abs(area[w] - q_area) <= 1e-6 * q_area;
        if (m_covered[w] != 0) m_faces.insert(m_faces.end(), lists[w].begin(), lists[w].end());
        m_face_start.push_back(static_cast<int>(m_faces.size()));
      }
  m_any_covered = std::find(m_covered.begin(), m_covered.end(), 1) != m_covered.end();
  m_state = std::vector<std::atomic<std::uint8_t>>(nw);
  m_sets = 0;
  m_jacobian[0].assign(6 * nf, 0.0);
  m_jacobian[1].clear();
}

void UnfoldedWindows::jacobians(int s, const Points& x, WorkerPool* pool) {
  const std::size_t nf = m_corners.size() / 3;
  std::vector<double>& jac = m_jacobian[s];
  jac.resize(6 * nf);
  const std::size_t pieces = pool != nullptr && pool->threads() > 1 && nf >= 4000 ? 2 : 1;
  for_each_index(pieces > 1 ? pool : nullptr, pieces, [&](std::size_t k) {
    for (std::size_t f = nf * k / pieces; f < nf * (k + 1) / pieces; ++f) {
      const int v0 = m_corners[3 * f], v1 = m_corners[3 * f + 1], v2 = m_corners[3 * f + 2];
      const double* inv = &m_rest_inverse[4 * f];
      for (int d = 0; d < 3; ++d) {
        const double e1 = x(v1, d) - x(v0, d), e2 = x(v2, d) - x(v0, d);
        jac[6 * f + static_cast<std::size_t>(d)] = e1 * inv[0] + e2 * inv[1];
        jac[6 * f + 3 + static_cast<std::size_t>(d)] = e1 * inv[2] + e2 * inv[3];
      }
    }
  });
}

bool UnfoldedWindows::unfolded(std::size_t w) const {
  const int* begin = m_faces.data() + m_face_start[w];
  const int* end = m_faces.data() + m_face_start[w + 1];
  if (begin == end) return false;
  // J₀: the polar factor M·(MᵀM)^(−1/2) of the faces' summed Jacobians M.
  double m[6] = {};
  for (int s = 0; s < m_sets; ++s)
    for (const int* f = begin; f != end; ++f) {
      const double* j = &m_jacobian[s][6 * static_cast<std::size_t>(*f)];
      for (int k = 0; k < 6; ++k) m[k] += j[k];
    }
  const double p = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
  const double q = m[0] * m[3] + m[1] * m[4] + m[2] * m[5];
  const double r = m[3] * m[3] + m[4] * m[4] + m[5] * m[5];
  const double det = p * r - q * q;
  if (!(det > 1e-12 * (p + r) * (p + r))) return false;
  // (MᵀM)^(1/2) = (MᵀM + δI)/τ with δ = √det, τ = √(p + r + 2δ); its inverse is adj/(δ).
  const double delta = std::sqrt(det), tau = std::sqrt(p + r + 2.0 * delta);
  const double i00 = (r + delta) / (tau * delta), i01 = -q / (tau * delta),
               i11 = (p + delta) / (tau * delta);
  double j0[6];
  for (int d = 0; d < 3; ++d) {
    j0[d] = m[d] * i00 + m[3 + d] * i01;
    j0[3 + d] = m[d] * i01 + m[3 + d] * i11;
  }
  // λ_min(sym(J_fᵀJ₀)) ≥ m_needed for every face: with a, c the diagonal and b the off-diagonal,
  // (a + c)/2 − m_needed ≥ √(((a − c)/2)² + b²).
  for (int s = 0; s < m_sets; ++s)
    for (const int* f = begin; f != end; ++f) {
      const double* j = &m_jacobian[s][6 * static_cast<std::size_t>(*f)];
      const double a = j[0] * j0[0] + j[1] * j0[1] + j[2] * j0[2];
      const double c = j[3] * j0[3] + j[4] * j0[4] + j[5] * j0[5];
      const double b = 0.5 * (j[0] * j0[3] + j[1] * j0[4] + j[2] * j0[5] + j[3] * j0[0] +
                              j[4] * j0[1] + j[5] * j0[2]);
      const double mean = 0.5 * (a + c) - m_needed, half = 0.5 * (a - c);
      if (!(mean >= 0.0 && mean * mean >= half * half + b * b)) return false;
    }
  return true;
}

std::uint8_t UnfoldedWindows::resolve(std::size_t w) const {
  const std::uint8_t state =
      m_covered[w] != 0 && m_sets > 0 && unfolded(w) ? kFlagged : kNotFlagged;
  m_state[w].store(state, std::memory_order_relaxed);
  return state;
}

void UnfoldedWindows::start(int sets, double distance, double reach) {
  // κ·distance ≥ reach, with a margin for rounding; no flag where distance is not positive.
  m_sets = distance > 0.0 ? sets : 0;
  m_needed = m_sets > 0 ? (reach * (1.0 + 1e-9) + 1e-12) / distance : 0.0;
  for (std::atomic<std::uint8_t>& state : m_state) state.store(kUnknown, std::memory_order_relaxed);
}

void UnfoldedWindows::update(const Points& x, double distance, double reach, WorkerPool* pool) {
  DEXCLOTH_DEMAND(m_nodes > 0);
  if (distance > 0.0 && m_any_covered) jacobians(0, x, pool);
  start(1, distance, reach);
}

void UnfoldedWindows::update_swept(const Points& x0, const Points& x1, double distance,
                                   double reach, WorkerPool* pool) {
  DEXCLOTH_DEMAND(m_nodes > 0);
  if (distance > 0.0 && m_any_covered) {
    jacobians(0, x0, pool);
    jacobians(1, x1, pool);
  }
  start(2, distance, reach);
}

}  // namespace dexcloth::collision
