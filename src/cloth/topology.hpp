#pragma once
/// Mesh connectivity derived from the faces: unique edges and bending hinges.
#include <array>
#include <vector>

#include "core/types.hpp"

namespace dexcloth::cloth {

/// An interior edge with its two wings, for dihedral bending (see bending.hpp).
struct Hinge {
  /// x0, x1: the shared edge in the order of the first face; x2: wing of (x0, x1, x2);
  /// x3: wing of (x1, x0, x3).
  std::array<int, 4> v{};
  double rest_angle{};         ///< rest dihedral angle θ̄ [rad]
  double weight{};             ///< |ē|² / (Ā1 + Ā2) from the rest shape [-]
  std::array<int, 2> faces{};  ///< the two faces: (x0, x1, x2) first, (x1, x0, x3) second
};

/// Edge-face incidences of `faces` (|F|×3) grouped by edge.
struct Topology {
  std::vector<std::array<int, 2>> edges;  ///< unique undirected edges (i < j), sorted
  /// Hinges of the edges shared by exactly two faces (rest_angle and weight left 0). Edges of
  /// one face (boundary) or of more than two faces (non-manifold) get no hinge.
  std::vector<Hinge> hinges;
};

/// Edges and hinges of a triangle mesh with vertex indices in `faces` (|F|×3).
Topology build_topology(const Triangles& faces);

}  // namespace dexcloth::cloth
