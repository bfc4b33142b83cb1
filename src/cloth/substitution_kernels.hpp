#pragma once
/// The dense steps of a supernodal factor's substitutions in single precision: AVX2 and FMA
/// where the CPU has them (chosen at run time, so the binary stays portable), plain loops
/// elsewhere. Eigen's kernels, without `-march`, use SSE2 only and went through a general
/// matrix–vector call per front; most fronts are a few columns wide.
///
/// A front's panel L is f rows × w columns, column-major with leading dimension ld: its top w
/// rows L₁₁ (lower triangular, the diagonal nonzero), the f − w rows below them L₂₁. Every
/// result is the same for the same inputs on one machine; the two kernels differ by rounding.
namespace dexcloth::cloth::kernels {

/// x₁ ← L₁₁⁻¹·x₁ (w entries) and y ← L₂₁·x₁ (f − w entries, written, not read).
void forward_panel(int f, int w, const float* L, int ld, float* x1, float* y);

/// x_u ← L_uu⁻ᵀ·(x_u − L_ruᵀ·g): L_uu the panel's top u rows and first u columns (lower
/// triangular), L_ru the f − u rows below them, g (f − u entries) those rows' values.
void backward_panel(int f, int u, const float* L, int ld, float* xu, const float* g);

/// Whether forward_panel and backward_panel run the AVX2 kernels on this CPU.
bool vector_kernels();

/// The plain kernels (for tests; forward_panel and backward_panel take them without AVX2).
void forward_panel_plain(int f, int w, const float* L, int ld, float* x1, float* y);
void backward_panel_plain(int f, int u, const float* L, int ld, float* xu, const float* g);

}  // namespace dexcloth::cloth::kernels
