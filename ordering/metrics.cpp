#include "ldlpgs/ordering/metrics.h"

#include <cassert>
#include <vector>

namespace ldlpgs {

ScalarCounts scalar_counts(const Graph& g, std::span<const int> perm) {
  const int n = g.n;
  assert(static_cast<int>(perm.size()) == n);
  std::vector<int> pinv(n);
  for (int k = 0; k < n; ++k) pinv[perm[k]] = k;
  // Elimination tree of P A P^T: for each row k, every earlier column i of row k hangs, through
  // its current root, under k (path compression on `ancestor`).
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k) {
    for (int j : g.neighbors(perm[k])) {
      int i = pinv[j];
      while (i != -1 && i < k) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
    }
  }
  // Row k of L is the union of the tree paths from each entry (k, i), i < k, up to k: the row
  // subtree. Each node visited adds one entry to its column.
  std::vector<int64_t> count(n, 0);
  std::vector<int> mark(n, -1);
  for (int k = 0; k < n; ++k) {
    mark[k] = k;
    for (int j : g.neighbors(perm[k])) {
      for (int i = pinv[j]; i < k && mark[i] != k; i = parent[i]) {
        ++count[i];
        mark[i] = k;
      }
    }
  }
  ScalarCounts c;
  for (int j = 0; j < n; ++j) {
    c.nnz_L += count[j] + 1;
    c.flops += static_cast<double>(count[j] + 1) * static_cast<double>(count[j] + 1);
  }
  return c;
}

BlockCosts block_costs(const BlockPattern& pattern, std::span<const int> pivots, const Elimination& e) {
  BlockCosts c;
  c.fill_edges = e.fill_edges;
  for (int k = 0; k < e.num_pivots(); ++k) {
    const int64_t d = pattern.block(pivots[k]).size;
    int64_t h = 0;
    for (int q : e.column(k)) h += pattern.block(pivots[q]).size;
    c.nnz_L += d * (d + 1) / 2 + h * d;
    c.flops += block_pivot_flops(d, h);
  }
  return c;
}

}  // namespace ldlpgs

namespace ldlpgs {

OrderingSummary summarize(const Ordering& o, const BlockPattern& blocks, const Graph& scalar_graph) {
  OrderingSummary s;
  s.name = o.name;
  s.time_ms = o.time_ms;
  const ScalarCounts c = scalar_counts(scalar_graph, o.perm);
  s.nnz_L = c.nnz_L;
  s.flops = c.flops;
  if (o.level == Level::block) s.block = block_costs(blocks, o.pivots, o.elimination);
  return s;
}

}  // namespace ldlpgs
