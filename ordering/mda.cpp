// Minimum degree (the talk's MDA): repeatedly eliminate a block of least degree in the current
// elimination graph. mda and mda-w run on the quotient graph (quotient_graph.h) with AMD's
// approximate degree; mda-exact and mda-w-exact below play the explicit graph, with a
// priority set keyed by (degree, block index): O(log n) per degree update, and the degrees of
// only the eliminated block's neighbours change.
//
// mda counts the degree in blocks; mda-w weights each neighbour by its block size, so the key
// is the height (in rows) of the block's column of L if it were eliminated now.
//
// Ties go to the highest block index: over the families and test matrices it gives 6% fewer
// block flops than the lowest for mda and 1% for mda-w (geometric means, bench/tie_breaking.cpp
// in papers/orderings.md), though it loses on bcsstk13.
#include <set>
#include <tuple>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/ordering/quotient_graph.h"

namespace ldlpgs {
std::vector<int> minimum_degree(const BlockPattern& pattern, bool weighted, TieBreak tie) {
  const int nb = pattern.num_blocks();
  EliminationGraph g(pattern.graph());
  auto key = [&](int v) {
    if (!weighted) return static_cast<int64_t>(g.degree(v));
    int64_t rows = 0;
    for (int u : g.neighbors(v)) rows += pattern.block(u).size;
    return rows;
  };
  using Key = std::tuple<int64_t, int, int>;  // (degree, tie, block)
  auto make_key = [&](int v) { return Key{key(v), tie == TieBreak::highest_index ? -v : v, v}; };
  std::vector<Key> current(nb);
  std::set<Key> queue;
  for (int v = 0; v < nb; ++v) queue.insert(current[v] = make_key(v));
  std::vector<int> pivots;
  pivots.reserve(nb);
  std::vector<int> nbrs;
  while (!queue.empty()) {
    const int p = std::get<2>(*queue.begin());
    queue.erase(queue.begin());
    pivots.push_back(p);
    nbrs.assign(g.neighbors(p).begin(), g.neighbors(p).end());
    g.eliminate(p);
    for (int u : nbrs) {
      queue.erase(current[u]);
      queue.insert(current[u] = make_key(u));
    }
  }
  return pivots;
}

std::vector<int> order_mda_exact(const BlockPattern& pattern) {
  return minimum_degree(pattern, false, TieBreak::highest_index);
}
std::vector<int> order_mda_w_exact(const BlockPattern& pattern) {
  return minimum_degree(pattern, true, TieBreak::highest_index);
}
std::vector<int> order_mda(const BlockPattern& pattern) {
  return quotient_order(pattern, {QuotientScore::degree, false, TieBreak::highest_index});
}
std::vector<int> order_mda_w(const BlockPattern& pattern) {
  return quotient_order(pattern, {QuotientScore::degree, true, TieBreak::highest_index});
}

}  // namespace ldlpgs
