#pragma once
// A certificate for block flops (metrics.h): the least block flops of any block elimination
// order, proved within a time limit, or a lower bound on it. `order --certify` compares the
// orderings' block flops with it: equal to the optimum (or to a lower bound) proves optimal.
//
// The proof (certify.cpp): peel simplicial blocks (never more fill or flops: proved there for
// block flops), which alone solves a chordal block graph; split what remains on clique
// separators (valid for block flops, less the separator's own cost: proved there); then an exact
// branch and bound over the connected sets of each atom, memoised, until the time limit; an atom
// it did not finish contributes a lower bound instead.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

struct BlockFlopsCertificate {
  bool optimal_proved = false;  // lower_bound is the optimum itself
  double lower_bound = 0;       // block flops no elimination order goes below (= the optimum when proved)
  int peeled = 0;               // blocks removed as simplicial before the search
  bool chordal = false;         // peeling removed every block: the block graph is chordal
  int atoms = 0;                // pieces left by the clique separators, searched one by one
  int64_t states = 0;           // connected sets the search solved (memo entries)
  std::vector<int> pivots;      // an order of the blocks reaching the optimum, when proved (its
                                // block flops played and checked); else empty (size blocks)
  double time_ms = 0;
};

// pivots (optional): an order whose block flops the search need not beat, the best one known
// (it prunes the search, and an order the search cannot beat is optimal); a permutation of the
// blocks, or ArgumentError.
BlockFlopsCertificate certify_block_flops(const BlockPattern& pattern, double time_limit_s,
                                          std::span<const int> pivots = {});

// The certificate's order as an Ordering named "optimal" (chosen "certify", time_ms the
// certificate's), when one was proved with fewer block flops than `fewest_known` (the least of
// the orderings compared): the row `ldlpgs order --certify` and ldlpgs.order(certify=True) add
// for an optimum no heuristic reached. nullopt otherwise.
std::optional<Ordering> certificate_ordering(const BlockPattern& pattern, const BlockFlopsCertificate& cert,
                                             double fewest_known);

// The block flops of a zero-fill order of `pattern`, as if it were chordal: a lower bound for
// every order, and the optimum on a chordal block graph (certify.cpp, 0 and 4).
double zero_fill_block_flops(const BlockPattern& pattern);

// An order no order beats: its block flops reach the lower bound (the optimum when proved).
inline bool certified_optimal(const BlockFlopsCertificate& cert, double block_flops) {
  return block_flops <= cert.lower_bound;
}

}  // namespace ldlpgs
