#include <numeric>

#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

// The blocks in their given order: the baseline. It creates no fill on a chain numbered from
// one end, and can fill badly on trees, loops and grids.
std::vector<int> order_natural(const BlockPattern& pattern) {
  std::vector<int> pivots(pattern.num_blocks());
  std::iota(pivots.begin(), pivots.end(), 0);
  return pivots;
}

}  // namespace ldlpgs
