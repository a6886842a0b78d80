#pragma once
// ordering/: elimination orderings on the block graph, and what they cost.
//
//   elimination_graph.h  the elimination game: EliminationGraph, eliminate() -> Elimination
//   natural.cpp          natural      blocks in their given order
//   quotient_graph.h     the quotient graph (elements, supervariables, approximate degrees)
//   mda.cpp              mda, mda-w   minimum degree (the talk's MDA), degree in blocks or rows,
//                                     on the quotient graph; mda-exact, mda-w-exact on the
//                                     explicit elimination graph
//   meca.cpp             meca, meca-w minimum edge creation (the talk's MECA), edges or entries,
//                                     approximate fill on the quotient graph; meca-exact and
//                                     meca-w-exact count it exactly on the explicit graph
//   amd.cpp              amd          SuiteSparse AMD on the block graph
//   metis.cpp            metis        METIS nested dissection, block sizes as vertex weights
//   best.cpp             best         the candidates below, each once; the fewest block flops
//   certify.h            certify      a proof that an order has the fewest block flops, or a bound
//   metrics.h            nnz(L) and flops as CHOLMOD counts them, block fill and block flops
//   postorder.h          an order's weighted elimination-tree postorder (the same fill), which
//                        the symbolic analysis factors in
//
// Every ordering has one signature, OrderingFn: a block graph in, a pivot sequence out. The
// `-scalar` variants (amd-scalar, metis-scalar) run the same function on the scalar graph (one
// block per row): they may split blocks, so they are references for fill and flops only.
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// pivots[k] = the block eliminated k-th (a permutation of 0 .. num_blocks-1).
using OrderingFn = std::vector<int> (*)(const BlockPattern& pattern);

std::vector<int> order_natural(const BlockPattern& pattern);
std::vector<int> order_mda(const BlockPattern& pattern);
std::vector<int> order_mda_w(const BlockPattern& pattern);
std::vector<int> order_meca(const BlockPattern& pattern);
std::vector<int> order_meca_w(const BlockPattern& pattern);
std::vector<int> order_mda_exact(const BlockPattern& pattern);
std::vector<int> order_mda_w_exact(const BlockPattern& pattern);
std::vector<int> order_meca_exact(const BlockPattern& pattern);
std::vector<int> order_meca_w_exact(const BlockPattern& pattern);
std::vector<int> order_amd(const BlockPattern& pattern);
std::vector<int> order_metis(const BlockPattern& pattern);
std::vector<int> order_best(const BlockPattern& pattern);

// The orderings `best` runs, in the order that breaks its ties (best.cpp).
inline constexpr std::array<std::string_view, 6> kBestCandidates = {"meca", "meca-w", "amd", "metis", "mda-w", "mda"};
// What a choosing ordering returns: its pivots and the name of the ordering that gave them.
struct Choice {
  std::vector<int> pivots;  // (size num_blocks)
  std::string chosen;       // a name of kBestCandidates
};
Choice choose_best(const BlockPattern& pattern);

// Ties between blocks of equal key (degree, or edges created) are broken by the lowest block
// index, or the highest, or (MECA only) the least degree first, then the lowest index. The
// defaults in order_mda_exact and order_meca_exact were chosen by measurement
// (bench/tie_breaking.cpp, papers/orderings.md); the quotient-graph forms keep them. These two
// play the exact game on the explicit graph.
enum class TieBreak { lowest_index, highest_index, least_degree };
std::vector<int> minimum_degree(const BlockPattern& pattern, bool weighted, TieBreak tie);
std::vector<int> minimum_edge_creation(const BlockPattern& pattern, bool weighted, TieBreak tie);

enum class Level { block, scalar };

struct OrderingInfo {
  std::string_view name;
  OrderingFn fn;
  Level level;  // scalar: run on the scalar graph
  std::string_view summary;
  Choice (*choose)(const BlockPattern&) = nullptr;  // set for `best`: fn, and which ordering won
};

// All orderings, in the order reports list them.
std::span<const OrderingInfo> orderings();
// Throws InputError naming the unknown ordering and listing the known ones.
const OrderingInfo& find_ordering(std::string_view name);
// Splits "mda,meca,amd" (or "all") and checks every name.
std::vector<std::string> parse_ordering_list(std::string_view list);

// An ordering computed for a matrix: the same type for every ordering.
struct Ordering {
  std::string name;
  std::string chosen;       // the ordering whose pivots these are: `name`, or best's winner
  Level level = Level::block;
  std::vector<int> pivots;  // pivot sequence on the pattern it ran on: blocks for block
                            // orderings, rows for scalar ones (size num_blocks or n)
  std::vector<int> perm;    // scalar pivot order: perm[k] = row eliminated k-th (size n)
  Elimination elimination;  // eliminated edges per pivot, on the pattern it ran on
  double time_ms = 0;       // time of the ordering function alone
};

// The name a table shows: the ordering, and the one that won when they differ ("best (meca-w)").
std::string shown_name(std::string_view name, std::string_view chosen);
std::string shown_name(const Ordering& o);

// Expands a block pivot sequence into the scalar pivot order (rows of each block in order).
std::vector<int> expand_pivots(const BlockPattern& pattern, std::span<const int> pivots);

// Runs the named ordering on the blocks (or, for a scalar ordering, on the rows) of `a`.
Ordering compute_ordering(const OrderingInfo& info, const BlockPattern& blocks, const SymmetricCsc& a);

}  // namespace ldlpgs
