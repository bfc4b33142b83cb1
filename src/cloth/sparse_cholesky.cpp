#include "cloth/sparse_cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "cloth/blas.hpp"
#include "cloth/substitution_kernels.hpp"
#include "core/assert.hpp"

namespace dexcloth::cloth {
namespace {

using Index = std::size_t;

Index at(int i) { return static_cast<Index>(i); }

/// Factors with fewer entries are solved on one thread: waking the workers costs more (a 33×33
/// sheet's 282k entries: 0.16 ms on one thread, 0.18–0.21 ms on two).
constexpr std::size_t kParallelSolveEntries = 400'000;

/// A supernode's panel of L (front rows × columns, column-major).
template <class T>
using Panel =
    Eigen::Map<const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>, 0, Eigen::OuterStride<>>;
template <class T>
using VectorMap = Eigen::Map<Eigen::Matrix<T, Eigen::Dynamic, 1>>;

/// Elimination tree (Liu's algorithm, path compression through `ancestor`) of the upper
/// pattern (column k: rows i ≤ k).
void elimination_tree(int n, std::span<const int> col_start, std::span<const int> row,
                      std::vector<int>& parent, std::vector<int>& ancestor) {
  ancestor.assign(at(n), -1);
  parent.assign(at(n), -1);
  for (int k = 0; k < n; ++k) {
    for (int p = col_start[at(k)]; p < col_start[at(k) + 1]; ++p) {
      for (int i = row[at(p)]; i != -1 && i < k;) {
        const int next = ancestor[at(i)];
        ancestor[at(i)] = k;
        if (next == -1) parent[at(i)] = k;
        i = next;
      }
    }
  }
}

/// The weighted count of every column of L, diagonal included: Σ weight[i] over the rows i of
/// column j. In time close to A's size (Gilbert, Ng & Peyton 1994, as in Davis's CSparse): row
/// i of L is the row subtree of the etree spanned by the columns j < i with A(i, j) ≠ 0, and
/// summing, up the tree, +weight[i] at each leaf of a row subtree and −weight[i] where two of
/// its leaves' paths meet (their least common ancestor, by path-compressed union–find over a
/// postorder) and above i counts every row subtree that holds a column.
/// `lower_start`/`lower_row`: A's lower pattern by column (rows i ≥ j of column j).
void column_counts(int n, const std::vector<int>& parent, const std::vector<int>& lower_start,
                   const std::vector<int>& lower_row, const std::vector<int>& weight,
                   std::vector<int>& count) {
  // A postorder of the etree: children lists, then a depth-first walk from each root.
  std::vector<int> head(at(n), -1), next(at(n), -1), post;
  post.reserve(at(n));
  for (int j = n - 1; j >= 0; --j)
    if (parent[at(j)] >= 0) {
      next[at(j)] = head[at(parent[at(j)])];
      head[at(parent[at(j)])] = j;
    }
  std::vector<int> stack;
  for (int root = 0; root < n; ++root) {
    if (parent[at(root)] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int j = stack.back();
      const int child = head[at(j)];
      if (child == -1) {
        stack.pop_back();
        post.push_back(j);
      } else {
        head[at(j)] = next[at(child)];
        stack.push_back(child);
      }
    }
  }
  // first[j]: the postorder index of j's first descendant; a leaf is its own.
  std::vector<int> first(at(n), -1), max_first(at(n), -1), prev_leaf(at(n), -1), ancestor(at(n));
  std::vector<int>& delta = count;
  delta.assign(at(n), 0);
  for (int k = 0; k < n; ++k) {
    int j = post[at(k)];
    delta[at(j)] = first[at(j)] == -1 ? weight[at(j)] : 0;
    for (; j != -1 && first[at(j)] == -1; j = parent[at(j)]) first[at(j)] = k;
  }
  for (int i = 0; i < n; ++i) ancestor[at(i)] = i;
  for (int k = 0; k < n; ++k) {
    const int j = post[at(k)];
    if (parent[at(j)] != -1) delta[at(parent[at(j)])] -= weight[at(j)];
    for (int p = lower_start[at(j)]; p < lower_start[at(j) + 1]; ++p) {
      const int i = lower_row[at(p)];
      // Is j a leaf of row i's subtree (no earlier column of it below j)?
      if (i <= j || first[at(j)] <= max_first[at(i)]) continue;
      max_first[at(i)] = first[at(j)];
      const int previous = prev_leaf[at(i)];
      prev_leaf[at(i)] = j;
      delta[at(j)] += weight[at(i)];
      if (previous == -1) continue;
      // Not the first leaf: the paths of this leaf and the previous one meet at q.
      int q = previous;
      while (q != ancestor[at(q)]) q = ancestor[at(q)];
      for (int s = previous; s != q;) {
        const int up = ancestor[at(s)];
        ancestor[at(s)] = q;
        s = up;
      }
      delta[at(q)] -= weight[at(i)];
    }
    if (parent[at(j)] != -1) ancestor[at(j)] = parent[at(j)];
  }
  for (int j = 0; j < n; ++j)
    if (parent[at(j)] != -1) count[at(parent[at(j)])] += count[at(j)];
}

/// The transpose of a pattern by column (`start`, n + 1, and `index`): `out_start` and
/// `out_index` by row, each entry's position in `index` in `out_entry`; entries in the order of
/// their columns.
void transpose(int n, std::span<const int> start, std::span<const int> index,
               std::vector<int>& out_start, std::vector<int>& out_index,
               std::vector<int>& out_entry) {
  out_start.assign(at(n) + 1, 0);
  out_index.resize(index.size());
  out_entry.resize(index.size());
  for (const int i : index) ++out_start[at(i) + 1];
  for (int j = 0; j < n; ++j) out_start[at(j) + 1] += out_start[at(j)];
  std::vector<int> next(out_start.begin(), out_start.end() - 1);
  for (int j = 0; j < n; ++j)
    for (int p = start[at(j)]; p < start[at(j) + 1]; ++p) {
      const int q = next[at(index[at(p)])]++;
      out_index[at(q)] = j;
      out_entry[at(q)] = p;
    }
}

/// Whether merging supernodes of `columns` columns into one adds few enough explicit zeros:
/// CHOLMOD's default relaxation (any up to 4 columns; up to 16 with < 80 % zeros, up to 48 with
/// < 10 %, any with < 5 %).
bool relaxed_merge_pays(int columns, double zero_share) {
  return columns <= 4 || (columns <= 16 && zero_share < 0.8) ||
         (columns <= 48 && zero_share < 0.1) || zero_share < 0.05;
}

}  // namespace

void SparseCholesky::begin_analysis(int threads, Precision precision) {
  DEXCLOTH_DEMAND(threads >= 1);
  m_precision = precision;
  m_threads = threads;
  // One BLAS thread: OpenBLAS's threaded kernels allocate on every call, and on fronts of this
  // size (a few hundred rows) two threads were slower than one (a 65×65 sheet: 62 vs 44 ms).
  openblas_set_num_threads(1);
}

void SparseCholesky::analyze(int n, std::span<const int> col_start, std::span<const int> row,
                             int threads, Precision precision) {
  begin_analysis(threads, precision);
  DEXCLOTH_DEMAND(n >= 0 && col_start.size() == at(n) + 1 && col_start[0] == 0);
  DEXCLOTH_DEMAND(row.size() == at(col_start[at(n)]));
  // Every unknown a group of its own; the groups' pattern is A's above the diagonal.
  std::vector<int> groups(at(n) + 1), group_start(1, 0), group_row;
  group_row.reserve(row.size());
  for (int j = 0; j <= n; ++j) groups[at(j)] = j;
  for (int j = 0; j < n; ++j) {
    for (int p = col_start[at(j)]; p < col_start[at(j) + 1]; ++p) {
      DEXCLOTH_DEMAND(row[at(p)] >= 0 && row[at(p)] <= j);
      if (row[at(p)] < j) group_row.push_back(row[at(p)]);
    }
    group_start.push_back(static_cast<int>(group_row.size()));
  }
  std::vector<int> group_of;
  analyze_groups(groups, group_start, group_row, group_of);

  // Where each value of A lands (grouped by supernode, in A's order within one): from A's lower
  // pattern by column (with each entry's index in `row`).
  std::vector<int> lower_start, lower_row, lower_entry, position(at(n), -1);
  transpose(n, col_start, row, lower_start, lower_row, lower_entry);
  m_column_stride = 0;
  m_blocks.clear();
  m_entry_start.assign(1, 0);
  m_entries.clear();
  for (int s = 0; s < supernodes(); ++s) {
    const int k1 = m_first[at(s)], k2 = m_first[at(s) + 1];
    const int f = m_row_start[at(s) + 1] - m_row_start[at(s)];
    for (int r = 0; r < f; ++r) position[at(m_rows[at(m_row_start[at(s)] + r)])] = r;
    for (int j = k1; j < k2; ++j)
      for (int q = lower_start[at(j)]; q < lower_start[at(j) + 1]; ++q)
        m_entries.push_back(
            {lower_entry[at(q)], at(j - k1) * at(f) + at(position[at(lower_row[at(q)])])});
    m_entry_start.push_back(m_entries.size());
  }
  m_values = row.size();
}

void SparseCholesky::analyze_blocks(std::span<const int> groups, std::span<const int> block_start,
                                    std::span<const int> block_row,
                                    std::span<const int> block_source, int column_stride,
                                    int threads, Precision precision) {
  begin_analysis(threads, precision);
  const int ng = static_cast<int>(groups.size()) - 1;
  DEXCLOTH_DEMAND(ng >= 0 && groups[0] == 0 && block_start.size() == groups.size() &&
                  block_start[0] == 0 && block_row.size() == at(block_start[at(ng)]) &&
                  block_source.size() == block_row.size() && column_stride > 0);
  // The groups' pattern: the blocks above the diagonal. Each column has its diagonal block and
  // no block twice.
  std::vector<int> group_start(1, 0), group_row, mark(at(ng), -1);
  group_row.reserve(block_row.size());
  for (int g = 0; g < ng; ++g) {
    DEXCLOTH_DEMAND(groups[at(g)] < groups[at(g) + 1]);
    bool diagonal = false;
    for (int q = block_start[at(g)]; q < block_start[at(g) + 1]; ++q) {
      const int h = block_row[at(q)];
      DEXCLOTH_DEMAND(h >= 0 && h <= g && mark[at(h)] != g && block_source[at(q)] >= 0);
      mark[at(h)] = g;
      if (h < g) {
        group_row.push_back(h);
      } else {
        diagonal = true;
      }
    }
    DEXCLOTH_DEMAND(diagonal);
    group_start.push_back(static_cast<int>(group_row.size()));
  }
  std::vector<int> group_of;
  analyze_groups(groups, group_start, group_row, group_of);

  // Where each block lands: block (h, g) of A, h ≤ g, is the rows of g's unknowns in the
  // columns of h's, a dense piece of the panel of h's supernode, its rows consecutive there.
  std::vector<int> lower_start, lower_row, lower_entry, position(at(m_n), -1);
  transpose(ng, block_start, block_row, lower_start, lower_row, lower_entry);
  m_column_stride = column_stride;
  m_entries.clear();
  m_entry_start.assign(1, 0);
  m_blocks.clear();
  int most = 0;  // the largest value offset read
  for (int s = 0; s < supernodes(); ++s) {
    const int k1 = m_first[at(s)], k2 = m_first[at(s) + 1];
    const int f = m_row_start[at(s) + 1] - m_row_start[at(s)];
    for (int r = 0; r < f; ++r) position[at(m_rows[at(m_row_start[at(s)] + r)])] = r;
    for (int h = group_of[at(k1)]; h < ng && groups[at(h)] < k2; ++h)
      for (int q = lower_start[at(h)]; q < lower_start[at(h) + 1]; ++q) {
        const int g = lower_row[at(q)], source = block_source[at(lower_entry[at(q)])];
        const int columns = groups[at(h) + 1] - groups[at(h)];
        const int rows = groups[at(g) + 1] - groups[at(g)];
        m_blocks.push_back({at(groups[at(h)] - k1) * at(f) + at(position[at(groups[at(g)])]),
                            source, columns, rows, g == h});
        most = std::max(most, source + (rows - 1) * column_stride + columns - 1);
      }
    m_entry_start.push_back(m_blocks.size());
  }
  m_values = at(most) + 1;
}

void SparseCholesky::analyze_groups(std::span<const int> groups,
                                    const std::vector<int>& group_start,
                                    const std::vector<int>& group_row, std::vector<int>& group_of) {
  const int ng = static_cast<int>(groups.size()) - 1;
  const int n = groups[at(ng)];
  m_n = n;
  std::vector<int> width(at(ng));
  group_of.resize(at(n));
  for (int g = 0; g < ng; ++g) {
    width[at(g)] = groups[at(g) + 1] - groups[at(g)];
    for (int j = groups[at(g)]; j < groups[at(g) + 1]; ++j) group_of[at(j)] = g;
  }
  // Transposed (the groups after each one with entries in its rows), for the column counts
  // and the fronts' rows.
  std::vector<int> group_lower_start, group_lower_row, group_entry, mark;
  transpose(ng, group_start, group_row, group_lower_start, group_lower_row, group_entry);

  // The elimination tree and L's column counts of the groups, spread over their unknowns: each
  // group a chain whose last unknown's parent is the parent group's first; the columns of a
  // group of w unknowns, the last group count less 1, …, w.
  std::vector<int> group_parent, group_count;
  elimination_tree(ng, group_start, group_row, group_parent, mark);
  column_counts(ng, group_parent, group_lower_start, group_lower_row, width, group_count);
  std::vector<int> parent(at(n)), count(at(n));
  for (int g = 0; g < ng; ++g)
    for (int j = groups[at(g)]; j < groups[at(g) + 1]; ++j) {
      parent[at(j)] = j + 1 < groups[at(g) + 1] ? j + 1
                      : group_parent[at(g)] < 0 ? -1
                                                : groups[at(group_parent[at(g)])];
      count[at(j)] = group_count[at(g)] - 1 - (j - groups[at(g)]);
    }

  // Fundamental supernodes: j joins j − 1 when it is j − 1's parent, its only child, and L's
  // column j is column j − 1 without its diagonal.
  std::vector<int> children(at(n), 0);
  for (int j = 0; j < n; ++j)
    if (parent[at(j)] >= 0) ++children[at(parent[at(j)])];
  std::vector<int> first;
  for (int j = 0; j < n; ++j)
    if (j == 0 || parent[at(j - 1)] != j || children[at(j)] != 1 ||
        count[at(j - 1)] != count[at(j)] + 1)
      first.push_back(j);
  first.push_back(n);

  // Relaxed amalgamation: a supernode whose parent is the next one merges into it while the
  // explicit zeros stay few (bigger fronts make the dense kernels efficient).
  m_first.assign(1, 0);
  double nonzero = 0.0;  // entries of L in the group being built
  for (std::size_t s = 0; s + 1 < first.size(); ++s) {
    const int k1 = first[s], k2 = first[s + 1];
    const int b = count[at(k2 - 1)];
    double s_nonzero = 0.0;
    for (int j = k1; j < k2; ++j) s_nonzero += count[at(j)] + 1;
    const int group_first = m_first.back();
    const bool joins = k1 > group_first && parent[at(k1 - 1)] >= k1 && parent[at(k1 - 1)] < k2;
    if (joins) {
      // The group's columns take this supernode's rows: its own w + b, and their own columns.
      const int merged_w = k2 - group_first;
      const double merged_stored =
          static_cast<double>(merged_w) * (merged_w + 1) / 2.0 + static_cast<double>(merged_w) * b;
      const double merged_nonzero = nonzero + s_nonzero;
      if (relaxed_merge_pays(merged_w, 1.0 - merged_nonzero / merged_stored)) {
        nonzero = merged_nonzero;
        continue;
      }
    }
    if (k1 > 0) m_first.push_back(k1);
    nonzero = s_nonzero;
  }
  if (n > 0) m_first.push_back(n);
  const int ns = static_cast<int>(m_first.size()) - 1;
  m_super_of.resize(at(n));
  for (int s = 0; s < ns; ++s)
    for (int j = m_first[at(s)]; j < m_first[at(s) + 1]; ++j) m_super_of[at(j)] = s;
  std::vector<int> sparent(at(ns), -1);
  for (int s = 0; s < ns; ++s) {
    const int p = parent[at(m_first[at(s) + 1] - 1)];
    sparent[at(s)] = p < 0 ? -1 : m_super_of[at(p)];
  }

  // Children lists of the supernodal tree.
  m_child_start.assign(at(ns) + 1, 0);
  for (int s = 0; s < ns; ++s)
    if (sparent[at(s)] >= 0) ++m_child_start[at(sparent[at(s)]) + 1];
  for (int s = 0; s < ns; ++s) m_child_start[at(s) + 1] += m_child_start[at(s)];
  m_children.resize(at(m_child_start[at(ns)]));
  {
    std::vector<int> next(m_child_start.begin(), m_child_start.end() - 1);
    for (int s = 0; s < ns; ++s)
      if (sparent[at(s)] >= 0) m_children[at(next[at(sparent[at(s)])]++)] = s;
  }

  // Front rows: a supernode's columns, then (increasing) the rows below them of its columns of
  // A and of its children's fronts; found by groups (a supernode's columns are whole groups,
  // the rows below them too), then spread over the groups' unknowns.
  std::vector<int> front_start(1, 0), front_group;  // each front's groups below its columns
  m_row_start.assign(1, 0);
  m_rows.clear();
  mark.assign(at(ng), -1);
  for (int s = 0; s < ns; ++s) {
    const int k1 = m_first[at(s)], k2 = m_first[at(s) + 1];
    const int g1 = group_of[at(k1)], g2 = k2 < n ? group_of[at(k2)] : ng;
    DEXCLOTH_DEMAND(groups[at(g1)] == k1 && groups[at(g2)] == k2);
    const std::size_t below = front_group.size();
    const auto add = [&](int h) {
      if (h >= g2 && mark[at(h)] != s) {
        mark[at(h)] = s;
        front_group.push_back(h);
      }
    };
    for (int g = g1; g < g2; ++g)
      for (int q = group_lower_start[at(g)]; q < group_lower_start[at(g) + 1]; ++q)
        add(group_lower_row[at(q)]);
    for (int c = m_child_start[at(s)]; c < m_child_start[at(s) + 1]; ++c) {
      const int child = m_children[at(c)];
      for (int r = front_start[at(child)]; r < front_start[at(child) + 1]; ++r)
        add(front_group[at(r)]);
    }
    std::sort(front_group.begin() + static_cast<std::ptrdiff_t>(below), front_group.end());
    front_start.push_back(static_cast<int>(front_group.size()));
    for (int j = k1; j < k2; ++j) m_rows.push_back(j);
    for (std::size_t r = below; r < front_group.size(); ++r)
      for (int j = groups[at(front_group[r])]; j < groups[at(front_group[r]) + 1]; ++j)
        m_rows.push_back(j);
    m_row_start.push_back(static_cast<int>(m_rows.size()));
  }

  // Panels, and the positions of each child's rows below its columns in its parent's front.
  m_panel_start.assign(1, 0);
  m_unused_upper = 0;
  m_flops = 0.0;
  std::vector<int> position(at(n), -1);
  m_relmap.assign(m_rows.size(), -1);
  std::vector<double> work(at(ns), 0.0);  // flops of each front
  for (int s = 0; s < ns; ++s) {
    const int w = m_first[at(s) + 1] - m_first[at(s)];
    const int f = m_row_start[at(s) + 1] - m_row_start[at(s)], b = f - w;
    m_panel_start.push_back(m_panel_start.back() + at(f) * at(w));
    m_unused_upper += at(w) * at(w - 1) / 2;
    work[at(s)] = w * (w + 1.0) * (2.0 * w + 1.0) / 6.0 + static_cast<double>(b) * w * (w + 1.0) +
                  static_cast<double>(b) * (b + 1.0) * w;
    m_flops += work[at(s)];
    for (int r = 0; r < f; ++r) position[at(m_rows[at(m_row_start[at(s)] + r)])] = r;
    for (int c = m_child_start[at(s)]; c < m_child_start[at(s) + 1]; ++c) {
      const int child = m_children[at(c)];
      const int cw = m_first[at(child) + 1] - m_first[at(child)];
      for (int r = m_row_start[at(child)] + cw; r < m_row_start[at(child) + 1]; ++r)
        m_relmap[at(r)] = position[at(m_rows[at(r)])];
    }
  }
  schedule(sparent, work);
}

void SparseCholesky::schedule(const std::vector<int>& sparent, const std::vector<double>& work) {
  const int ns = static_cast<int>(sparent.size());
  // A postorder of the supernodal tree (children before parents, each subtree contiguous), so
  // that the update matrices waiting for their parents form a stack.
  m_postorder.clear();
  std::vector<int> post_index(at(ns)), subtree_size(at(ns), 1);
  std::vector<double> subtree_work(work);
  std::vector<std::pair<int, int>> path;  // (supernode, next child to visit)
  std::vector<int> roots;
  for (int root = 0; root < ns; ++root) {
    if (sparent[at(root)] >= 0) continue;
    roots.push_back(root);
    path.emplace_back(root, m_child_start[at(root)]);
    while (!path.empty()) {
      auto& [s, next] = path.back();
      if (next < m_child_start[at(s) + 1]) {
        const int child = m_children[at(next++)];
        path.emplace_back(child, m_child_start[at(child)]);
      } else {
        const int done = s;
        post_index[at(done)] = static_cast<int>(m_postorder.size());
        m_postorder.push_back(done);
        path.pop_back();
        if (!path.empty()) {
          subtree_size[at(path.back().first)] += subtree_size[at(done)];
          subtree_work[at(path.back().first)] += subtree_work[at(done)];
        }
      }
    }
  }
  DEXCLOTH_DEMAND(static_cast<int>(m_postorder.size()) == ns);

  // Subtrees for the threads: starting from the roots, the heaviest subtree is split (its root
  // goes to the serial top, its children to the threads) until the subtrees share out within
  // 10 % (largest first onto the least loaded thread).
  const int threads = m_threads;
  std::vector<int> frontier = roots;
  std::vector<char> in_top(at(ns), 0);
  m_tasks.assign(at(threads), {});
  for (int split = 0;; ++split) {
    std::sort(frontier.begin(), frontier.end(), [&](int a, int b) {
      return subtree_work[at(a)] != subtree_work[at(b)] ? subtree_work[at(a)] > subtree_work[at(b)]
                                                        : a < b;
    });
    std::vector<double> load(at(threads), 0.0);
    for (auto& task : m_tasks) task.clear();
    for (int r : frontier) {
      const auto t =
          at(static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin()));
      load[t] += subtree_work[at(r)];
      m_tasks[t].push_back(r);
    }
    double total = 0.0;
    for (double l : load) total += l;
    const double most = *std::max_element(load.begin(), load.end());
    m_parallel_share = subtree_work.empty() ? 1.0 : total / m_flops;
    if (threads == 1 || frontier.empty() || most <= 1.1 * total / threads || split >= 64) break;
    const int heaviest = frontier.front();
    if (m_child_start[at(heaviest)] == m_child_start[at(heaviest) + 1]) break;
    frontier.erase(frontier.begin());
    in_top[at(heaviest)] = 1;
    for (int c = m_child_start[at(heaviest)]; c < m_child_start[at(heaviest) + 1]; ++c)
      frontier.push_back(m_children[at(c)]);
  }
  // Each task's supernodes in postorder; the top after them, in postorder.
  m_task_order.assign(at(threads), {});
  for (int t = 0; t < threads; ++t) {
    std::sort(m_tasks[at(t)].begin(), m_tasks[at(t)].end(),
              [&](int a, int b) { return post_index[at(a)] < post_index[at(b)]; });
    for (int r : m_tasks[at(t)])
      for (int k = post_index[at(r)] - subtree_size[at(r)] + 1; k <= post_index[at(r)]; ++k)
        m_task_order[at(t)].push_back(m_postorder[at(k)]);
  }
  m_top_order.clear();
  for (int s : m_postorder)
    if (in_top[at(s)]) m_top_order.push_back(s);
  schedule_solves(in_top);

  // Stack offsets: each thread's region, then the top's, each holding two stacks, one for the
  // supernodes at even depths of the tree and one for those at odd depths, so that a supernode
  // builds its update matrix in place, on one stack, while its children's wait on the other
  // (one stack would put it over them). A supernode's children are the top of their stack when
  // its turn comes (the ones pushed after them have been consumed); they are popped as it is
  // pushed.
  std::vector<int> depth(at(ns), 0);
  for (int s = ns - 1; s >= 0; --s)
    if (sparent[at(s)] >= 0) depth[at(s)] = depth[at(sparent[at(s)])] + 1;
  m_stack_offset.assign(at(ns), 0);
  std::size_t base = 0;
  const auto place = [&](const std::vector<int>& order) {
    std::size_t top[2] = {0, 0}, peak[2] = {0, 0};
    for (int s : order) {
      const int parity = depth[at(s)] % 2;
      for (int c = m_child_start[at(s)]; c < m_child_start[at(s) + 1]; ++c) {
        const int child = m_children[at(c)];
        if (in_top[at(child)] == in_top[at(s)]) {
          top[1 - parity] = m_stack_offset[at(child)];
          break;
        }
      }
      const int w = m_first[at(s) + 1] - m_first[at(s)];
      const int b = m_row_start[at(s) + 1] - m_row_start[at(s)] - w;
      m_stack_offset[at(s)] = top[parity];
      top[parity] += at(b) * at(b);
      peak[parity] = std::max(peak[parity], top[parity]);
    }
    // From offsets within each stack to offsets in the buffer: the even stack, then the odd.
    for (int s : order) m_stack_offset[at(s)] += base + (depth[at(s)] % 2 == 1 ? peak[0] : 0);
    base += peak[0] + peak[1];
  };
  for (const std::vector<int>& order : m_task_order) place(order);
  place(m_top_order);
  m_stack_size = base;
  m_failure.assign(at(threads), -1);
  size_buffers();
}

WorkerPool* SparseCholesky::pool() const { return lent_or_own(m_lent_pool, m_own_pool, m_threads); }

template <class T>
SparseCholesky::Numeric<T>& SparseCholesky::numeric() {
  if constexpr (std::is_same_v<T, float>) {
    return m_single;
  } else {
    return m_double;
  }
}

template <class T>
const SparseCholesky::Numeric<T>& SparseCholesky::numeric() const {
  if constexpr (std::is_same_v<T, float>) {
    return m_single;
  } else {
    return m_double;
  }
}

void SparseCholesky::size_buffers() {
  const int threads = m_threads;
  // Only sized, the contents neither kept nor zeroed (every factorisation writes what it reads;
  // zeroing the last analysis's ~14 MB of panels took a third of pinch_move's re-analyses, and
  // a vector's copy and zero-fill on growing another third).
  const auto size = [&](auto& numeric) {
    numeric.panel.resize(m_panel_start.back());
    numeric.stack.resize(m_stack_size);
    numeric.deferred.resize(m_deferred_start.back());
    numeric.gather.resize(at(threads));
    numeric.product.resize(at(threads));
    for (auto& v : numeric.gather) v.resize(at(m_n));
    for (auto& v : numeric.product) v.resize(at(m_n));
  };
  const auto release = [](auto& numeric) { numeric = {}; };
  if (m_precision == Precision::single_precision) {
    size(m_single);
    m_single.x.resize(at(m_n));  // the solves' float copy of their double vector
    release(m_double);
  } else {
    size(m_double);
    release(m_single);
  }
}

void SparseCholesky::schedule_solves(const std::vector<char>& in_top) {
  const int ns = static_cast<int>(in_top.size());
  const int threads = m_threads;
  // Each task's supernodes in column order, and the rows below them that lie in the top: a
  // suffix of the sorted rows, the top being above every subtree (an ancestor's columns follow
  // its descendants').
  m_solve_order.assign(at(threads), {});
  for (int t = 0; t < threads; ++t) {
    m_solve_order[at(t)] = m_task_order[at(t)];
    std::sort(m_solve_order[at(t)].begin(), m_solve_order[at(t)].end());
  }
  m_threaded_solves = threads > 1 && factor_nonzeros() >= kParallelSolveEntries;
  m_in_top.assign(in_top.begin(), in_top.end());
  m_deferred_start.assign(at(ns) + 1, 0);
  for (int s = 0; s < ns; ++s) {
    const int w = m_first[at(s) + 1] - m_first[at(s)];
    int top_rows = 0;
    if (!in_top[at(s)]) {
      for (int r = m_row_start[at(s)] + w; r < m_row_start[at(s) + 1]; ++r) {
        const bool top = in_top[at(m_super_of[at(m_rows[at(r)])])] != 0;
        DEXCLOTH_DEMAND(top || top_rows == 0);  // the suffix
        top_rows += top ? 1 : 0;
      }
    }
    m_deferred_start[at(s) + 1] = m_deferred_start[at(s)] + at(top_rows);
  }
}

template <class T>
int SparseCholesky::factor_front(int s, std::span<const double> base, std::span<const int> source) {
  Numeric<T>& numeric = this->numeric<T>();
  const int k1 = m_first[at(s)], w = m_first[at(s) + 1] - k1;
  const int f = m_row_start[at(s) + 1] - m_row_start[at(s)], b = f - w;
  T* P = numeric.panel.data() + m_panel_start[at(s)];
  T* U = numeric.stack.data() + m_stack_offset[at(s)];  // built in place
  // The front: this supernode's columns of A, ...
  // (Of the update matrices only the lower triangles are written and read.)
  std::fill(P, P + at(f) * at(w), T{0});
  for (int q = 0; q < b; ++q) std::fill(U + at(q) * at(b) + at(q), U + at(q + 1) * at(b), T{0});
  if (m_column_stride > 0) {
    const std::size_t stride = at(m_column_stride);
    for (std::size_t k = m_entry_start[at(s)]; k < m_entry_start[at(s) + 1]; ++k) {
      const Block& block = m_blocks[k];
      const double* values = base.data() + block.source;
      T* dest = P + block.offset;
      if (block.columns == 3 && block.rows == 3 && !block.diagonal) {  // most blocks
        for (std::size_t a = 0; a < 3; ++a, dest += f, ++values) {
          dest[0] += static_cast<T>(values[0]);
          dest[1] += static_cast<T>(values[stride]);
          dest[2] += static_cast<T>(values[2 * stride]);
        }
        continue;
      }
      for (int a = 0; a < block.columns; ++a)
        for (int r = block.diagonal ? a : 0; r < block.rows; ++r)
          dest[at(a) * at(f) + at(r)] += static_cast<T>(values[at(a) + stride * at(r)]);
    }
  } else if (source.empty()) {
    for (std::size_t k = m_entry_start[at(s)]; k < m_entry_start[at(s) + 1]; ++k)
      P[m_entries[k].offset] += static_cast<T>(base[at(m_entries[k].entry)]);
  } else {
    for (std::size_t k = m_entry_start[at(s)]; k < m_entry_start[at(s) + 1]; ++k)
      P[m_entries[k].offset] += static_cast<T>(base[at(source[at(m_entries[k].entry)])]);
  }
  // ... and the extend-add of its children's update matrices (lower triangles).
  for (int c = m_child_start[at(s)]; c < m_child_start[at(s) + 1]; ++c) {
    const int child = m_children[at(c)];
    const int cw = m_first[at(child) + 1] - m_first[at(child)];
    const int cb = m_row_start[at(child) + 1] - m_row_start[at(child)] - cw;
    const int* map = m_relmap.data() + m_row_start[at(child)] + cw;
    const T* Uc = numeric.stack.data() + m_stack_offset[at(child)];
    for (int q = 0; q < cb; ++q) {
      const int pc = map[q];
      const T* column = Uc + at(q) * at(cb);
      T* dest = pc < w ? P + at(pc) * at(f) : U + at(pc - w) * at(b) - w;
      for (int r = q; r < cb; ++r) dest[map[r]] += column[r];
    }
  }
  // Dense partial factorisation: L₁₁ = chol(F₁₁), L₂₁ = F₂₁·L₁₁⁻ᵀ, U = F₂₂ − L₂₁·L₂₁ᵀ.
  int info = 0;
  blas::cholesky(w, P, f, &info);
  if (info != 0) return k1 + std::max(0, info - 1);
  for (int j = 0; j < w; ++j)
    if (!std::isfinite(P[at(j) * at(f) + at(j)])) return k1 + j;
  if (b > 0) {
    blas::solve_right_lower_transposed(b, w, P, f, P + w, f);
    blas::subtract_gram(b, w, P + w, f, U, b);
  }
  return -1;
}

int SparseCholesky::factorize(std::span<const double> values) { return factorize(values, {}); }

int SparseCholesky::factorize(std::span<const double> base, std::span<const int> source) {
  DEXCLOTH_DEMAND(source.empty()
                      ? (m_column_stride > 0 ? base.size() >= m_values : base.size() == m_values)
                      : m_column_stride == 0 && source.size() == m_values);
  return m_precision == Precision::single_precision ? factorize_in<float>(base, source)
                                                    : factorize_in<double>(base, source);
}

template <class T>
int SparseCholesky::factorize_in(std::span<const double> base, std::span<const int> source) {
  // The threads' subtrees (each stops at its first failed pivot), then the top.
  auto subtrees = [&](int t) {
    m_failure[at(t)] = -1;
    for (int s : m_task_order[at(t)])
      if ((m_failure[at(t)] = factor_front<T>(s, base, source)) >= 0) return;
  };
  if (WorkerPool* p = pool()) {
    p->run(subtrees);
  } else {
    subtrees(0);
  }
  int failed = -1;
  for (int f : m_failure)
    if (f >= 0 && (failed < 0 || f < failed)) failed = f;
  if (failed >= 0) return failed;
  for (int s : m_top_order)
    if (const int f = factor_front<T>(s, base, source); f >= 0) return f;
  return -1;
}

void SparseCholesky::solve_in_place(std::span<double> b) const {
  forward_in_place(b);
  backward_in_place(b, 0);
}

template <class T>
void SparseCholesky::forward_front(int s, T* x, T* product, T* deferred) const {
  const int k1 = m_first[at(s)], w = m_first[at(s) + 1] - k1;
  const int f = m_row_start[at(s) + 1] - m_row_start[at(s)], b = f - w;
  const T* panel = numeric<T>().panel.data() + m_panel_start[at(s)];
  // x₁ = L₁₁⁻¹·x₁; the rows below lose L₂₁·x₁ (those in the top later, when `deferred`).
  if constexpr (std::is_same_v<T, float>) {
    kernels::forward_panel(f, w, panel, f, x + k1, product);
  } else {
    const Panel<T> L(panel, f, w, Eigen::OuterStride<>(f));
    VectorMap<T> x1(x + k1, w);
    L.topRows(w).template triangularView<Eigen::Lower>().solveInPlace(x1);
    if (b > 0) VectorMap<T>(product, b).noalias() = L.bottomRows(b) * x1;
  }
  if (b == 0) return;
  const int* below = m_rows.data() + m_row_start[at(s)] + w;
  const int now = deferred == nullptr
                      ? b
                      : b - static_cast<int>(m_deferred_start[at(s) + 1] - m_deferred_start[at(s)]);
  for (int r = 0; r < now; ++r) x[below[r]] -= product[r];
  for (int r = now; r < b; ++r) deferred[r - now] = product[r];
}

void SparseCholesky::forward_in_place(std::span<double> x) const {
  DEXCLOTH_DEMAND(x.size() == at(m_n));
  if (m_precision == Precision::double_precision) return forward_in(x.data());
  std::vector<float>& xs = m_single.x;
  std::copy(x.begin(), x.end(), xs.begin());
  forward_in(xs.data());
  std::copy(xs.begin(), xs.end(), x.begin());
}

template <class T>
void SparseCholesky::forward_in(T* x) const {
  const Numeric<T>& numeric = this->numeric<T>();
  const int ns = supernodes();
  if (!m_threaded_solves) {
    for (int s = 0; s < ns; ++s) forward_front<T>(s, x, numeric.product[0].data(), nullptr);
    return;
  }
  // The threads' subtrees, each in column order, keep their updates of the top's rows; then, in
  // column order, those updates and the top's supernodes: every row loses the same terms in the
  // same order as on one thread.
  auto subtrees = [&](int t) {
    for (int s : m_solve_order[at(t)])
      forward_front(s, x, numeric.product[at(t)].data(),
                    numeric.deferred.data() + m_deferred_start[at(s)]);
  };
  pool()->run(subtrees);
  for (int s = 0; s < ns; ++s) {
    if (m_in_top[at(s)]) {
      forward_front<T>(s, x, numeric.product[0].data(), nullptr);
      continue;
    }
    const std::size_t d0 = m_deferred_start[at(s)], count = m_deferred_start[at(s) + 1] - d0;
    const int* top_rows = m_rows.data() + m_row_start[at(s) + 1] - count;
    for (std::size_t r = 0; r < count; ++r) x[at(top_rows[r])] -= numeric.deferred[d0 + r];
  }
}

template <class T>
void SparseCholesky::backward_front(int s, T* x, int lead, T* gather) const {
  const int k1 = m_first[at(s)];
  if (k1 >= lead) return;  // the tail: given
  const int w = m_first[at(s) + 1] - k1;
  const int f = m_row_start[at(s) + 1] - m_row_start[at(s)];
  // The unknown columns [k1, k1 + u): x_u = L_uu⁻ᵀ·(x_u − L_ru ᵀ·x_r) over the front's other
  // rows r (known: below the supernode, or given in the tail).
  const int u = std::min(w, lead - k1), known = f - u;
  const T* panel = numeric<T>().panel.data() + m_panel_start[at(s)];
  const int* rows = m_rows.data() + m_row_start[at(s)] + u;
  for (int r = 0; r < known; ++r) gather[r] = x[rows[r]];
  if constexpr (std::is_same_v<T, float>) {
    kernels::backward_panel(f, u, panel, f, x + k1, gather);
  } else {
    const Panel<T> L(panel, f, u, Eigen::OuterStride<>(f));
    VectorMap<T> xu(x + k1, u);
    if (known > 0) xu.noalias() -= L.bottomRows(known).transpose() * VectorMap<T>(gather, known);
    L.topRows(u).template triangularView<Eigen::Lower>().transpose().solveInPlace(xu);
  }
}

void SparseCholesky::backward_in_place(std::span<double> x, int tail) const {
  DEXCLOTH_DEMAND(x.size() == at(m_n) && tail >= 0 && tail <= m_n);
  if (m_precision == Precision::double_precision) return backward_in(x.data(), m_n - tail);
  std::vector<float>& xs = m_single.x;
  std::copy(x.begin(), x.end(), xs.begin());
  backward_in(xs.data(), m_n - tail);
  std::copy(xs.begin(), xs.end(), x.begin());
}

template <class T>
void SparseCholesky::backward_in(T* x, int lead) const {
  const Numeric<T>& numeric = this->numeric<T>();
  const int ns = supernodes();
  // Each supernode only reads the rows below it, all known by then: the top first, then the
  // threads' subtrees in parallel (bitwise the same in any order).
  for (int s = ns - 1; s >= 0; --s)
    if (!m_threaded_solves || m_in_top[at(s)]) backward_front(s, x, lead, numeric.gather[0].data());
  if (!m_threaded_solves) return;
  auto subtrees = [&](int t) {
    const std::vector<int>& order = m_solve_order[at(t)];
    for (auto it = order.rbegin(); it != order.rend(); ++it)
      backward_front(*it, x, lead, numeric.gather[at(t)].data());
  };
  pool()->run(subtrees);
}

void SparseCholesky::trailing_factor(int tail, Eigen::MatrixXd& L22) const {
  DEXCLOTH_DEMAND(tail >= 0 && tail <= m_n);
  const int lead = m_n - tail;
  L22.setZero(tail, tail);
  for (int s = static_cast<int>(m_first.size()) - 2; s >= 0 && m_first[at(s) + 1] > lead; --s) {
    const int k1 = m_first[at(s)], k2 = m_first[at(s) + 1];
    const int f = m_row_start[at(s) + 1] - m_row_start[at(s)];
    const int* rows = m_rows.data() + m_row_start[at(s)];
    for (int j = std::max(k1, lead); j < k2; ++j)
      for (int r = j - k1; r < f; ++r)
        L22(rows[r] - lead, j - lead) = entry(s, at(j - k1) * at(f) + at(r));
  }
}

double SparseCholesky::entry(int s, std::size_t k) const {
  const std::size_t offset = m_panel_start[at(s)] + k;
  return m_precision == Precision::single_precision ? m_single.panel.data()[offset]
                                                    : m_double.panel.data()[offset];
}

}  // namespace dexcloth::cloth
