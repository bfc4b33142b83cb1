#pragma once
/// Per-vertex Coulomb friction as a nonlinear complementarity problem (paper §4.2, DESIGN.md
/// "Friction"). A cloth vertex of mass m touches M surfaces; contact i has normal n_i, normal
/// force magnitude fN_i, coefficient μ_i and relative velocity v_ri (vertex minus surface, at the
/// candidate velocity v̄). Unknown tangential forces fT_i satisfy, with w_i = P_i(v_ri + h Σ fT_j/m)
/// the next relative tangential velocity:
///   ‖fT_i‖ ≤ μ_i fN_i,   (μ_i fN_i − ‖fT_i‖)·‖w_i‖ = 0,   fT_i = −μ_i fN_i ŵ_i when w_i ≠ 0.
/// The solution is the unique minimiser of the convex ½(m/h)‖Δv‖² + Σ μ_i fN_i ‖P_i(v_ri + Δv)‖,
/// Δv = h Σ fT_j / m, which is how candidates are checked and how the general case is solved.
#include <array>
#include <span>

#include "core/types.hpp"

namespace dexcloth::coupling {

/// Most contacts one vertex can have (layers of cloth plus fingers).
inline constexpr int kMaxVertexContacts = 8;

/// One contact of a cloth vertex.
struct FrictionContact {
  Vec3 normal{Vec3::UnitZ()};            ///< unit contact normal (its sign does not matter)
  double normal_force{};                 ///< ‖fN‖ [N], ≥ 0
  double mu{};                           ///< Coulomb coefficient [-], ≥ 0
  Vec3 relative_velocity{Vec3::Zero()};  ///< vertex velocity minus surface velocity [m/s]
};

/// Which case of the enumeration produced the answer.
enum class FrictionCase {
  none,         ///< no friction capacity (all fN or μ zero): fT = 0
  static_at,    ///< the vertex sticks to contact `anchor` (and to contacts moving with it)
  all_dynamic,  ///< every contact slides
  general,      ///< non-parallel contact planes: 3-D candidates, else block Gauss–Seidel
};

struct FrictionResult {
  FrictionResult() { force.fill(Vec3::Zero()); }
  std::array<Vec3, kMaxVertexContacts> force;       ///< fT_i [N]
  std::array<bool, kMaxVertexContacts> sticking{};  ///< next relative tangential velocity zero
  Vec3 delta_v{Vec3::Zero()};                       ///< h Σ fT_j / m [m/s]: ṽ = v̄ + delta_v
  FrictionCase which{FrictionCase::none};
  int anchor{-1};      ///< contact the vertex sticks to (static_at)
  bool ok{true};       ///< every condition verified to tolerance
  double violation{};  ///< friction_violation relative to the problem's force scale
};

/// Normals closer than this (|n_i × n_0|) are parallel to rounding.
inline constexpr double kParallelSin = 1e-6;

/// Solves the friction NCP of one vertex. contacts.size() ≤ kMaxVertexContacts; mass > 0, h > 0.
/// Contacts whose planes are parallel (sandwich or same side, |n_i × n_0| ≤ max(coplanar_sin,
/// kParallelSin)) share one plane, that of their sign-aligned mean normal, and are solved
/// exactly by case enumeration: "static at k" for each k, ordered by the paper's heuristic
/// μ‖fN‖ − m‖v_r‖/h, then "all dynamic" (Newton on the smooth convex function); each candidate is
/// checked against the cone and complementarity before it is taken. Other configurations try the
/// same candidates in 3-D ("static at k": Δv on the line that stops contact k, placed along n_k
/// by a 1-D minimisation; "all dynamic": Newton), after block Gauss–Seidel on the dual. When no
/// candidate passes the check, either way, the Gauss–Seidel answer is refined by accelerated
/// projected gradient on the dual and its Δv polished by the 3-D Newton; the better answer stays,
/// and `ok` says whether it passes.
FrictionResult solve_friction(std::span<const FrictionContact> contacts, double mass, double h,
                              double coplanar_sin = 0.0);

/// Largest violation of the friction conditions by `result` (0 for an exact solution), as a force
/// [N]: cone excess, complementarity (μ fN − ‖fT‖)·‖w‖·m/h, misalignment of a sliding force with
/// −ŵ, and the momentum balance ‖(m/h)Δv − Σ fT‖, in the planes solve_friction used with the
/// same `coplanar_sin`. For tests and for the `ok` flag.
double friction_violation(std::span<const FrictionContact> contacts, double mass, double h,
                          const FrictionResult& result, double coplanar_sin = 0.0);

}  // namespace dexcloth::coupling
