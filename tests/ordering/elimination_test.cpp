// eliminate() derives the block structure of L from the elimination tree and row subtrees;
// EliminationGraph plays the game itself, edge by edge. They must agree, column by column,
// fill flags included, for every ordering on mechanisms and test matrices.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs {
namespace {

// The game played literally: before eliminating pivot k, its live neighbours are column k of L.
Elimination play(const BlockPattern& p, std::span<const int> pivots) {
  const int nb = p.num_blocks();
  std::vector<int> position(nb);
  for (int k = 0; k < nb; ++k) position[pivots[k]] = k;
  EliminationGraph g(p.graph());
  Elimination e;
  e.ptr.push_back(0);
  int64_t created = 0;
  for (int k = 0; k < nb; ++k) {
    std::vector<int> col;
    for (int u : g.neighbors(pivots[k])) col.push_back(position[u]);
    std::sort(col.begin(), col.end());
    for (int q : col) {
      auto orig = p.neighbors(pivots[k]);
      e.edges.push_back(q);
      e.fill.push_back(!std::binary_search(orig.begin(), orig.end(), pivots[q]));
    }
    e.ptr.push_back(static_cast<int>(e.edges.size()));
    created += g.eliminate(pivots[k]);
  }
  for (uint8_t f : e.fill) e.fill_edges += f;
  EXPECT_EQ(created, e.fill_edges) << "the game's own count of new edges";
  return e;
}

void expect_same(const Elimination& a, const Elimination& b) {
  EXPECT_EQ(a.ptr, b.ptr);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.fill, b.fill);
  EXPECT_EQ(a.fill_edges, b.fill_edges);
}

TEST(Elimination, RowSubtreesEqualTheGameOnMechanisms) {
  for (std::string_view family : family_names()) {
    const BlockPattern p = constraint_graph(make_family(family, 120, 5));
    for (const OrderingInfo& info : orderings()) {
      if (info.level != Level::block) continue;
      const std::vector<int> pivots = info.fn(p);
      expect_same(eliminate(p, pivots), play(p, pivots));
    }
    // A random order makes plenty of fill.
    std::vector<int> shuffled(p.num_blocks());
    std::iota(shuffled.begin(), shuffled.end(), 0);
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(11));
    expect_same(eliminate(p, shuffled), play(p, shuffled));
  }
}

TEST(Elimination, RowSubtreesEqualTheGameOnTestMatrices) {
  for (const char* f : {"can___24.mtx", "bcsstk01.mtx", "494_bus.mtx", "dwt_878.mtx"}) {
    const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES) + "/" + f);
    for (const BlockPattern& p : {BlockPattern::from_scalar(a, partition_auto(a)), BlockPattern::unit(a)}) {
      for (const char* name : {"natural", "mda", "amd", "metis"}) {
        const std::vector<int> pivots = find_ordering(name).fn(p);
        expect_same(eliminate(p, pivots), play(p, pivots));
      }
    }
  }
}

TEST(Elimination, EdgesAreLaterPivotsInOrder) {
  const BlockPattern p = constraint_graph(make_family("grid", 200));
  const Elimination e = eliminate(p, order_amd(p));
  for (int k = 0; k < e.num_pivots(); ++k) {
    auto col = e.column(k);
    EXPECT_TRUE(std::is_sorted(col.begin(), col.end()));
    EXPECT_TRUE(std::adjacent_find(col.begin(), col.end()) == col.end());
    for (int q : col) EXPECT_GT(q, k);
  }
}

TEST(EliminationGraph, FillIfEliminatedMatchesEliminate) {
  // What fill_if_eliminated predicts is what eliminate then creates.
  const BlockPattern p = constraint_graph(make_family("ladder", 60));
  EliminationGraph g(p.graph());
  const std::vector<int> ones(p.num_blocks(), 1);
  for (int v : order_natural(p)) {
    const int64_t predicted = g.fill_if_eliminated(v, ones);
    std::vector<std::pair<int, int>> created;
    EXPECT_EQ(g.eliminate(v, &created), predicted);
    EXPECT_EQ(static_cast<int64_t>(created.size()), predicted);
  }
}

}  // namespace
}  // namespace ldlpgs
