// postorder(): an equivalent pivot sequence. Checked against the definition, not against a
// second implementation: the same block costs as the given order (the elimination game played
// on both, eliminate()), every subtree a run of consecutive pivots ending at its root, and the
// heaviest child right before its parent; on mechanisms and test matrices, with every ordering
// and with a random order.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/ordering/postorder.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs {
namespace {

void expect_postorder(const BlockPattern& p, const std::vector<int>& pivots) {
  const Elimination before = eliminate(p, pivots);
  const std::vector<int> post = postorder(p, pivots, before);
  std::vector<int> sorted = post;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> all(p.num_blocks());
  std::iota(all.begin(), all.end(), 0);
  ASSERT_EQ(sorted, all) << "not a permutation of the blocks";

  // The same fill, nnz(L) and flops.
  const Elimination after = eliminate(p, post);
  const BlockCosts a = block_costs(p, pivots, before), b = block_costs(p, post, after);
  EXPECT_EQ(a.fill_edges, b.fill_edges);
  EXPECT_EQ(a.nnz_L, b.nnz_L);
  EXPECT_EQ(a.flops, b.flops);

  // In the new order: each pivot's subtree is the run of `size[k]` pivots ending at k (every
  // pivot in it has its parent inside the run or is k), and k's last child is k - 1, its heaviest.
  const int np = after.num_pivots();
  std::vector<int> parent(np), size(np, 1), weight(np);
  for (int k = 0; k < np; ++k) {
    const auto column = after.column(k);
    parent[k] = column.empty() ? -1 : column.front();
    weight[k] = p.block(post[k]).size;
    for (int j : column) weight[k] += p.block(post[j]).size;
  }
  for (int k = 0; k < np; ++k)
    if (parent[k] >= 0) size[parent[k]] += size[k];
  int heaviest_missed = 0;
  for (int k = 0; k < np; ++k) {
    for (int i = k - size[k] + 1; i < k; ++i) {
      ASSERT_GE(i, 0);
      ASSERT_TRUE(parent[i] > i && parent[i] <= k) << "pivot " << i << " in the run of " << k << " but not below it";
    }
    int most = -1;
    for (int i = k - size[k] + 1; i < k; ++i)
      if (parent[i] == k) most = std::max(most, weight[i]);
    if (most >= 0 && weight[k - 1] != most) ++heaviest_missed;
  }
  EXPECT_EQ(heaviest_missed, 0) << "parents whose last child is not a heaviest one";
}

TEST(Postorder, IsAnEquivalentPostorderOnMechanisms) {
  for (std::string_view family : family_names()) {
    SCOPED_TRACE(family);
    const BlockPattern p = constraint_graph(make_family(family, 120, 5));
    for (const OrderingInfo& info : orderings()) {
      if (info.level != Level::block) continue;
      SCOPED_TRACE(info.name);
      expect_postorder(p, info.fn(p));
    }
    std::vector<int> shuffled(p.num_blocks());
    std::iota(shuffled.begin(), shuffled.end(), 0);
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
    expect_postorder(p, shuffled);
  }
}

TEST(Postorder, IsAnEquivalentPostorderOnTestMatrices) {
  for (const char* f : {"bcsstk01.mtx", "494_bus.mtx", "dwt_878.mtx", "bcsstk13.mtx"}) {
    SCOPED_TRACE(f);
    const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES) + "/" + f);
    for (const BlockPattern& p : {BlockPattern::from_scalar(a, partition_auto(a)), BlockPattern::unit(a)})
      for (const char* name : {"natural", "meca", "amd", "metis"}) expect_postorder(p, find_ordering(name).fn(p));
  }
}

// What a caller passes is checked in every build: a permutation of the blocks, and its elimination.
TEST(PostorderBadInput, PivotsThatAreNotAPermutationOrAnotherElimination) {
  const BlockPattern p = constraint_graph(make_family("chain", 10));
  const std::vector<int> pivots = find_ordering("natural").fn(p);
  const Elimination e = eliminate(p, pivots);
  std::vector<int> repeated = pivots;
  repeated[1] = repeated[0];
  EXPECT_THROW(postorder(p, repeated, e), ArgumentError);
  EXPECT_THROW(postorder(p, std::vector<int>(pivots.begin(), pivots.end() - 1), e), ArgumentError);
  const BlockPattern bigger = constraint_graph(make_family("chain", 12));
  const std::vector<int> more = find_ordering("natural").fn(bigger);
  EXPECT_THROW(postorder(bigger, more, e), ArgumentError);
}

// A postorder is its own postorder.
TEST(Postorder, IsIdempotent) {
  const BlockPattern p = constraint_graph(make_family("tree", 300, 3));
  const std::vector<int> pivots = find_ordering("amd").fn(p);
  const std::vector<int> once = postorder(p, pivots, eliminate(p, pivots));
  EXPECT_EQ(postorder(p, once, eliminate(p, once)), once);
}

}  // namespace
}  // namespace ldlpgs
