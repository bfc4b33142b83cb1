#pragma once
/// Real roots of low-degree polynomials on an interval, robust to degenerate leading
/// coefficients: the coplanarity cubic of continuous collision detection.
#include <array>

namespace dexcloth::collision {

/// Real roots of c0 + c1·t + c2·t² written to `roots` in ascending order; returns how many
/// (0, 1 or 2). Numerically stable form; a zero c2 gives the linear root, an identically constant
/// polynomial gives none.
int quadratic_roots(double c0, double c1, double c2, std::array<double, 2>& roots);

/// Candidate contact times in [0,1] for p(t) = c[0] + c[1]·t + c[2]·t² + c[3]·t³, ascending:
/// [0,1] is split at the real roots of p′ (exact quadratic formula) into monotone pieces; each
/// piece whose end values bracket zero gets its root by safeguarded Newton–bisection to full
/// double precision; every split point where |p| ≤ `near_zero` (a tangential touch, a double
/// root) is a candidate too. Lower-degree and constant polynomials go through the same path.
/// Returns the number of candidates written to `out`: at most 7 (three pieces, each its start
/// and a root, and the end).
using CubicCandidates = std::array<double, 7>;
int cubic_candidates(const std::array<double, 4>& c, double near_zero, CubicCandidates& out);

}  // namespace dexcloth::collision
