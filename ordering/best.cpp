// best: the cheap block orderings, each run once, and the one with the fewest block flops
// (metrics.h, the cost the block LDL^T pays). No heuristic wins everywhere: on the talk's
// tracked vehicle meca-w and amd find the optimum and meca does not; on the shattered
// multi-wheeled vehicle mda and amd lose to meca-w. The cost is the sum of the candidates' times plus one eliminate() per distinct
// order (O(blocks of L)); measured in papers/orderings.md ("The best order, with a certificate").
//
// Ties (equal block flops) go to the fewer block fill edges, then to the earlier candidate in
// kBestCandidates, which lists meca first: where meca is optimal, best is meca, as the former
// default was.
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

Choice choose_best(const BlockPattern& pattern) {
  Choice best;
  BlockCosts best_costs;
  // Candidates often agree (on the 1000-arm star meca, mda and mda-w give one order, meca-w and
  // amd another): an order seen before is not played again
  // (papers/orderings.md, "The best order, with a certificate").
  std::vector<std::pair<std::vector<int>, BlockCosts>> seen;  // (size candidates)
  for (std::string_view name : kBestCandidates) {
    const OrderingInfo& info = find_ordering(name);
    std::vector<int> pivots = info.fn(pattern);
    const auto same = std::find_if(seen.begin(), seen.end(), [&](const auto& x) { return x.first == pivots; });
    const BlockCosts c = same != seen.end() ? same->second : block_costs(pattern, pivots, eliminate(pattern, pivots));
    if (same == seen.end()) seen.emplace_back(pivots, c);
    if (best.chosen.empty() || c.flops < best_costs.flops ||
        (c.flops == best_costs.flops && c.fill_edges < best_costs.fill_edges)) {
      best = {std::move(pivots), std::string(name)};
      best_costs = c;
    }
  }
  return best;
}

std::vector<int> order_best(const BlockPattern& pattern) { return choose_best(pattern).pivots; }

}  // namespace ldlpgs
