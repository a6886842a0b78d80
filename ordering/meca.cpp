// Minimum edge creation (the talk's MECA): repeatedly eliminate the block whose elimination
// creates the fewest new edges (pairs of its neighbours not yet adjacent). meca-w counts new
// scalar entries instead: a new edge between blocks of sizes d_u and d_v costs d_u * d_v.
// meca and meca-w run on the quotient graph with an approximate fill score (quotient_graph.h);
// meca-exact and meca-w-exact, below, keep the exact scores on the explicit graph.
//
// Keeping the scores exact without rescoring (a rescore of v costs the sum of its neighbours'
// degrees, which made MECA 5x slower on bcsstk13). Eliminating p creates edges E+ among N(p)
// and removes p. For a block x outside N(p), N(x) is unchanged and only gains the edges of E+
// inside it: each (a, b) in E+ lowers the score of every common neighbour x of a and b by
// w_a w_b. For u in N(p), with Z the neighbours u gained, A = N(u) \ Z the ones it kept and
// O = A \ N(p) those not adjacent to p:
//   fill(u) -= w_p w(O)                                    pairs (p, y), y in O, are gone
//   fill(u) -= sum over (a, b) in E+, a, b in A, of w_a w_b
//   fill(u) += sum over z in Z of w_z (w(O) - w(N(z) n O))  new pairs (z, y) still missing
// (pairs inside Z, and between Z and A n N(p), are edges: N(p) is now a clique). A step costs
// about degree(p) * (degree + |E+|) + |E+| * degree, small because MECA keeps |E+| small.
// ordering_test checks every choice against a brute-force recount.
//
// Ties: meca goes to the highest block index (7% fewer block flops than least degree first,
// geometric mean over the families and test matrices); meca-w to the least degree, then the
// lowest index (all three rules within 0.2% of each other). Measured by bench/tie_breaking.cpp,
// table in papers/orderings.md.
#include <set>
#include <tuple>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/ordering/quotient_graph.h"

namespace ldlpgs {
std::vector<int> minimum_edge_creation(const BlockPattern& pattern, bool weighted, TieBreak tie) {
  const int nb = pattern.num_blocks();
  std::vector<int> weight(nb, 1);
  if (weighted) weight = pattern.block_sizes();
  EliminationGraph g(pattern.graph());
  using Key = std::tuple<int64_t, int, int, int>;  // (fill, degree or 0, index tie, block)
  auto secondary = [&](int v) { return tie == TieBreak::least_degree ? g.degree(v) : 0; };
  auto index_tie = [&](int v) { return tie == TieBreak::highest_index ? -v : v; };
  std::vector<Key> current(nb);
  std::set<Key> queue;
  for (int v = 0; v < nb; ++v) {
    current[v] = {g.fill_if_eliminated(v, weight), secondary(v), index_tie(v), v};
    queue.insert(current[v]);
  }
  auto add_to_score = [&](int v, int64_t delta) {
    queue.erase(current[v]);
    std::get<0>(current[v]) += delta;
    std::get<1>(current[v]) = secondary(v);
    queue.insert(current[v]);
  };
  std::vector<int> pivots, nbrs;
  std::vector<std::pair<int, int>> created;
  std::vector<std::vector<int>> gained(nb);  // Z for each block of N(p), this step
  std::vector<uint8_t> in_nbrs(nb, 0), in_gained(nb, 0), in_outside(nb, 0);
  pivots.reserve(nb);
  while (!queue.empty()) {
    const int p = std::get<3>(*queue.begin());
    queue.erase(queue.begin());
    pivots.push_back(p);
    nbrs.assign(g.neighbors(p).begin(), g.neighbors(p).end());
    created.clear();
    g.eliminate(p, &created);
    for (int u : nbrs) in_nbrs[u] = 1;
    for (auto [a, b] : created) {
      gained[a].push_back(b);
      gained[b].push_back(a);
      const int64_t wab = static_cast<int64_t>(weight[a]) * weight[b];
      auto na = g.neighbors(a), nb_ = g.neighbors(b);
      // Common neighbours of a and b outside N(p), by a merge of the two sorted lists.
      for (auto i = na.begin(), j = nb_.begin(); i != na.end() && j != nb_.end();) {
        if (*i < *j) {
          ++i;
        } else if (*j < *i) {
          ++j;
        } else {
          if (!in_nbrs[*i]) add_to_score(*i, -wab);
          ++i;
          ++j;
        }
      }
    }
    for (int u : nbrs) {
      for (int z : gained[u]) in_gained[z] = 1;
      int64_t w_outside = 0;
      for (int y : g.neighbors(u)) {
        if (!in_nbrs[y]) {
          in_outside[y] = 1;
          w_outside += weight[y];
        }
      }
      int64_t delta = -static_cast<int64_t>(weight[p]) * w_outside;
      for (auto [a, b] : created) {
        if (a != u && b != u && !in_gained[a] && !in_gained[b]) delta -= static_cast<int64_t>(weight[a]) * weight[b];
      }
      for (int z : gained[u]) {
        int64_t adjacent = 0;
        for (int y : g.neighbors(z)) {
          if (in_outside[y]) adjacent += weight[y];
        }
        delta += weight[z] * (w_outside - adjacent);
      }
      add_to_score(u, delta);
      for (int y : g.neighbors(u)) in_outside[y] = 0;
      for (int z : gained[u]) in_gained[z] = 0;
    }
    for (int u : nbrs) {
      in_nbrs[u] = 0;
      gained[u].clear();
    }
  }
  return pivots;
}

std::vector<int> order_meca_exact(const BlockPattern& pattern) {
  return minimum_edge_creation(pattern, false, TieBreak::highest_index);
}
std::vector<int> order_meca_w_exact(const BlockPattern& pattern) {
  return minimum_edge_creation(pattern, true, TieBreak::least_degree);
}
std::vector<int> order_meca(const BlockPattern& pattern) {
  return quotient_order(pattern, {QuotientScore::fill, false, TieBreak::highest_index});
}
std::vector<int> order_meca_w(const BlockPattern& pattern) {
  return quotient_order(pattern, {QuotientScore::fill, true, TieBreak::least_degree});
}

}  // namespace ldlpgs
