#include "cloth/collision/predicates.hpp"

#include <array>
#include <cmath>

namespace dexcloth::collision {

namespace {

// Error-free transformations: a + b = x + y and a·b = x + y exactly.
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// Non-overlapping expansions, increasing magnitude, zeros eliminated (Shewchuk §2).
template <int N>
struct Expansion {
  std::array<double, N> c{};
  int n{};
};

// h = e + b (Grow-Expansion).
template <int N, int M>
void grow(const Expansion<M>& e, double b, Expansion<N>& h) {
  double q = b;
  h.n = 0;
  for (int i = 0; i < e.n; ++i) {
    double x, y;
    two_sum(q, e.c[static_cast<std::size_t>(i)], x, y);
    q = x;
    if (y != 0.0) h.c[static_cast<std::size_t>(h.n++)] = y;
  }
  if (q != 0.0 || h.n == 0) h.c[static_cast<std::size_t>(h.n++)] = q;
}

// h = e + f, one component of f at a time.
template <int N, int A, int B>
void add(const Expansion<A>& e, const Expansion<B>& f, Expansion<N>& h) {
  Expansion<N> tmp;
  tmp.n = e.n;
  for (int i = 0; i < e.n; ++i) tmp.c[static_cast<std::size_t>(i)] = e.c[static_cast<std::size_t>(i)];
  for (int j = 0; j < f.n; ++j) {
    grow(tmp, f.c[static_cast<std::size_t>(j)], h);
    tmp = h;
  }
  h = tmp;
}

// h = e·b (Scale-Expansion).
template <int N, int M>
void scale(const Expansion<M>& e, double b, Expansion<N>& h) {
  h.n = 0;
  if (e.n == 0) return;
  double q, lo;
  two_product(e.c[0], b, q, lo);
  if (lo != 0.0) h.c[static_cast<std::size_t>(h.n++)] = lo;
  for (int i = 1; i < e.n; ++i) {
    double t_hi, t_lo, s, s_lo;
    two_product(e.c[static_cast<std::size_t>(i)], b, t_hi, t_lo);
    two_sum(q, t_lo, s, s_lo);
    if (s_lo != 0.0) h.c[static_cast<std::size_t>(h.n++)] = s_lo;
    two_sum(t_hi, s, q, s_lo);
    if (s_lo != 0.0) h.c[static_cast<std::size_t>(h.n++)] = s_lo;
  }
  if (q != 0.0 || h.n == 0) h.c[static_cast<std::size_t>(h.n++)] = q;
}

// h = e·f.
template <int N, int A, int B>
void multiply(const Expansion<A>& e, const Expansion<B>& f, Expansion<N>& h) {
  h.n = 1;
  h.c[0] = 0.0;
  for (int j = 0; j < f.n; ++j) {
    Expansion<2 * A> part;
    scale(e, f.c[static_cast<std::size_t>(j)], part);
    Expansion<N> sum;
    add(h, part, sum);
    h = sum;
  }
}

template <int N>
int sign(const Expansion<N>& e) {
  for (int i = e.n - 1; i >= 0; --i) {
    const double v = e.c[static_cast<std::size_t>(i)];
    if (v != 0.0) return v > 0.0 ? 1 : -1;
  }
  return 0;
}

Expansion<2> difference(double a, double b) {
  Expansion<2> e;
  double x, y;
  two_sum(a, -b, x, y);
  if (y != 0.0) e.c[static_cast<std::size_t>(e.n++)] = y;
  e.c[static_cast<std::size_t>(e.n++)] = x;
  return e;
}

Expansion<2> negate(Expansion<2> e) {
  for (int i = 0; i < e.n; ++i) e.c[static_cast<std::size_t>(i)] = -e.c[static_cast<std::size_t>(i)];
  return e;
}

// 2×2 determinant p·s − q·r of exact differences.
Expansion<16> det2(const Expansion<2>& p, const Expansion<2>& q, const Expansion<2>& r,
                   const Expansion<2>& s) {
  Expansion<8> ps, qr;
  multiply(p, s, ps);
  multiply(negate(q), r, qr);
  Expansion<16> out;
  add(ps, qr, out);
  return out;
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Expansion<2> bx = difference(b.x(), a.x()), by = difference(b.y(), a.y()),
                     bz = difference(b.z(), a.z());
  const Expansion<2> cx = difference(c.x(), a.x()), cy = difference(c.y(), a.y()),
                     cz = difference(c.z(), a.z());
  const Expansion<2> dx = difference(d.x(), a.x()), dy = difference(d.y(), a.y()),
                     dz = difference(d.z(), a.z());
  // Cofactor expansion along the first column (bx, by, bz).
  Expansion<64> t0, t1, t2;
  multiply(bx, det2(cy, cz, dy, dz), t0);
  multiply(by, det2(cz, cx, dz, dx), t1);
  multiply(bz, det2(cx, cy, dx, dy), t2);
  Expansion<128> s01;
  add(t0, t1, s01);
  Expansion<192> total;
  add(s01, t2, total);
  return sign(total);
}

}  // namespace

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double m0 = v.y() * w.z(), m1 = v.z() * w.y();
  const double n0 = v.z() * w.x(), n1 = v.x() * w.z();
  const double k0 = v.x() * w.y(), k1 = v.y() * w.x();
  const double det = u.x() * (m0 - m1) + u.y() * (n0 - n1) + u.z() * (k0 - k1);
  const double permanent = std::abs(u.x()) * (std::abs(m0) + std::abs(m1)) +
                           std::abs(u.y()) * (std::abs(n0) + std::abs(n1)) +
                           std::abs(u.z()) * (std::abs(k0) + std::abs(k1));
  // Shewchuk's o3derrboundA is (7 + 56ε)ε ≈ 7.8e-16; a larger bound only costs time.
  const double bound = 1e-15 * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient3d_exact(a, b, c, d);
}

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double l = (b.x() - a.x()) * (c.y() - a.y());
  const double r = (b.y() - a.y()) * (c.x() - a.x());
  const double det = l - r;
  const double bound = 1e-15 * (std::abs(l) + std::abs(r));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  const Expansion<16> e =
      det2(difference(b.x(), a.x()), difference(b.y(), a.y()), difference(c.x(), a.x()),
           difference(c.y(), a.y()));
  return sign(e);
}

}  // namespace dexcloth::collision
