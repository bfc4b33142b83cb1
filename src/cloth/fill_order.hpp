#pragma once
/// Fill-reducing elimination orders of a symmetric pattern's graph, for the direct solver.
#include <vector>

namespace dexcloth::cloth {

/// Adjacency of an undirected graph in compressed form: the neighbours of node i are
/// neighbour[start[i] .. start[i+1]) (no self loops; each edge listed from both ends).
struct Graph {
  std::vector<int> start{0};
  std::vector<int> neighbour;

  int num_nodes() const { return static_cast<int>(start.size()) - 1; }
};

/// Floating-point operations of a Cholesky factorisation of `graph` eliminated in `order`
/// (order[k] is the node eliminated k-th), counting each node as a dense b×b block:
/// Σ_k (b·c_k)² for c_k the nodes in column k of L (diagonal included).
double cholesky_flops(const Graph& graph, const std::vector<int>& order, int block);

/// `order` rearranged in a postorder of its elimination tree: the same factor up to symmetric
/// permutation (the same fill and operations), with every subtree's columns contiguous and each
/// node right after its last child, so chains of columns with one structure become supernodes.
std::vector<int> postordered(const Graph& graph, const std::vector<int>& order);

/// The better of METIS's nested dissection and approximate minimum degree (fewer operations of
/// `block`×`block` blocks), postordered. Deterministic (METIS with its fixed default seed).
std::vector<int> fill_reducing_order(const Graph& graph, int block);

}  // namespace dexcloth::cloth
