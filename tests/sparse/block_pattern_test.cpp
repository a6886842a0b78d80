// Block patterns: from_scalar against a brute-force block adjacency on every test matrix (auto
// and uniform partitions), unit() against the scalar graph, block_of_row against the prefix sums,
// and expand(): exactly the dense-block structure, values -1 / 1 + degree, positive definite by a
// dense Cholesky, and from_scalar(expand()) giving the same block graph back.
#include "ldlpgs/sparse/block_pattern.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

using Edge = std::pair<int, int>;  // (smaller, larger)
using Sizes = std::vector<int>;

using testing::test_matrices;

// The two partitions the tests use on a matrix: auto (blocks of identical rows) and uniform 3.
std::vector<std::pair<std::string, Sizes>> partitions(const SymmetricCsc& a) {
  return {{"auto", partition_auto(a)}, {"uniform 3", partition_uniform(a.n, 3)}};
}

// Brute force: the block of each row, by walking the sizes.
std::vector<int> block_of(const Sizes& sizes) {
  std::vector<int> b;
  for (int k = 0; k < static_cast<int>(sizes.size()); ++k) b.insert(b.end(), sizes[k], k);
  return b;
}

// Brute force: the pairs of distinct blocks holding a stored entry.
std::set<Edge> block_edges(const SymmetricCsc& a, const Sizes& sizes) {
  const std::vector<int> b = block_of(sizes);
  std::set<Edge> edges;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int x = b[a.row_idx[p]], y = b[j];
      if (x != y) edges.insert({std::min(x, y), std::max(x, y)});
    }
  }
  return edges;
}

// The edges of g, checking on the way what Graph promises: lists ascending, in range, no self
// loops, every edge stored in both directions.
std::set<Edge> edges_of(const Graph& g) {
  std::set<std::pair<int, int>> directed;
  for (int v = 0; v < g.n; ++v) {
    const auto nb = g.neighbors(v);
    EXPECT_TRUE(std::is_sorted(nb.begin(), nb.end())) << "vertex " << v;
    EXPECT_EQ(std::adjacent_find(nb.begin(), nb.end()), nb.end()) << "vertex " << v;
    for (int u : nb) {
      EXPECT_NE(u, v) << "self loop";
      EXPECT_TRUE(u >= 0 && u < g.n) << u;
      directed.insert({v, u});
    }
  }
  std::set<Edge> edges;
  for (auto [v, u] : directed) {
    EXPECT_TRUE(directed.count({u, v})) << v << "-" << u << " stored one way only";
    edges.insert({std::min(u, v), std::max(u, v)});
  }
  return edges;
}

// The blocks of p are the given sizes at their prefix-sum positions.
void expect_blocks(const BlockPattern& p, const Sizes& sizes) {
  ASSERT_EQ(p.num_blocks(), static_cast<int>(sizes.size()));
  EXPECT_EQ(p.block_sizes(), sizes);
  int position = 0;
  for (int b = 0; b < p.num_blocks(); ++b) {
    EXPECT_EQ(p.block(b).size, sizes[b]) << "block " << b;
    EXPECT_EQ(p.block(b).position, position) << "block " << b;
    EXPECT_EQ(p.blocks()[b].position, position);
    position += sizes[b];
  }
  EXPECT_EQ(p.num_rows(), position);
  EXPECT_EQ(p.graph().n, p.num_blocks());
}

// --- from_scalar ----------------------------------------------------------------------------

TEST(FromScalar, HandBuilt) {
  // 6 x 6 in blocks {0,1} {2} {3,4,5}. Entries (1,0) and (4,3) lie inside blocks and make no
  // edge; (2,0) joins blocks 0-1, (5,1) joins 0-2; blocks 1 and 2 are not coupled.
  std::vector<Triplet> t = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {5, 1, 1}, {4, 3, 1}, {3, 3, 1}};
  const Sizes sizes = {2, 1, 3};
  const BlockPattern p = BlockPattern::from_scalar(csc_from_triplets(6, t), sizes);
  expect_blocks(p, sizes);
  EXPECT_EQ(edges_of(p.graph()), (std::set<Edge>{{0, 1}, {0, 2}}));
  EXPECT_EQ(p.num_edges(), 2);
  // An explicit zero at (5,2) is a stored entry: it couples blocks 1 and 2.
  t.push_back({5, 2, 0.0});
  const BlockPattern q = BlockPattern::from_scalar(csc_from_triplets(6, t), sizes);
  EXPECT_EQ(edges_of(q.graph()), (std::set<Edge>{{0, 1}, {0, 2}, {1, 2}}));
}

TEST(FromScalar, OneBlockHasNoEdges) {
  const SymmetricCsc a = test_matrices().front().a;
  const BlockPattern p = BlockPattern::from_scalar(a, Sizes{a.n});
  expect_blocks(p, Sizes{a.n});
  EXPECT_EQ(p.num_edges(), 0);
}

TEST(FromScalar, MatchesBruteForceOnEveryTestMatrix) {
  ASSERT_GE(test_matrices().size(), 11u);
  for (const auto& [name, a] : test_matrices()) {
    for (const auto& [how, sizes] : partitions(a)) {
      SCOPED_TRACE(name + ", " + how);
      const BlockPattern p = BlockPattern::from_scalar(a, sizes);
      expect_blocks(p, sizes);
      const std::set<Edge> expected = block_edges(a, sizes);
      EXPECT_EQ(edges_of(p.graph()), expected);
      EXPECT_EQ(p.num_edges(), static_cast<int64_t>(expected.size()));
      for (int b = 0; b < p.num_blocks(); ++b) {
        ASSERT_EQ(p.neighbors(b).size(), static_cast<size_t>(p.graph().degree(b)));
      }
    }
  }
}

// --- unit -----------------------------------------------------------------------------------

TEST(Unit, IsTheScalarGraphOnEveryTestMatrix) {
  for (const auto& [name, a] : test_matrices()) {
    SCOPED_TRACE(name);
    const BlockPattern p = BlockPattern::unit(a);
    expect_blocks(p, Sizes(a.n, 1));
    // With blocks of one row, block adjacency is entry adjacency.
    EXPECT_EQ(edges_of(p.graph()), block_edges(a, Sizes(a.n, 1)));
  }
}

// --- block_of_row ---------------------------------------------------------------------------

TEST(BlockOfRow, MatchesPrefixSums) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    Sizes sizes(1 + rng() % 30);
    for (int& s : sizes) s = 1 + static_cast<int>(rng() % 7);
    const BlockPattern p(sizes, graph_from_edges(static_cast<int>(sizes.size()), {}));
    expect_blocks(p, sizes);
    EXPECT_EQ(p.block_of_row(), block_of(sizes)) << "trial " << trial;
  }
  EXPECT_EQ(BlockPattern(Sizes{2, 1, 3}, graph_from_edges(3, {})).block_of_row(),
            (std::vector<int>{0, 0, 1, 2, 2, 2}));
}

TEST(BlockOfRow, Empty) {
  const BlockPattern p;
  EXPECT_EQ(p.num_blocks(), 0);
  EXPECT_EQ(p.num_rows(), 0);
  EXPECT_TRUE(p.block_of_row().empty());
}

// --- expand ---------------------------------------------------------------------------------

// Checks expand() against the definition, built from the block sizes and edges alone: an entry
// (r, c) is stored iff r and c are in the same block or in adjacent blocks; off-diagonal values
// are -1, the diagonal is 1 + the number of off-diagonal entries in its row; the matrix is
// positive definite (dense LLT, for small n); and its block graph under the same sizes is p's.
void expect_expand(const BlockPattern& p) {
  const SymmetricCsc e = p.expand();
  const int n = p.num_rows();
  ASSERT_EQ(e.n, n);
  ASSERT_EQ(static_cast<int>(e.col_ptr.size()), n + 1);
  ASSERT_EQ(e.col_ptr[0], 0);
  ASSERT_EQ(e.row_idx.size(), static_cast<size_t>(e.nnz()));
  ASSERT_EQ(e.values.size(), static_cast<size_t>(e.nnz()));

  const Sizes sizes = p.block_sizes();
  const std::vector<int> b = block_of(sizes);
  const int nb = p.num_blocks();
  std::vector<char> adjacent(static_cast<size_t>(nb) * nb, 0);
  for (auto [x, y] : edges_of(p.graph())) adjacent[x * nb + y] = adjacent[y * nb + x] = 1;
  auto coupled = [&](int r, int c) { return b[r] == b[c] || adjacent[b[r] * nb + b[c]]; };
  // The expected lower structure, column by column, and the degree of every row.
  std::vector<std::vector<int>> rows(n);
  std::vector<int> degree(n, 0);
  for (int c = 0; c < n; ++c) {
    for (int r = c; r < n; ++r) {
      if (!coupled(r, c)) continue;
      rows[c].push_back(r);
      if (r != c) ++degree[r], ++degree[c];
    }
  }
  for (int c = 0; c < n; ++c) {
    std::vector<int> got(e.row_idx.begin() + e.col_ptr[c], e.row_idx.begin() + e.col_ptr[c + 1]);
    ASSERT_EQ(got, rows[c]) << "column " << c;
    for (int p = e.col_ptr[c]; p < e.col_ptr[c + 1]; ++p) {
      const double expected = e.row_idx[p] == c ? 1.0 + degree[c] : -1.0;
      ASSERT_EQ(e.values[p], expected) << "entry (" << e.row_idx[p] << "," << c << ")";
    }
  }
  if (n <= 1000) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c) {
      for (int p = e.col_ptr[c]; p < e.col_ptr[c + 1]; ++p) {
        d(e.row_idx[p], c) = d(c, e.row_idx[p]) = e.values[p];
      }
    }
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(d).info(), Eigen::Success) << "not positive definite";
  }
  const BlockPattern back = BlockPattern::from_scalar(e, sizes);
  EXPECT_EQ(back.block_sizes(), sizes);
  EXPECT_EQ(back.graph().ptr, p.graph().ptr);
  EXPECT_EQ(back.graph().adj, p.graph().adj);
}

TEST(Expand, HandBuilt) {
  // Blocks {0,1} {2} {3,4,5}, edge 0-2 only. Row degrees: rows 0,1: 1 in-block + 3 = 4;
  // row 2: 0 (isolated block); rows 3,4,5: 2 in-block + 2 = 4.
  const BlockPattern p(Sizes{2, 1, 3}, graph_from_edges(3, std::vector<Edge>{{0, 2}}));
  const SymmetricCsc e = p.expand();
  EXPECT_EQ(e.col_ptr, (std::vector<int>{0, 5, 9, 10, 13, 15, 16}));
  EXPECT_EQ(e.row_idx, (std::vector<int>{0, 1, 3, 4, 5, 1, 3, 4, 5, 2, 3, 4, 5, 4, 5, 5}));
  EXPECT_EQ(e.values, (std::vector<double>{5, -1, -1, -1, -1, 5, -1, -1, -1, 1, 5, -1, -1, 5,
                                           -1, 5}));
  expect_expand(p);
}

TEST(Expand, CheckerCanFail) {
  // A pattern whose expand() is compared against another pattern's definition must be refused:
  // same sizes, one edge more.
  const BlockPattern p(Sizes{2, 1, 3}, graph_from_edges(3, std::vector<Edge>{{0, 2}}));
  const BlockPattern q(Sizes{2, 1, 3}, graph_from_edges(3, std::vector<Edge>{{0, 2}, {1, 2}}));
  EXPECT_NE(p.expand().row_idx, q.expand().row_idx);
  EXPECT_NE(BlockPattern::from_scalar(p.expand(), Sizes{2, 1, 3}).graph().adj, q.graph().adj);
}

TEST(Expand, RandomPatterns) {
  // Random graphs with the joint sizes of the talk (1, 3, 4, 5, 6), from empty to dense.
  std::mt19937 rng(99);
  const int kSizes[] = {1, 3, 4, 5, 6};
  for (int trial = 0; trial < 40; ++trial) {
    const int nb = 1 + static_cast<int>(rng() % 25);
    Sizes sizes(nb);
    for (int& s : sizes) s = kSizes[rng() % 5];
    std::vector<Edge> edges;
    const int count = static_cast<int>(rng() % (nb * nb / 2 + 1));
    for (int k = 0; k < count; ++k) {
      const int u = static_cast<int>(rng() % nb), v = static_cast<int>(rng() % nb);
      if (u != v) edges.emplace_back(u, v);
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_expand(BlockPattern(sizes, graph_from_edges(nb, edges)));
  }
}

TEST(Expand, EveryTestMatrixPattern) {
  for (const auto& [name, a] : test_matrices()) {
    for (const auto& [how, sizes] : partitions(a)) {
      SCOPED_TRACE(name + ", " + how);
      expect_expand(BlockPattern::from_scalar(a, sizes));
    }
  }
}

}  // namespace
}  // namespace ldlpgs
