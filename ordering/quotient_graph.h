#pragma once
// The quotient graph (George and Liu; as AMD keeps it, Amestoy, Davis and Duff 1996) on which
// the greedy block orderings mda, mda-w, meca and meca-w run at AMD's scale.
//
// The elimination graph is never formed. An eliminated pivot p becomes an element: the clique
// L_p of its live neighbours, stored once as a list instead of |L_p|^2 fill edges. A variable i
// keeps A_i (its original edges not yet covered by an element) and E_i (the elements it belongs
// to); its neighbours in the elimination graph are A_i u (union of L_e, e in E_i) minus i. An
// element that a newer element contains is absorbed (removed); variables with the same A and E
// (indistinguishable: same closed neighbourhood) are merged into one supervariable, found by
// hashing, and eliminated together (mass elimination). Degrees are AMD's upper bound
//   d_i <= min(d_i_old + |L_p \ i|, |A_i \ i| + |L_p \ i| + sum_{e in E_i, e != p} |L_e \ L_p|)
// with |L_e \ L_p| counted for all e at once by subtracting, from |L_e|, the variables of L_p
// in it. Every count is kept in three weights at once (Mass): blocks, block weights, and
// squares of block weights; the last serves the fill score, which counts pairs of neighbours:
// pairs(S) = (w(S)^2 - q(S)) / 2 for a set S of total weight w and sum of squared weights q.
#include <cstdint>
#include <span>
#include <vector>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

// A count in three weights: c blocks, w their weights (1 or the block size), q the squares.
struct Mass {
  int64_t c = 0, w = 0, q = 0;
  Mass& operator+=(const Mass& o) {
    c += o.c;
    w += o.w;
    q += o.q;
    return *this;
  }
  Mass& operator-=(const Mass& o) {
    c -= o.c;
    w -= o.w;
    q -= o.q;
    return *this;
  }
  friend Mass operator+(Mass a, const Mass& b) { return a += b; }
  friend Mass operator-(Mass a, const Mass& b) { return a -= b; }
  // Weighted pairs of distinct blocks in a set of this mass: sum over u < v of w_u w_v.
  int64_t pairs() const { return (w * w - q) / 2; }
};

// What the greedy ordering minimises, for a supervariable i. d is the bound on its external
// degree, cover the largest element-clique among its neighbours (the pairs already adjacent
// that the score may subtract), own the mass of i itself, own_max the largest weight in i.
enum class QuotientScore {
  degree,         // mda, mda-w: d.w + own.w - own_max (the degree of i's heaviest block)
  fill,           // meca, meca-w: d.pairs() - cover.pairs() (approximate fill), or the fill
                  // counted exactly where the neighbourhood is small (quotient_graph.cpp)
};

struct QuotientOptions {
  QuotientScore score = QuotientScore::degree;
  bool weighted = false;  // block sizes as weights (else every block weighs 1)
  TieBreak tie = TieBreak::highest_index;
  // Room for the elements' lists in the workspace, in entries per entry of the graph: the lists
  // are compacted when it fills (AMD's garbage collection). The order does not depend on it; a
  // test sets 0 to compact often.
  double element_room = 1;
};

// One step of the game as the quotient graph saw it, for tests: the pivot supervariable's
// blocks, and the degree bound d (in blocks) of every block adjacent to it afterwards.
struct QuotientStep {
  std::vector<int> eliminated;                   // blocks eliminated together at this step
  std::vector<std::pair<int, int64_t>> degrees;  // (block, d.c + blocks merged with it - 1)
};

// The block pivot sequence. When `trace` is given, one QuotientStep per pivot supervariable.
std::vector<int> quotient_order(const BlockPattern& pattern, const QuotientOptions& options,
                                std::vector<QuotientStep>* trace = nullptr);

}  // namespace ldlpgs
