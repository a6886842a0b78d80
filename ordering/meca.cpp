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

namespace {

// The exact game: the queue of blocks by score, and the scratch of one step's rescoring.
class EdgeCreationGame {
 public:
  EdgeCreationGame(const BlockPattern& pattern, bool weighted, TieBreak tie)
      : nb_(pattern.num_blocks()), weight_(weighted ? pattern.block_sizes() : std::vector<int>(nb_, 1)),
        tie_(tie), g_(pattern.graph()), current_(nb_), gained_(nb_), in_nbrs_(nb_, 0), in_gained_(nb_, 0),
        in_outside_(nb_, 0) {
    for (int v = 0; v < nb_; ++v) {
      current_[v] = {g_.fill_if_eliminated(v, weight_), secondary(v), index_tie(v), v};
      queue_.insert(current_[v]);
    }
  }

  std::vector<int> run() {
    std::vector<int> pivots;
    pivots.reserve(nb_);
    while (!queue_.empty()) {
      const int p = std::get<3>(*queue_.begin());
      queue_.erase(queue_.begin());
      pivots.push_back(p);
      nbrs_.assign(g_.neighbors(p).begin(), g_.neighbors(p).end());
      created_.clear();
      g_.eliminate(p, &created_);
      for (int u : nbrs_) in_nbrs_[u] = 1;
      for (auto [a, b] : created_) lower_common_neighbours(a, b);
      for (int u : nbrs_) rescore_neighbour(u, p);
      for (int u : nbrs_) {
        in_nbrs_[u] = 0;
        gained_[u].clear();
      }
    }
    return pivots;
  }

 private:
  using Key = std::tuple<int64_t, int, int, int>;  // (fill, degree or 0, index tie, block)

  int secondary(int v) const { return tie_ == TieBreak::least_degree ? g_.degree(v) : 0; }
  int index_tie(int v) const { return tie_ == TieBreak::highest_index ? -v : v; }
  void add_to_score(int v, int64_t delta) {
    queue_.erase(current_[v]);
    std::get<0>(current_[v]) += delta;
    std::get<1>(current_[v]) = secondary(v);
    queue_.insert(current_[v]);
  }

  // The new edge (a, b): every common neighbour of a and b outside N(p) misses it no longer.
  void lower_common_neighbours(int a, int b) {
    gained_[a].push_back(b);
    gained_[b].push_back(a);
    const int64_t wab = static_cast<int64_t>(weight_[a]) * weight_[b];
    auto na = g_.neighbors(a), nb = g_.neighbors(b);
    for (auto i = na.begin(), j = nb.begin(); i != na.end() && j != nb.end();) {  // (a merge: sorted lists)
      if (*i < *j) {
        ++i;
      } else if (*j < *i) {
        ++j;
      } else {
        if (!in_nbrs_[*i]) add_to_score(*i, -wab);
        ++i;
        ++j;
      }
    }
  }

  // u in N(p): the three terms of the comment above, with O its neighbours outside N(p) and Z
  // the neighbours it gained.
  void rescore_neighbour(int u, int p) {
    for (int z : gained_[u]) in_gained_[z] = 1;
    int64_t w_outside = 0;
    for (int y : g_.neighbors(u)) {
      if (!in_nbrs_[y]) {
        in_outside_[y] = 1;
        w_outside += weight_[y];
      }
    }
    int64_t delta = -static_cast<int64_t>(weight_[p]) * w_outside;
    for (auto [a, b] : created_) {
      if (a != u && b != u && !in_gained_[a] && !in_gained_[b]) delta -= static_cast<int64_t>(weight_[a]) * weight_[b];
    }
    for (int z : gained_[u]) {
      int64_t adjacent = 0;
      for (int y : g_.neighbors(z)) {
        if (in_outside_[y]) adjacent += weight_[y];
      }
      delta += weight_[z] * (w_outside - adjacent);
    }
    add_to_score(u, delta);
    for (int y : g_.neighbors(u)) in_outside_[y] = 0;
    for (int z : gained_[u]) in_gained_[z] = 0;
  }

  const int nb_;
  const std::vector<int> weight_;
  const TieBreak tie_;
  EliminationGraph g_;
  std::vector<Key> current_;
  std::set<Key> queue_;
  std::vector<int> nbrs_;                      // N(p), this step
  std::vector<std::pair<int, int>> created_;   // E+, this step
  std::vector<std::vector<int>> gained_;       // Z for each block of N(p), this step
  std::vector<uint8_t> in_nbrs_, in_gained_, in_outside_;
};

}  // namespace

std::vector<int> minimum_edge_creation(const BlockPattern& pattern, bool weighted, TieBreak tie) {
  return EdgeCreationGame(pattern, weighted, tie).run();
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
