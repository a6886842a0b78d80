#pragma once
// What an ordering costs: the scalar nnz(L) and flops exactly as CHOLMOD counts them, and the
// block costs of the block LDL^T, which works on dense blocks.
#include <cstdint>
#include <span>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// Scalar symbolic counts of L for the permuted matrix P A P^T (perm[k] = row eliminated k-th):
// the elimination tree, then the row subtrees (Liu; CSparse's cs_etree and cs_ereach), O(nnz(L)).
struct ScalarCounts {
  int64_t nnz_L = 0;  // entries of L, diagonal included (CHOLMOD's Common->lnz)
  double flops = 0;   // sum over columns of (entries in the column, diagonal included)^2
                      // (CHOLMOD's Common->fl) = sum c_j (c_j + 2) + n
};
ScalarCounts scalar_counts(const Graph& scalar_graph, std::span<const int> perm);

// Costs of the block LDL^T with dense blocks. For pivot k of size d whose eliminated edges
// hold h rows (the height of its column of L below the pivot):
//   nnz:   d (d + 1) / 2 + h d                entries of its column of L
//   flops: d (d + 1) (2d + 1) / 6             LDL^T of the pivot block N
//        + h d (d + 1)                        L = E N^-1
//        + d h^2                              S -= E L^T (h (h + 1) / 2 dot products of length d, x2)
// which is the talk's cost model (LDL(N) ~ d^3, L ~ h d^2, reduction ~ d h (h + 1) / 2
// multiply-adds), and exactly CHOLMOD's Common->fl for the matrix with every block dense.
struct BlockCosts {
  int64_t fill_edges = 0;  // block edges created by elimination
  int64_t nnz_L = 0;       // scalar entries stored by the block factor (dense blocks)
  double flops = 0;        // as above
};
// The flops above for one pivot of d rows whose column of L holds h rows below it.
inline double block_pivot_flops(int64_t d, int64_t h) {
  return static_cast<double>(d * (d + 1) * (2 * d + 1) / 6 + h * d * (d + 1) + d * h * h);
}
BlockCosts block_costs(const BlockPattern& pattern, std::span<const int> pivots, const Elimination& e);

}  // namespace ldlpgs

#include <optional>
#include <string>

#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

// One row of an orderings comparison.
struct OrderingSummary {
  std::string name;
  int64_t nnz_L = 0;               // scalar, as CHOLMOD counts
  double flops = 0;                // scalar, as CHOLMOD counts
  std::optional<BlockCosts> block; // block orderings only: the scalar ones may split blocks
  double time_ms = 0;
};
OrderingSummary summarize(const Ordering& o, const BlockPattern& blocks, const Graph& scalar_graph);

}  // namespace ldlpgs
