#include "cloth/substitution_kernels.hpp"

#include <algorithm>
#include <type_traits>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace dexcloth::cloth::kernels {
namespace {

/// Columns a kernel applies at once: a front's panel is read once per four columns.
constexpr int kBlock = 4;

/// dest[r] −= Σ_k L[k·ld + r]·c[k] for r < m, k < cols.
void update_plain(int m, int cols, const float* L, int ld, const float* c, float* dest) {
  for (int r = 0; r < m; ++r) {
    float t = dest[r];
    for (int k = 0; k < cols; ++k) t -= L[k * ld + r] * c[k];
    dest[r] = t;
  }
}

/// s[k] = Σ_r L[k·ld + r]·v[r] for r < m, k < cols.
void dots_plain(int m, int cols, const float* L, int ld, const float* v, float* s) {
  for (int k = 0; k < cols; ++k) {
    float t = 0.0F;
    for (int r = 0; r < m; ++r) t += L[k * ld + r] * v[r];
    s[k] = t;
  }
}

/// The forward step of forward_panel, its column blocks applied by `update` (update_plain's
/// contract): each block's triangle solved, then the rows below it, those of L₁₁ into x₁ and
/// those of L₂₁ into y (their coefficients negated, so that y gets +L₂₁·x₁ exactly as a
/// subtraction of −L₂₁·x₁ would round).
template <class Update>
void forward(int f, int w, const float* L, int ld, float* x1, float* y, Update update) {
  std::fill(y, y + (f - w), 0.0F);
  for (int j0 = 0; j0 < w; j0 += kBlock) {
    const int jb = std::min(kBlock, w - j0);
    const float* block = L + static_cast<long>(j0) * ld;  // columns j0.., from row 0
    float* x = x1 + j0;
    for (int j = 0; j < jb; ++j) {
      x[j] /= block[j * ld + j0 + j];
      for (int i = j + 1; i < jb; ++i) x[i] -= block[j * ld + j0 + i] * x[j];
    }
    update(w - j0 - jb, jb, block + j0 + jb, ld, x, x + jb);
    float minus_x[kBlock];
    for (int k = 0; k < jb; ++k) minus_x[k] = -x[k];
    update(f - w, jb, block + w, ld, minus_x, y);
  }
}

/// The backward step of backward_panel, its column blocks last to first, their products with
/// the known rows and the solved rows below them by `dots` (dots_plain's contract).
template <class Dots>
void backward(int f, int u, const float* L, int ld, float* xu, const float* g, Dots dots) {
  const int below = f - u;
  for (int j1 = u; j1 > 0; j1 -= kBlock) {
    const int j0 = std::max(0, j1 - kBlock), jb = j1 - j0;
    const float* block = L + static_cast<long>(j0) * ld;
    float s[kBlock];
    dots(below, jb, block + u, ld, g, s);
    for (int k = 0; k < jb; ++k) xu[j0 + k] -= s[k];
    dots(u - j1, jb, block + j1, ld, xu + j1, s);
    for (int k = 0; k < jb; ++k) xu[j0 + k] -= s[k];
    for (int j = jb - 1; j >= 0; --j) {
      float t = xu[j0 + j];
      for (int i = j + 1; i < jb; ++i) t -= block[j * ld + j0 + i] * xu[j0 + i];
      xu[j0 + j] = t / block[j * ld + j0 + j];
    }
  }
}

#if defined(__x86_64__)

template <int Cols>
__attribute__((target("avx2,fma"))) void update_avx2(int m, const float* L, int ld, const float* c,
                                                     float* dest) {
  __m256 coefficient[Cols];
  for (int k = 0; k < Cols; ++k) coefficient[k] = _mm256_set1_ps(c[k]);
  int r = 0;
  for (; r + 8 <= m; r += 8) {
    __m256 t = _mm256_loadu_ps(dest + r);
    for (int k = 0; k < Cols; ++k)
      t = _mm256_fnmadd_ps(_mm256_loadu_ps(L + k * ld + r), coefficient[k], t);
    _mm256_storeu_ps(dest + r, t);
  }
  for (; r < m; ++r) {
    float t = dest[r];
    for (int k = 0; k < Cols; ++k) t -= L[k * ld + r] * c[k];
    dest[r] = t;
  }
}

__attribute__((target("avx2,fma"))) float horizontal_sum(__m256 v) {
  __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  s = _mm_add_ps(s, _mm_movehl_ps(s, s));
  s = _mm_add_ss(s, _mm_movehdup_ps(s));
  return _mm_cvtss_f32(s);
}

template <int Cols>
__attribute__((target("avx2,fma"))) void dots_avx2(int m, const float* L, int ld, const float* v,
                                                   float* s) {
  __m256 sum[Cols];
  for (int k = 0; k < Cols; ++k) sum[k] = _mm256_setzero_ps();
  int r = 0;
  for (; r + 8 <= m; r += 8) {
    const __m256 vr = _mm256_loadu_ps(v + r);
    for (int k = 0; k < Cols; ++k)
      sum[k] = _mm256_fmadd_ps(_mm256_loadu_ps(L + k * ld + r), vr, sum[k]);
  }
  for (int k = 0; k < Cols; ++k) {
    float t = horizontal_sum(sum[k]);
    for (int q = r; q < m; ++q) t += L[k * ld + q] * v[q];
    s[k] = t;
  }
}

/// Calls `kernel` with the column count `cols` (1–4) as a compile-time constant.
template <class Kernel>
void with_columns(int cols, Kernel kernel) {
  switch (cols) {
    case 4:
      return kernel(std::integral_constant<int, 4>{});
    case 3:
      return kernel(std::integral_constant<int, 3>{});
    case 2:
      return kernel(std::integral_constant<int, 2>{});
    default:
      return kernel(std::integral_constant<int, 1>{});
  }
}

void update_vector(int m, int cols, const float* L, int ld, const float* c, float* dest) {
  with_columns(cols, [&](auto n) { update_avx2<decltype(n)::value>(m, L, ld, c, dest); });
}

void dots_vector(int m, int cols, const float* L, int ld, const float* v, float* s) {
  with_columns(cols, [&](auto n) { dots_avx2<decltype(n)::value>(m, L, ld, v, s); });
}

bool cpu_has_avx2_fma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

#else

bool cpu_has_avx2_fma() { return false; }
void update_vector(int m, int cols, const float* L, int ld, const float* c, float* dest) {
  update_plain(m, cols, L, ld, c, dest);
}
void dots_vector(int m, int cols, const float* L, int ld, const float* v, float* s) {
  dots_plain(m, cols, L, ld, v, s);
}

#endif

}  // namespace

bool vector_kernels() {
  static const bool available = cpu_has_avx2_fma();
  return available;
}

void forward_panel_plain(int f, int w, const float* L, int ld, float* x1, float* y) {
  forward(f, w, L, ld, x1, y, update_plain);
}

void backward_panel_plain(int f, int u, const float* L, int ld, float* xu, const float* g) {
  backward(f, u, L, ld, xu, g, dots_plain);
}

void forward_panel(int f, int w, const float* L, int ld, float* x1, float* y) {
  if (vector_kernels()) return forward(f, w, L, ld, x1, y, update_vector);
  forward_panel_plain(f, w, L, ld, x1, y);
}

void backward_panel(int f, int u, const float* L, int ld, float* xu, const float* g) {
  if (vector_kernels()) return backward(f, u, L, ld, xu, g, dots_vector);
  backward_panel_plain(f, u, L, ld, xu, g);
}

}  // namespace dexcloth::cloth::kernels
