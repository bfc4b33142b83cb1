#pragma once
/// Fixed sparsity of the 3|V|×3|V| implicit-Euler system, one 3×3 block per coupled vertex
/// pair, with the element-to-block maps used by assembly and a fill-reducing vertex order.
#include <array>
#include <vector>

#include "cloth/topology.hpp"
#include "core/types.hpp"

namespace dexcloth::cloth {

/// Block pattern compressed by block column; both triangles are stored (the matrix is
/// symmetric). Block b covers rows 3·row[b] .. 3·row[b]+2 of columns 3j .. 3j+2 of its column j.
struct SystemPattern {
  int num_vertices{};          ///< |V|
  std::vector<int> col_start;  ///< |V|+1 offsets into `row`
  std::vector<int> row;        ///< block row (vertex) of each block, sorted per column
  std::vector<int> transpose;  ///< per block (i, j): index of block (j, i)
  std::vector<int> diagonal;   ///< per vertex i: index of block (i, i)
  std::vector<std::array<int, 9>>
      face_blocks;  ///< per face: block (corner a, corner b) at [3a + b]
  std::vector<std::array<int, 16>> hinge_blocks;  ///< per hinge: block (a, b) at [4a + b]
  /// Fill-reducing elimination order of the vertices (fill_reducing_order): fill_order[k] is
  /// the vertex eliminated k-th (used by the direct solver).
  std::vector<int> fill_order;

  /// Number of 3×3 blocks.
  int num_blocks() const { return static_cast<int>(row.size()); }
};

/// The pattern coupling the vertices of each face (|F|×3) and of each hinge, for |V| =
/// `num_vertices` (every vertex gets a diagonal block).
SystemPattern build_system_pattern(int num_vertices, const Triangles& faces,
                                   const std::vector<Hinge>& hinges);

}  // namespace dexcloth::cloth
