#pragma once
// The elimination game (the talk's "Gaussian elimination <-> graph elimination"): eliminating
// pivot p connects all of p's neighbours pairwise (the fill) and removes p. EliminationGraph is
// the explicit graph the game is played on (MDA and MECA choose their pivots on it); `eliminate`
// gives the game's outcome for a whole pivot sequence, the block structure of L, from the
// elimination tree instead of playing it edge by edge.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

class EliminationGraph {
 public:
  explicit EliminationGraph(const Graph& g);

  // The live neighbours of v, ascending.
  std::span<const int> neighbors(int v) const { return adj_[v]; }
  int degree(int v) const { return static_cast<int>(adj_[v].size()); }
  bool eliminated(int v) const { return eliminated_[v] != 0; }

  // Eliminates p; returns the number of edges it created, and appends them (u < v) to
  // created_edges when given. Cost O(sum of the neighbours' degrees + degree(p)^2), all in
  // sorted merges.
  int64_t eliminate(int p, std::vector<std::pair<int, int>>* created_edges = nullptr);

  // The fill eliminating p would create: pairs of neighbours not yet adjacent, each weighted by
  // weight[u] * weight[v] (pass all-ones weights to count edges). O(sum of neighbour degrees).
  int64_t fill_if_eliminated(int p, std::span<const int> weight);

 private:
  std::vector<std::vector<int>> adj_;  // live neighbour lists, ascending (size n)
  std::vector<uint8_t> eliminated_;    // (size n)
  std::vector<int> merged_;            // scratch for eliminate
  std::vector<int> mark_;              // stamps for fill_if_eliminated (size n)
  int stamp_ = 0;
};

// The block structure of L for a pivot sequence: for each pivot k, the pivot positions of the
// blocks adjacent to it when it is eliminated ("its eliminated edges, in pivot order", the
// talk's Elim(n_i)), each flagged when elimination created it (a fill block).
struct Elimination {
  std::vector<int> ptr;       // edges of pivot k: [ptr[k], ptr[k+1]) (size num_blocks+1)
  std::vector<int> edges;     // pivot positions, ascending, all > k (size ptr[num_blocks])
  std::vector<uint8_t> fill;  // 1 for a fill edge (size ptr[num_blocks])
  int64_t fill_edges = 0;     // number of fill edges

  int num_pivots() const { return static_cast<int>(ptr.size()) - 1; }
  std::span<const int> column(int k) const {
    return {edges.data() + ptr[k], static_cast<size_t>(ptr[k + 1] - ptr[k])};
  }
};

// The outcome of the game for `pivots` (a permutation of the blocks: pivots[k] = block
// eliminated k-th), in O(blocks of L).
Elimination eliminate(const BlockPattern& pattern, std::span<const int> pivots);

}  // namespace ldlpgs
