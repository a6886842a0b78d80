#include "ldlpgs/ordering/elimination_graph.h"

#include <algorithm>
#include <cassert>

namespace ldlpgs {

EliminationGraph::EliminationGraph(const Graph& g)
    : adj_(g.n), eliminated_(g.n, 0), mark_(g.n, 0) {
  for (int v = 0; v < g.n; ++v) {
    auto nbrs = g.neighbors(v);
    adj_[v].assign(nbrs.begin(), nbrs.end());
  }
}

int64_t EliminationGraph::eliminate(int p, std::vector<std::pair<int, int>>* created_edges) {
  assert(!eliminated_[p]);
  const std::vector<int>& clique = adj_[p];
  int64_t created = 0;
  for (int u : clique) {
    // N(u) <- (N(u) u N(p)) \ {u, p}, by one merge of two sorted lists.
    const std::vector<int>& old = adj_[u];
    merged_.clear();
    size_t a = 0, b = 0;
    while (a < old.size() || b < clique.size()) {
      int x;
      if (b == clique.size() || (a < old.size() && old[a] < clique[b])) {
        x = old[a++];
      } else if (a == old.size() || clique[b] < old[a]) {
        x = clique[b++];
        if (created_edges && u < x) created_edges->emplace_back(u, x);
      } else {
        x = old[a++];
        ++b;
      }
      if (x != u && x != p) merged_.push_back(x);
    }
    created += static_cast<int64_t>(merged_.size()) - static_cast<int64_t>(old.size() - 1);
    adj_[u].swap(merged_);
  }
  adj_[p].clear();
  adj_[p].shrink_to_fit();
  eliminated_[p] = 1;
  assert(created % 2 == 0);  // each new edge was added at both ends
  return created / 2;
}

int64_t EliminationGraph::fill_if_eliminated(int p, std::span<const int> weight) {
  const std::vector<int>& nbrs = adj_[p];
  if (nbrs.size() < 2) return 0;
  if (++stamp_ == 0) {  // the stamps wrapped around: clear them
    std::fill(mark_.begin(), mark_.end(), 0);
    stamp_ = 1;
  }
  int64_t total = 0, sum_sq = 0;
  for (int u : nbrs) {
    mark_[u] = stamp_;
    total += weight[u];
    sum_sq += static_cast<int64_t>(weight[u]) * weight[u];
  }
  // All pairs among the neighbours, minus the pairs already joined by an edge.
  int64_t pairs = (total * total - sum_sq) / 2, present = 0;
  for (int u : nbrs) {
    int64_t w = 0;
    for (int x : adj_[u]) {
      if (mark_[x] == stamp_) w += weight[x];
    }
    present += w * weight[u];
  }
  return pairs - present / 2;
}

Elimination eliminate(const BlockPattern& pattern, std::span<const int> pivots) {
  // The game's outcome without playing it edge by edge: in pivot order, the blocks adjacent to
  // pivot i when it is eliminated are the rows k > i of column i of L, and row k of L is the
  // union of the elimination-tree paths from its original entries up to k (the row subtree,
  // as in scalar_counts). This costs O(blocks of L) instead of the game's O(sum of degree^2).
  // elimination_test checks it against EliminationGraph, the game itself.
  const int nb = pattern.num_blocks();
  assert(static_cast<int>(pivots.size()) == nb);
  std::vector<int> position(nb, -1);
  for (int k = 0; k < nb; ++k) {
    assert(position[pivots[k]] == -1);
    position[pivots[k]] = k;
  }
  std::vector<int> parent(nb, -1), ancestor(nb, -1);
  for (int k = 0; k < nb; ++k) {
    for (int j : pattern.neighbors(pivots[k])) {
      for (int i = position[j]; i != -1 && i < k;) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
    }
  }
  Elimination e;
  e.ptr.assign(nb + 1, 0);
  std::vector<int> mark(nb, -1), original(nb, -1);
  // Two sweeps over the row subtrees: count each column, then fill it. Rows arrive in
  // increasing k, so each column comes out sorted in pivot order.
  for (int sweep = 0; sweep < 2; ++sweep) {
    std::vector<int> next(e.ptr.begin(), e.ptr.end() - 1);
    std::fill(mark.begin(), mark.end(), -1);
    for (int k = 0; k < nb; ++k) {
      mark[k] = k;
      for (int j : pattern.neighbors(pivots[k])) original[position[j]] = k;
      for (int j : pattern.neighbors(pivots[k])) {
        for (int i = position[j]; i < k && mark[i] != k; i = parent[i]) {
          mark[i] = k;
          if (sweep == 0) {
            ++e.ptr[i + 1];
          } else {
            e.edges[next[i]] = k;
            e.fill[next[i]++] = original[i] != k;
          }
        }
      }
    }
    if (sweep == 0) {
      for (int k = 0; k < nb; ++k) e.ptr[k + 1] += e.ptr[k];
      e.edges.resize(e.ptr[nb]);
      e.fill.resize(e.ptr[nb]);
    }
  }
  for (uint8_t f : e.fill) e.fill_edges += f;
  return e;
}

}  // namespace ldlpgs
