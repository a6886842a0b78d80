// METIS nested dissection (METIS_NodeND) on the block graph, block sizes as vertex weights so
// separators balance rows, not blocks. Debian's METIS has 32-bit idx_t, as our indices.
// On graphs under about 240 vertices METIS_NodeND does no bisection at all beyond the first: it
// orders with its own multiple minimum degree.
#include <metis.h>

#include <numeric>
#include <stdexcept>
#include <type_traits>

#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

static_assert(std::is_same_v<idx_t, int>, "METIS must be built with 32-bit idx_t");

std::vector<int> order_metis(const BlockPattern& pattern) {
  const Graph& g = pattern.graph();
  std::vector<int> pivots(g.n);
  std::iota(pivots.begin(), pivots.end(), 0);
  // METIS cannot partition a graph without edges; any order is then perfect.
  if (g.n < 2 || g.num_edges() == 0) return pivots;
  idx_t n = g.n;
  std::vector<idx_t> xadj(g.ptr.begin(), g.ptr.end()), adjncy(g.adj.begin(), g.adj.end());
  std::vector<idx_t> vwgt = pattern.block_sizes(), iperm(g.n);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  // perm[k] is the vertex eliminated k-th ("row k of A' is row perm[k] of A").
  const int status = METIS_NodeND(&n, xadj.data(), adjncy.data(), vwgt.data(), options,
                                  pivots.data(), iperm.data());
  if (status != METIS_OK) throw std::runtime_error("METIS_NodeND failed with status " + std::to_string(status));
  return pivots;
}

}  // namespace ldlpgs
