// SuiteSparse AMD (approximate minimum degree on a quotient graph) on the block graph, with its
// default controls (dense rows postponed, aggressive absorption). AMD does not see block sizes.
#include <amd.h>

#include <stdexcept>

#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

std::vector<int> order_amd(const BlockPattern& pattern) {
  const Graph& g = pattern.graph();
  std::vector<int> pivots(g.n);
  if (g.n == 0) return pivots;
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  // The graph has sorted lists, no diagonal, both triangles: AMD takes it as it is. AMD refuses
  // a null row-index array, which an edgeless graph's empty vector may give.
  const int none = 0;
  const int status = amd_order(g.n, g.ptr.data(), g.adj.empty() ? &none : g.adj.data(), pivots.data(), control, info);
  if (status != AMD_OK) throw std::runtime_error("amd_order failed with status " + std::to_string(status));
  return pivots;
}

}  // namespace ldlpgs
