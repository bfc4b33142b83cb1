#pragma once
/// The BLAS and LAPACK routines the cloth calls (Debian's OpenBLAS: kernels dispatched at run
/// time for the CPU at hand, so the binary stays portable), Fortran calling convention: every
/// argument by pointer, column-major arrays, one trailing hidden length per character argument.
#include <cstddef>

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda,
             double* b, const int* ldb, int* info, std::size_t);
void dlauum_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb, std::size_t, std::size_t, std::size_t, std::size_t);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc,
            std::size_t, std::size_t);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy, std::size_t);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a,
            const int* lda, double* x, const int* incx, std::size_t, std::size_t, std::size_t);
void spotrf_(const char* uplo, const int* n, float* a, const int* lda, int* info, std::size_t);
void strsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const float* alpha, const float* a, const int* lda, float* b,
            const int* ldb, std::size_t, std::size_t, std::size_t, std::size_t);
void ssyrk_(const char* uplo, const char* trans, const int* n, const int* k, const float* alpha,
            const float* a, const int* lda, const float* beta, float* c, const int* ldc,
            std::size_t, std::size_t);
void openblas_set_num_threads(int threads);
}

namespace dexcloth::cloth::blas {

/// The kernels of a supernodal Cholesky in either precision (lower triangles, column-major):
/// A = L·Lᵀ in place; B ← B·L⁻ᵀ (B m×n); C ← C − A·Aᵀ (C n×n, A n×k).
inline void cholesky(int n, double* a, int lda, int* info) { dpotrf_("L", &n, a, &lda, info, 1); }
inline void cholesky(int n, float* a, int lda, int* info) { spotrf_("L", &n, a, &lda, info, 1); }
inline void solve_right_lower_transposed(int m, int n, const double* l, int ldl, double* b,
                                         int ldb) {
  const double one = 1.0;
  dtrsm_("R", "L", "T", "N", &m, &n, &one, l, &ldl, b, &ldb, 1, 1, 1, 1);
}
inline void solve_right_lower_transposed(int m, int n, const float* l, int ldl, float* b, int ldb) {
  const float one = 1.0F;
  strsm_("R", "L", "T", "N", &m, &n, &one, l, &ldl, b, &ldb, 1, 1, 1, 1);
}
inline void subtract_gram(int n, int k, const double* a, int lda, double* c, int ldc) {
  const double one = 1.0, minus_one = -1.0;
  dsyrk_("L", "N", &n, &k, &minus_one, a, &lda, &one, c, &ldc, 1, 1);
}
inline void subtract_gram(int n, int k, const float* a, int lda, float* c, int ldc) {
  const float one = 1.0F, minus_one = -1.0F;
  ssyrk_("L", "N", &n, &k, &minus_one, a, &lda, &one, c, &ldc, 1, 1);
}

}  // namespace dexcloth::cloth::blas
