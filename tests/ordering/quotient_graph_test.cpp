// The quotient-graph orderings (mda, mda-w, meca, meca-w) against independent references: a
// dense adjacency matrix replaying the game (the exact external degree, recounted from scratch
// after every step), the exact explicit-graph orderings (fill and flops), and the zero-fill
// orders that cliques and chordal graphs admit.
#include "ldlpgs/ordering/quotient_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs {
namespace {

// A random graph of n blocks of sizes 1..6, each pair joined with probability `density`.
BlockPattern random_pattern(int n, double density, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coin(0, 1);
  std::uniform_int_distribution<int> size(1, 6);
  std::vector<std::pair<int, int>> edges;
  for (int u = 0; u < n; ++u) {
    for (int v = u + 1; v < n; ++v) {
      if (coin(rng) < density) edges.emplace_back(u, v);
    }
  }
  std::vector<int> sizes(n);
  for (int& s : sizes) s = size(rng);
  return BlockPattern(sizes, graph_from_edges(n, edges));
}

BlockPattern clique(int n, int size) {
  std::vector<std::pair<int, int>> edges;
  for (int u = 0; u < n; ++u) {
    for (int v = u + 1; v < n; ++v) edges.emplace_back(u, v);
  }
  return BlockPattern(std::vector<int>(n, size), graph_from_edges(n, edges));
}

const QuotientOptions kForms[] = {
    {QuotientScore::degree, false, TieBreak::highest_index},
    {QuotientScore::degree, true, TieBreak::highest_index},
    {QuotientScore::fill, false, TieBreak::highest_index},
    {QuotientScore::fill, true, TieBreak::least_degree},
};

bool is_permutation_of_n(std::vector<int> p, int n) {
  std::sort(p.begin(), p.end());
  std::vector<int> iota(n);
  std::iota(iota.begin(), iota.end(), 0);
  return p == iota;
}

TEST(QuotientGraph, RandomGraphsGiveAPermutation) {
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    const BlockPattern p = random_pattern(5 + seed % 30, 0.05 + 0.02 * (seed % 10), seed);
    for (const QuotientOptions& o : kForms) EXPECT_TRUE(is_permutation_of_n(quotient_order(p, o), p.num_blocks())) << seed;
  }
}

// The workspace compacted whenever an element does not fit (no room for elements beyond the
// graph's own entries) gives the same orders as the default room, where compactions are rare.
TEST(QuotientGraph, CompactingTheWorkspaceLeavesTheOrderAsItWas) {
  std::vector<BlockPattern> patterns;
  for (uint32_t seed = 1; seed <= 10; ++seed) patterns.push_back(random_pattern(20 + 4 * seed, 0.1, seed));
  for (const char* family : {"grid", "tree", "star", "heavy"}) patterns.push_back(constraint_graph(make_family(family, 300, 2)));
  const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES "/bcsstk01.mtx"));
  patterns.push_back(BlockPattern::from_scalar(a, partition_auto(a)));
  for (const BlockPattern& p : patterns)
    for (QuotientOptions o : kForms) {
      const std::vector<int> roomy = quotient_order(p, o);
      o.element_room = 0;
      EXPECT_EQ(quotient_order(p, o), roomy) << p.num_blocks() << " blocks, score " << static_cast<int>(o.score);
    }
}

// After each step, the degree the quotient graph keeps for every block next to the pivot is at
// least the block's degree in the elimination graph, recounted on a dense adjacency matrix.
TEST(QuotientGraph, ApproximateDegreeBoundsTheExactDegree) {
  int64_t checked = 0, exact = 0;
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    const BlockPattern p = random_pattern(8 + seed % 25, 0.08 + 0.03 * (seed % 8), seed);
    const int n = p.num_blocks();
    for (const QuotientOptions& o : kForms) {
      std::vector<QuotientStep> trace;
      quotient_order(p, o, &trace);
      std::vector<uint8_t> adj(n * n, 0), alive(n, 1);
      for (int v = 0; v < n; ++v) {
        for (int u : p.neighbors(v)) adj[v * n + u] = 1;
      }
      for (const QuotientStep& step : trace) {
        for (int v : step.eliminated) {
          std::vector<int> nb;
          for (int u = 0; u < n; ++u) {
            if (alive[u] && u != v && adj[v * n + u]) nb.push_back(u);
          }
          for (int a : nb) {
            for (int b : nb) {
              if (a != b) adj[a * n + b] = 1;
            }
          }
          alive[v] = 0;
        }
        for (auto [b, d] : step.degrees) {
          int64_t degree = 0;
          for (int u = 0; u < n; ++u) degree += alive[u] && u != b && adj[b * n + u];
          ASSERT_TRUE(alive[b]);
          ASSERT_GE(d, degree) << "seed " << seed << " block " << b;
          ++checked;
          exact += d == degree;
        }
      }
    }
  }
  EXPECT_GT(checked, 1000);
  // The bound is AMD's: exact most of the time on such small graphs (94% of these checks).
  EXPECT_GT(static_cast<double>(exact) / checked, 0.8);
}

TEST(QuotientGraph, CliqueIsOneSupervariableWithoutFill) {
  const BlockPattern p = clique(200, 3);
  for (const QuotientOptions& o : kForms) {
    std::vector<QuotientStep> trace;
    const std::vector<int> pivots = quotient_order(p, o, &trace);
    EXPECT_EQ(eliminate(p, pivots).fill_edges, 0);
    // One block alone, then the other 199 found indistinguishable and eliminated together.
    EXPECT_EQ(trace.size(), 2u);
  }
}

TEST(QuotientGraph, ChordalGraphsGetZeroFillFromMeca) {
  // Trees of bodies give chordal block graphs (cliques glued along single blocks); the approximate
  // fill must still find their perfect elimination orders. The natural order of a tree does not.
  for (const char* family : {"chain", "tree", "star"}) {
    for (int size : {20, 60, 300, 3000}) {
      const BlockPattern p = constraint_graph(make_family(family, size, 5));
      for (const char* name : {"meca", "meca-w"})
        EXPECT_EQ(eliminate(p, find_ordering(name).fn(p)).fill_edges, 0) << family << size << " " << name;
    }
  }
}

// The quotient orderings by name, with the explicit-graph orderings they stand in for.
constexpr std::pair<const char*, const char*> kNamedForms[] = {
    {"mda", "mda-exact"}, {"mda-w", "mda-w-exact"}, {"meca", "meca-exact"}, {"meca-w", "meca-w-exact"}};

// Block flops of `fast`'s order of p over `exact`'s.
double flop_ratio(const BlockPattern& p, const char* fast, const char* exact) {
  const std::vector<int> q = find_ordering(fast).fn(p), e = find_ordering(exact).fn(p);
  return block_costs(p, q, eliminate(p, q)).flops / block_costs(p, e, eliminate(p, e)).flops;
}

// Fill and flops of the quotient orderings against the exact ones, on the test matrices and the
// families at talk sizes and beyond: the geometric mean within 3%, no case worse than 25%
// (measured: papers/orderings.md).
TEST(QuotientGraph, FillAndFlopsCloseToTheExactOrderings) {
  std::vector<BlockPattern> patterns;
  for (const char* f : {"can___24.mtx", "bcsstk01.mtx", "LFAT5.mtx", "494_bus.mtx", "dwt_878.mtx", "jagmesh7.mtx"}) {
    const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES) + "/" + f);
    patterns.push_back(BlockPattern::from_scalar(a, partition_auto(a)));
  }
  for (std::string_view family : family_names()) {
    for (int size : {20, 40, 60, 300}) patterns.push_back(constraint_graph(make_family(family, size, 2)));
  }
  for (auto [fast, exact] : kNamedForms) {
    double log_sum = 0, worst = 0;
    for (const BlockPattern& p : patterns) {
      const double ratio = flop_ratio(p, fast, exact);
      log_sum += std::log(ratio);
      worst = std::max(worst, ratio);
    }
    EXPECT_LT(std::exp(log_sum / patterns.size()), 1.03) << fast;
    EXPECT_LT(worst, 1.25) << fast;
  }
}

// Grids are where the quotient forms had drifted from the exact game, each for its own reason:
// late in the elimination meca's blocks have degree bounds past the exact count's 16 blocks but
// short lists (a few supervariables), now counted exactly too (quotient_graph.cpp, the second
// tier); and mda-w's tie rule read the highest index of a supervariable where the exact game
// takes its heaviest block first. Before: meca 2.6 %, 4.7 % and 16 % above meca-exact on
// grid-1000, -3000 and -5000, meca-w 3.1-3.9 %, mda-w 6 % below and 13 % above on grid-3000
// and -5000 (papers/orderings.md). Now all four within 2 % either way.
TEST(QuotientGraph, OrderingsFollowTheExactGameOnGrids) {
  for (int size : {1000, 3000, 5000}) {
    const BlockPattern p = constraint_graph(make_family("grid", size));
    for (auto [fast, exact] : kNamedForms)
      EXPECT_NEAR(flop_ratio(p, fast, exact), 1.0, 0.02) << "grid-" << size << " " << fast;
  }
}

}  // namespace
}  // namespace ldlpgs
