#pragma once
// The weighted postorder of the block elimination tree (CHOLMOD's cholmod_analyze with
// Common->postorder): an equivalent pivot sequence in which every subtree is a run of
// consecutive pivots and each pivot's heaviest child comes last, right before it.
#include <span>
#include <vector>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

// e: the elimination game of `pivots` (eliminate(pattern, pivots)); pivots must be a permutation
// of the blocks and e of as many pivots (ArgumentError otherwise, in every build). The parent of pivot k in the
// block elimination tree is its first eliminated edge; a child's weight is its column of L's
// rows, its block included. Children are visited lightest first (ties in pivot order), roots in
// pivot order. Eliminating in any postorder of the tree gives the same filled graph (Liu, "The
// role of elimination trees in sparse factorization", 1990), so fill, nnz(L) and flops are
// `pivots`' own; what changes is that a chain of parents becomes consecutive pivots, which the
// symbolic analysis groups into supernodes (papers/factor.md, "Postordered pivots").
std::vector<int> postorder(const BlockPattern& pattern, std::span<const int> pivots, const Elimination& e);

}  // namespace ldlpgs
