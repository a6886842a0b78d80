#include "ldlpgs/ordering/postorder.h"

#include <algorithm>
#include <string>
#include <utility>

#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

std::vector<int> postorder(const BlockPattern& pattern, std::span<const int> pivots, const Elimination& e) {
  const int np = e.num_pivots();
  check_permutation(pivots, pattern.num_blocks(), "postorder (pivots)");
  if (np != pattern.num_blocks())
    throw ArgumentError("postorder: an elimination of " + std::to_string(np) + " pivots for " +
                        std::to_string(pattern.num_blocks()) + " blocks");
  // parent[k] (np: a root, child of a virtual node np) and weight[k].
  std::vector<int> parent(np), weight(np);
  for (int k = 0; k < np; ++k) {
    const auto column = e.column(k);
    parent[k] = column.empty() ? np : column.front();
    weight[k] = pattern.block(pivots[k]).size;
    for (int j : column) weight[k] += pattern.block(pivots[j]).size;
  }
  // The children of each node v, [ptr[v], ptr[v + 1]) of `children`, in pivot order, then
  // lightest first; the roots stay in pivot order.
  std::vector<int> ptr(np + 3, 0), children(np);
  for (int k = 0; k < np; ++k) ++ptr[parent[k] + 2];
  for (int v = 0; v <= np; ++v) ptr[v + 2] += ptr[v + 1];
  for (int k = 0; k < np; ++k) children[ptr[parent[k] + 1]++] = k;
  for (int v = 0; v < np; ++v)
    std::stable_sort(children.begin() + ptr[v], children.begin() + ptr[v + 1],
                     [&](int a, int b) { return weight[a] < weight[b]; });
  // Depth first from the virtual root; a node is emitted after its children.
  std::vector<int> order;
  order.reserve(np);
  std::vector<std::pair<int, int>> stack;  // (node, its next child's index); never reallocates
  stack.reserve(np + 1);
  stack.emplace_back(np, ptr[np]);
  while (!stack.empty()) {
    auto& [v, next] = stack.back();
    if (next < ptr[v + 1]) {
      const int child = children[next++];
      stack.emplace_back(child, ptr[child]);
    } else {
      if (v < np) order.push_back(pivots[v]);
      stack.pop_back();
    }
  }
  return order;
}

}  // namespace ldlpgs
