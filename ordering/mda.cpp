// Minimum degree (the talk's MDA): repeatedly eliminate a block of least degree in the current
// elimination graph. Played on the explicit graph (no quotient graph, unlike AMD), with a
// priority set keyed by (degree, block index): O(log n) per degree update, and the degrees of
// only the eliminated block's neighbours change.
//
// mda counts the degree in blocks; mda-w weights each neighbour by its block size, so the key
// is the height (in rows) of the block's column of L if it were eliminated now.
//
// Ties go to the lowest block index. Measured against breaking ties by larger block first and
// by fewer fill edges, on every family and test matrix: see papers/orderings.md.
#include <set>
#include <utility>

#include "ordering/ordering.h"

namespace ldlpgs {
namespace {

std::vector<int> minimum_degree(const BlockPattern& pattern, bool weighted) {
  const int nb = pattern.num_blocks();
  EliminationGraph g(pattern.graph());
  auto key = [&](int v) {
    if (!weighted) return static_cast<int64_t>(g.degree(v));
    int64_t rows = 0;
    for (int u : g.neighbors(v)) rows += pattern.block(u).size;
    return rows;
  };
  std::vector<int64_t> current(nb);
  std::set<std::pair<int64_t, int>> queue;
  for (int v = 0; v < nb; ++v) queue.emplace(current[v] = key(v), v);
  std::vector<int> pivots;
  pivots.reserve(nb);
  std::vector<int> nbrs;
  while (!queue.empty()) {
    const int p = queue.begin()->second;
    queue.erase(queue.begin());
    pivots.push_back(p);
    nbrs.assign(g.neighbors(p).begin(), g.neighbors(p).end());
    g.eliminate(p);
    for (int u : nbrs) {
      queue.erase({current[u], u});
      queue.emplace(current[u] = key(u), u);
    }
  }
  return pivots;
}

}  // namespace

std::vector<int> order_mda(const BlockPattern& pattern) { return minimum_degree(pattern, false); }
std::vector<int> order_mda_w(const BlockPattern& pattern) { return minimum_degree(pattern, true); }

}  // namespace ldlpgs
