// The certificate against brute force: on random block graphs of up to 8 blocks (sizes 1-6),
// every one of the n! orders is played with eliminate() and costed with block_costs(), and the
// certified optimum must equal the least of them, a lower bound must never exceed it, and
// `best` must be no worse than any of its candidates. Then the case: the talk's tracked
// vehicle, 38,300 block flops, certified.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "ldlpgs/ordering/certify.h"
#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"

namespace ldlpgs {
namespace {

double cost(const BlockPattern& p, std::span<const int> pivots) {
  return block_costs(p, pivots, eliminate(p, pivots)).flops;
}

double brute_force_minimum(const BlockPattern& p) {
  std::vector<int> order(p.num_blocks());
  std::iota(order.begin(), order.end(), 0);
  double least = cost(p, order);
  while (std::next_permutation(order.begin(), order.end())) least = std::min(least, cost(p, order));
  return least;
}

// Random graphs of 1 to 8 blocks, block sizes 1 to 6: two in three with edge probability 0.2
// to 0.7 (sparse ones have simplicial blocks, dense ones not); one in three two cycles of 4 or
// 5 glued on a block or an edge, with a random chord or none, which peeling leaves whole and
// only a clique separator splits.
std::vector<BlockPattern> random_patterns(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<BlockPattern> out;
  for (int i = 0; i < count; ++i) {
    int n = 1 + static_cast<int>(rng() % 8);
    std::vector<std::pair<int, int>> edges;
    if (i % 3 == 2) {
      const int a = 4 + static_cast<int>(rng() % 2), shared = 1 + static_cast<int>(rng() % 2);
      const int b = std::min(4 + static_cast<int>(rng() % 2), 8 - a + shared);
      n = a + b - shared;
      for (int k = 0; k < a; ++k) edges.emplace_back(k, (k + 1) % a);  // cycle 0 .. a-1
      // cycle b: the shared blocks a-1 (and 0), then a .. n-1
      std::vector<int> cycle = shared == 2 ? std::vector<int>{0, a - 1} : std::vector<int>{a - 1};
      for (int k = a; k < n; ++k) cycle.push_back(k);
      for (size_t k = shared - 1; k < cycle.size(); ++k) edges.emplace_back(cycle[k], cycle[(k + 1) % cycle.size()]);
      if (rng() % 2) edges.emplace_back(static_cast<int>(rng() % n), static_cast<int>(rng() % n));
      std::erase_if(edges, [](auto e) { return e.first == e.second; });
      for (auto& e : edges)
        if (e.first > e.second) std::swap(e.first, e.second);
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    } else {
      const double density = 0.2 + 0.5 * std::uniform_real_distribution<double>(0, 1)(rng);
      for (int u = 0; u < n; ++u)
        for (int v = u + 1; v < n; ++v)
          if (std::uniform_real_distribution<double>(0, 1)(rng) < density) edges.emplace_back(u, v);
    }
    std::vector<int> sizes(n);
    for (int& s : sizes) s = 1 + static_cast<int>(rng() % 6);
    out.emplace_back(sizes, graph_from_edges(n, edges));
  }
  return out;
}

TEST(Certify, EqualsTheBruteForceMinimumOfBlockFlops) {
  int with_atoms = 0, with_peeling = 0, with_search = 0, chordal = 0;
  for (const BlockPattern& p : random_patterns(150, 15)) {
    const double least = brute_force_minimum(p);
    const Choice best = choose_best(p);
    for (std::span<const int> known : {std::span<const int>(), std::span<const int>(best.pivots)}) {
      const BlockFlopsCertificate c = certify_block_flops(p, 60, known);
      ASSERT_TRUE(c.optimal_proved) << p.num_blocks() << " blocks";
      EXPECT_EQ(c.lower_bound, least) << p.num_blocks() << " blocks, " << p.num_edges() << " edges";
      // and the order it proves with reaches it
      ASSERT_EQ(std::ssize(c.pivots), p.num_blocks());
      check_permutation(c.pivots, p.num_blocks(), "certificate");
      EXPECT_EQ(cost(p, c.pivots), least) << p.num_blocks() << " blocks";
      with_atoms += c.atoms > 1;
      with_peeling += c.peeled > 0 && !c.chordal;
      with_search += c.states > 0;
      chordal += c.chordal;
    }
  }
  // the cases exercise every part of the proof
  EXPECT_GT(with_atoms, 10);
  EXPECT_GT(with_peeling, 10);
  EXPECT_GT(with_search, 10);
  EXPECT_GT(chordal, 10);
}

TEST(Certify, ZeroFillBoundNeverExceedsTheMinimumAndIsItOnChordalGraphs) {
  for (const BlockPattern& p : random_patterns(150, 16)) {
    const double least = brute_force_minimum(p);
    const double bound = zero_fill_block_flops(p);
    EXPECT_LE(bound, least);
    if (certify_block_flops(p, 60).chordal) {
      EXPECT_EQ(bound, least);
    }
  }
}

TEST(Certify, OutOfTimeGivesALowerBound) {
  // A 6 x 6 grid of 6-row blocks: not chordal, no clique separator, too many connected sets
  // for no time at all.
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      if (i + 1 < 6) edges.emplace_back(6 * i + j, 6 * (i + 1) + j);
      if (j + 1 < 6) edges.emplace_back(6 * i + j, 6 * i + j + 1);
    }
  const BlockPattern p(std::vector<int>(36, 6), graph_from_edges(36, edges));
  const BlockFlopsCertificate c = certify_block_flops(p, 0);
  EXPECT_FALSE(c.optimal_proved);
  EXPECT_TRUE(c.pivots.empty());
  EXPECT_EQ(c.lower_bound, zero_fill_block_flops(p));
  EXPECT_LE(c.lower_bound, cost(p, choose_best(p).pivots));
}

TEST(Certify, RefusesPivotsThatAreNotAnOrder) {
  const BlockPattern p = constraint_graph(make_family("loop", 6));
  EXPECT_THROW(certify_block_flops(p, 1, std::vector<int>{0, 1}), ArgumentError);
}

TEST(Best, IsNeverWorseThanItsCandidates) {
  std::vector<BlockPattern> patterns = random_patterns(100, 17);
  for (std::string_view family : family_names())
    for (int size : {12, 40}) patterns.push_back(constraint_graph(make_family(family, size, 3)));
  for (const BlockPattern& p : patterns) {
    const Choice best = choose_best(p);
    const double flops = cost(p, best.pivots);
    EXPECT_EQ(flops, cost(p, find_ordering(best.chosen).fn(p))) << best.chosen;
    for (std::string_view name : kBestCandidates) EXPECT_LE(flops, cost(p, find_ordering(name).fn(p))) << name;
  }
}

TEST(Best, ComputeOrderingReportsTheWinner) {
  const BlockPattern p = constraint_graph(make_family("chain", 10));
  const SymmetricCsc a = p.expand();
  const Ordering o = compute_ordering(find_ordering("best"), p, a);
  EXPECT_EQ(o.name, "best");
  EXPECT_NE(std::find(kBestCandidates.begin(), kBestCandidates.end(), o.chosen), kBestCandidates.end());
  EXPECT_EQ(compute_ordering(find_ordering("amd"), p, a).chosen, "amd");
}

// meca 41,400 block flops and 38 fill edges on the tracked vehicle, the optimum
// (meca-w, amd) 38,300 and 34.
TEST(Certify, TrackedVehicleIsSolvedAt38300) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("tracked-vehicle", &m));
  const BlockPattern p = m.constraint_graph(true);
  ASSERT_EQ(p.num_blocks(), 40);
  EXPECT_EQ(cost(p, order_meca(p)), 41400);
  const Choice best = choose_best(p);
  EXPECT_EQ(cost(p, best.pivots), 38300);
  EXPECT_EQ(best.chosen, "meca-w");  // the first candidate at 38,300 (amd ties with it)
  const BlockFlopsCertificate c = certify_block_flops(p, 60, best.pivots);
  EXPECT_TRUE(c.optimal_proved);
  EXPECT_EQ(c.lower_bound, 38300);
  // and without the known order to prune with
  EXPECT_EQ(certify_block_flops(p, 60).lower_bound, 38300);
}

// Two components searched one after the other, with a known order that visits both: the
// optimum and its order against brute force (a block of the second component was once looked
// up by its index in the first, -1, out of bounds).
TEST(Certify, TwoComponentsWithAKnownOrder) {
  std::vector<std::pair<int, int>> edges;
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < 4; ++i) edges.emplace_back(4 * c + i, 4 * c + (i + 1) % 4);
  const BlockPattern p(std::vector<int>{1, 3, 2, 6, 4, 1, 5, 2}, graph_from_edges(8, edges));
  const std::vector<int> known = {7, 0, 6, 1, 5, 2, 4, 3};  // alternates between the components
  const BlockFlopsCertificate c = certify_block_flops(p, 60, known);
  ASSERT_TRUE(c.optimal_proved);
  EXPECT_EQ(c.lower_bound, brute_force_minimum(p));
  EXPECT_EQ(cost(p, c.pivots), c.lower_bound);
}

// A closed loop of 40 constraints: the search proves an optimum below every ordering's, and its
// order, played as the game, costs exactly that (the brute force above checks the same on
// graphs small enough to enumerate).
TEST(Certify, ReturnsAnOptimalOrderNoHeuristicFinds) {
  const BlockPattern p = constraint_graph(make_family("loop", 40));
  const Choice best = choose_best(p);
  const BlockFlopsCertificate c = certify_block_flops(p, 60, best.pivots);
  ASSERT_TRUE(c.optimal_proved);
  ASSERT_EQ(std::ssize(c.pivots), p.num_blocks());
  check_permutation(c.pivots, p.num_blocks(), "certificate");
  EXPECT_EQ(cost(p, c.pivots), c.lower_bound);
  EXPECT_LT(c.lower_bound, cost(p, best.pivots));
  const std::optional<Ordering> o = certificate_ordering(p, c, cost(p, best.pivots));
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(o->name, "optimal");
  EXPECT_EQ(block_costs(p, o->pivots, o->elimination).flops, c.lower_bound);
  EXPECT_FALSE(certificate_ordering(p, c, c.lower_bound).has_value());  // reached already: no row
}

}  // namespace
}  // namespace ldlpgs
