#include "cloth/system_pattern.hpp"

#include <algorithm>
#include <utility>

#include "cloth/fill_order.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

/// Index of block (r, c) in `p`; the block must exist.
int find_block(const SystemPattern& p, int r, int c) {
  const auto first = p.row.begin() + p.col_start[static_cast<std::size_t>(c)];
  const auto last = p.row.begin() + p.col_start[static_cast<std::size_t>(c) + 1];
  const auto it = std::lower_bound(first, last, r);
  DEXCLOTH_DEMAND(it != last && *it == r);
  return static_cast<int>(it - p.row.begin());
}

}  // namespace

SystemPattern build_system_pattern(int num_vertices, const Triangles& faces,
                                   const std::vector<Hinge>& hinges) {
  SystemPattern p;
  p.num_vertices = num_vertices;
  const auto nv = static_cast<std::size_t>(num_vertices);

  // Coupled (column, row) vertex pairs: diagonal, faces, hinges; sorted and unique.
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(nv + 9 * static_cast<std::size_t>(faces.rows()) + 16 * hinges.size());
  for (int i = 0; i < num_vertices; ++i) pairs.emplace_back(i, i);
  for (int f = 0; f < faces.rows(); ++f) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) pairs.emplace_back(faces(f, b), faces(f, a));
    }
  }
  for (const Hinge& h : hinges) {
    for (int a : h.v) {
      for (int b : h.v) pairs.emplace_back(b, a);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  // Compress by column.
  p.col_start.assign(nv + 1, 0);
  p.row.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ++p.col_start[static_cast<std::size_t>(pairs[k].first) + 1];
    p.row[k] = pairs[k].second;
  }
  for (std::size_t i = 0; i < nv; ++i) p.col_start[i + 1] += p.col_start[i];

  // Transposes and diagonals.
  p.transpose.resize(pairs.size());
  p.diagonal.resize(nv);
  for (int c = 0; c < num_vertices; ++c) {
    for (int b = p.col_start[static_cast<std::size_t>(c)];
         b < p.col_start[static_cast<std::size_t>(c) + 1]; ++b) {
      p.transpose[static_cast<std::size_t>(b)] =
          find_block(p, c, p.row[static_cast<std::size_t>(b)]);
    }
    p.diagonal[static_cast<std::size_t>(c)] = find_block(p, c, c);
  }

  // Element-to-block maps.
  p.face_blocks.resize(static_cast<std::size_t>(faces.rows()));
  for (int f = 0; f < faces.rows(); ++f) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        p.face_blocks[static_cast<std::size_t>(f)][static_cast<std::size_t>(3 * a + b)] =
            find_block(p, faces(f, a), faces(f, b));
      }
    }
  }
  p.hinge_blocks.resize(hinges.size());
  for (std::size_t h = 0; h < hinges.size(); ++h) {
    for (std::size_t a = 0; a < 4; ++a) {
      for (std::size_t b = 0; b < 4; ++b) {
        p.hinge_blocks[h][4 * a + b] = find_block(p, hinges[h].v[a], hinges[h].v[b]);
      }
    }
  }

  // Fill-reducing order of the vertex graph (3×3 blocks).
  Graph graph;
  graph.start = p.col_start;
  for (int c = 0; c < num_vertices; ++c) {
    graph.start[static_cast<std::size_t>(c) + 1] = graph.start[static_cast<std::size_t>(c)];
    for (int b = p.col_start[static_cast<std::size_t>(c)];
         b < p.col_start[static_cast<std::size_t>(c) + 1]; ++b)
      if (p.row[static_cast<std::size_t>(b)] != c) {
        graph.neighbour.push_back(p.row[static_cast<std::size_t>(b)]);
        ++graph.start[static_cast<std::size_t>(c) + 1];
      }
  }
  p.fill_order = fill_reducing_order(graph, 3);
  return p;
}

}  // namespace dexcloth::cloth
