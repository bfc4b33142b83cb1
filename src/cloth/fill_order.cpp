#include "cloth/fill_order.hpp"

#include <metis.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>

#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Elimination tree and the column counts of L (diagonal excluded) of `graph` in `order`:
/// row k of L is the set of columns reached in the tree from A(i, k), i < k (new numbering).
void etree_and_counts(const Graph& graph, const std::vector<int>& order, std::vector<int>& parent,
                      std::vector<int>& count) {
  const int n = graph.num_nodes();
  std::vector<int> position(at(n)), ancestor(at(n), -1), flag(at(n), -1);
  for (int k = 0; k < n; ++k) position[at(order[at(k)])] = k;
  parent.assign(at(n), -1);
  count.assign(at(n), 0);
  for (int k = 0; k < n; ++k) {
    const int node = order[at(k)];
    const auto neighbours = [&](auto&& visit) {
      for (int p = graph.start[at(node)]; p < graph.start[at(node) + 1]; ++p) {
        const int i = position[at(graph.neighbour[at(p)])];
        if (i < k) visit(i);
      }
    };
    neighbours([&](int i) {
      while (i != -1 && i < k) {
        const int next = ancestor[at(i)];
        ancestor[at(i)] = k;
        if (next == -1) parent[at(i)] = k;
        i = next;
      }
    });
    flag[at(k)] = k;
    neighbours([&](int i) {
      for (; flag[at(i)] != k; i = parent[at(i)]) {
        ++count[at(i)];
        flag[at(i)] = k;
      }
    });
  }
}

std::vector<int> amd_order(const Graph& graph) {
  const int n = graph.num_nodes();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(graph.neighbour.size() + at(n));
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 1.0);
    for (int p = graph.start[at(i)]; p < graph.start[at(i) + 1]; ++p)
      entries.emplace_back(graph.neighbour[at(p)], i, 1.0);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  Eigen::AMDOrdering<int>()(A, perm);  // new-to-old
  return {perm.indices().data(), perm.indices().data() + perm.size()};
}

std::vector<int> nested_dissection_order(const Graph& graph) {
  idx_t n = graph.num_nodes();
  std::vector<idx_t> xadj(graph.start.begin(), graph.start.end());
  std::vector<idx_t> adjncy(graph.neighbour.begin(), graph.neighbour.end());
  std::vector<idx_t> perm(at(n)), iperm(at(n));
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  const int status =
      METIS_NodeND(&n, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  DEXCLOTH_DEMAND(status == METIS_OK);
  return {perm.begin(), perm.end()};  // perm[k]: the node eliminated k-th
}

}  // namespace

double cholesky_flops(const Graph& graph, const std::vector<int>& order, int block) {
  std::vector<int> parent, count;
  etree_and_counts(graph, order, parent, count);
  double flops = 0.0;
  for (int c : count) flops += static_cast<double>(block) * block * (c + 1.0) * (c + 1.0);
  return flops;
}

std::vector<int> postordered(const Graph& graph, const std::vector<int>& order) {
  const int n = graph.num_nodes();
  std::vector<int> parent, count;
  etree_and_counts(graph, order, parent, count);
  // Children lists (increasing), then a depth-first walk from each root in order.
  std::vector<int> child_start(at(n) + 1, 0), children(at(n));
  for (int k = 0; k < n; ++k)
    if (parent[at(k)] >= 0) ++child_start[at(parent[at(k)]) + 1];
  for (int k = 0; k < n; ++k) child_start[at(k) + 1] += child_start[at(k)];
  std::vector<int> next(child_start.begin(), child_start.end() - 1);
  for (int k = 0; k < n; ++k)
    if (parent[at(k)] >= 0) children[at(next[at(parent[at(k)])]++)] = k;
  std::vector<int> out;
  out.reserve(at(n));
  std::vector<std::pair<int, int>> path;  // (column, next child)
  for (int root = 0; root < n; ++root) {
    if (parent[at(root)] >= 0) continue;
    path.emplace_back(root, child_start[at(root)]);
    while (!path.empty()) {
      auto& [k, c] = path.back();
      if (c < child_start[at(k) + 1]) {
        const int child = children[at(c++)];
        path.emplace_back(child, child_start[at(child)]);
      } else {
        out.push_back(order[at(k)]);
        path.pop_back();
      }
    }
  }
  DEXCLOTH_DEMAND(static_cast<int>(out.size()) == n);
  return out;
}

std::vector<int> fill_reducing_order(const Graph& graph, int block) {
  if (graph.num_nodes() == 0) return {};
  std::vector<int> amd = amd_order(graph), nd = nested_dissection_order(graph);
  const bool nd_better = cholesky_flops(graph, nd, block) < cholesky_flops(graph, amd, block);
  return postordered(graph, nd_better ? nd : amd);
}

}  // namespace dexcloth::cloth
