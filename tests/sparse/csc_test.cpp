// Scalar storage: csc_from_triplets against a dense matrix accumulated straight from the same
// triplets (hand-built cases and random ones), graph_from_edges against a boolean adjacency
// matrix, and graph_of against the off-diagonal entries of every test matrix.
#include "ldlpgs/sparse/csc.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/matrix_market.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

namespace fs = std::filesystem;
using Position = std::pair<int, int>;  // (row, col), row >= col

using testing::expect_valid;
using testing::stored;

// a as a dense lower triangle, read from the arrays.
Eigen::MatrixXd dense_lower(const SymmetricCsc& a) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(a.n, a.n);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) d(a.row_idx[p], j) = a.values[p];
  }
  return d;
}

// The reference: every triplet added into the lower triangle of a dense matrix at
// (max(i,j), min(i,j)), and the set of positions that received at least one triplet.
struct Reference {
  Eigen::MatrixXd lower;
  std::set<Position> positions;
};
Reference reference(int n, const std::vector<Triplet>& t) {
  Reference r{Eigen::MatrixXd::Zero(n, n), {}};
  for (const Triplet& e : t) {
    const int i = std::max(e.row, e.col), j = std::min(e.row, e.col);
    r.lower(i, j) += e.value;
    r.positions.insert({i, j});
  }
  return r;
}

void expect_matches_reference(int n, const std::vector<Triplet>& t) {
  const SymmetricCsc a = csc_from_triplets(n, t);
  ASSERT_EQ(a.n, n);
  expect_valid(a);
  const Reference r = reference(n, t);
  // Exactly the positions given (explicit zeros and sums to zero included), nothing else.
  EXPECT_EQ(stored(a), r.positions);
  // Values are integers or dyadic fractions below, so sums are exact in any order.
  EXPECT_EQ(dense_lower(a), r.lower);
}

// --- csc_from_triplets ----------------------------------------------------------------------

TEST(CscFromTriplets, HandBuilt) {
  // 5 x 5: (0,2) is given as an upper entry and also as (2,0): both land on (2,0) and add up;
  // (3,3) is given three times; column 1 has no diagonal; column 4 is empty; the input is in no
  // particular order.
  const std::vector<Triplet> t = {{3, 3, 1.0},  {0, 2, 0.5},  {4, 1, -2.0}, {2, 0, 0.25},
                                  {3, 3, 2.0},  {0, 0, 4.0},  {1, 3, 7.0},  {3, 3, -0.5},
                                  {2, 1, 1.5},  {1, 0, -1.0}, {2, 2, 8.0}};
  const SymmetricCsc a = csc_from_triplets(5, t);
  expect_valid(a);
  // By hand: column 0: rows 0, 1, 2 = 4, -1, 0.75; column 1: rows 2, 3, 4 = 1.5, 7, -2;
  // column 2: row 2 = 8; column 3: row 3 = 2.5; column 4: empty.
  EXPECT_EQ(a.col_ptr, (std::vector<int>{0, 3, 6, 7, 8, 8}));
  EXPECT_EQ(a.row_idx, (std::vector<int>{0, 1, 2, 2, 3, 4, 2, 3}));
  EXPECT_EQ(a.values, (std::vector<double>{4, -1, 0.75, 1.5, 7, -2, 8, 2.5}));
  expect_matches_reference(5, t);
}

TEST(CscFromTriplets, ExplicitZerosAndCancellingDuplicatesStayStored) {
  // Structure is what was given, not what is nonzero (CHOLMOD keeps them too): the orderings
  // count explicit zeros as edges.
  const std::vector<Triplet> t = {{1, 0, 0.0}, {2, 1, 3.0}, {1, 2, -3.0}, {2, 2, 1.0}};
  const SymmetricCsc a = csc_from_triplets(3, t);
  EXPECT_EQ(stored(a), (std::set<Position>{{1, 0}, {2, 1}, {2, 2}}));
  expect_matches_reference(3, t);
}

TEST(CscFromTriplets, EmptyInputs) {
  const SymmetricCsc none = csc_from_triplets(0, {});
  EXPECT_EQ(none.n, 0);
  EXPECT_EQ(none.col_ptr, std::vector<int>{0});
  EXPECT_EQ(none.nnz(), 0);
  const SymmetricCsc zero = csc_from_triplets(4, {});
  expect_valid(zero);
  EXPECT_EQ(zero.col_ptr, std::vector<int>(5, 0));
}

TEST(CscFromTriplets, RandomAgainstDense) {
  // Random sizes, entries from both triangles, many duplicates (few distinct positions for many
  // triplets), integer values so that every sum is exact.
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 25);
    const int count = static_cast<int>(rng() % (3 * n * n / 2 + 2));
    std::vector<Triplet> t;
    for (int k = 0; k < count; ++k) {
      t.push_back({static_cast<int>(rng() % n), static_cast<int>(rng() % n),
                   static_cast<double>(static_cast<int>(rng() % 41) - 20)});
    }
    SCOPED_TRACE("trial " + std::to_string(trial) + ", n " + std::to_string(n));
    expect_matches_reference(n, t);
  }
}

TEST(CscFromTriplets, CheckerCanFail) {
  // The reference must tell a transposed or unsummed result apart from the right one.
  const std::vector<Triplet> t = {{0, 1, 2.0}, {1, 0, 3.0}};
  const Reference r = reference(2, t);
  EXPECT_EQ(r.lower(1, 0), 5.0);
  EXPECT_EQ(r.lower(0, 1), 0.0);
  EXPECT_EQ(r.positions, (std::set<Position>{{1, 0}}));
}

// --- graph_from_edges -----------------------------------------------------------------------

// Brute force: a boolean adjacency matrix from the edge list.
std::vector<std::vector<bool>> adjacency(int n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<std::vector<bool>> m(n, std::vector<bool>(n, false));
  for (auto [u, v] : edges) m[u][v] = m[v][u] = true;
  return m;
}

// g against the boolean matrix: neighbour lists ascending, exactly the adjacent vertices, in both
// directions, no self loops, and the counts that follow.
void expect_graph(const Graph& g, const std::vector<std::vector<bool>>& m) {
  const int n = static_cast<int>(m.size());
  ASSERT_EQ(g.n, n);
  ASSERT_EQ(static_cast<int>(g.ptr.size()), n + 1);
  ASSERT_EQ(g.ptr[0], 0);
  ASSERT_EQ(static_cast<int>(g.adj.size()), g.ptr[n]);
  int64_t twice_edges = 0;
  for (int v = 0; v < n; ++v) {
    std::vector<int> expected;
    for (int u = 0; u < n; ++u) {
      if (m[v][u]) expected.push_back(u);
    }
    const auto nb = g.neighbors(v);
    EXPECT_EQ(std::vector<int>(nb.begin(), nb.end()), expected) << "vertex " << v;
    EXPECT_EQ(g.degree(v), static_cast<int>(expected.size()));
    twice_edges += static_cast<int64_t>(expected.size());
  }
  EXPECT_EQ(g.num_edges(), twice_edges / 2);
}

TEST(GraphFromEdges, HandBuilt) {
  // (0,1) three times in both orders, (3,2) twice; vertex 4 isolated.
  const std::vector<std::pair<int, int>> edges = {{0, 1}, {1, 0}, {3, 2}, {0, 1},
                                                  {2, 3}, {3, 0}, {1, 3}};
  const Graph g = graph_from_edges(5, edges);
  EXPECT_EQ(g.ptr, (std::vector<int>{0, 2, 4, 5, 8, 8}));
  EXPECT_EQ(g.adj, (std::vector<int>{1, 3, 0, 3, 3, 0, 1, 2}));
  EXPECT_EQ(g.num_edges(), 4);
  expect_graph(g, adjacency(5, edges));
}

TEST(GraphFromEdges, Empty) {
  expect_graph(graph_from_edges(0, {}), {});
  const Graph g = graph_from_edges(3, {});
  expect_graph(g, adjacency(3, {}));
  EXPECT_EQ(g.num_edges(), 0);
}

TEST(GraphFromEdges, RandomAgainstAdjacencyMatrix) {
  std::mt19937 rng(777);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + static_cast<int>(rng() % 40);
    const int count = static_cast<int>(rng() % (n * n));
    std::vector<std::pair<int, int>> edges;
    while (static_cast<int>(edges.size()) < count) {
      const int u = static_cast<int>(rng() % n), v = static_cast<int>(rng() % n);
      if (u != v) edges.emplace_back(u, v);
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_graph(graph_from_edges(n, edges), adjacency(n, edges));
  }
}

// --- graph_of -------------------------------------------------------------------------------

// Brute force: an edge for every stored off-diagonal entry, read from the arrays.
std::vector<std::vector<bool>> adjacency_of(const SymmetricCsc& a) {
  std::vector<std::pair<int, int>> edges;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      if (a.row_idx[p] != j) edges.emplace_back(a.row_idx[p], j);
    }
  }
  return adjacency(a.n, edges);
}

TEST(GraphOf, HandBuiltExplicitZeroIsAnEdgeDiagonalIsNot) {
  const SymmetricCsc a =
      csc_from_triplets(4, std::vector<Triplet>{{0, 0, 1}, {1, 0, 0.0}, {3, 1, 2}, {3, 3, 1}});
  const Graph g = graph_of(a);
  EXPECT_EQ(g.ptr, (std::vector<int>{0, 1, 3, 3, 4}));
  EXPECT_EQ(g.adj, (std::vector<int>{1, 0, 3, 1}));
}

TEST(GraphOf, DiagonalMatrixHasNoEdges) {
  const SymmetricCsc a = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {1, 1, 1}, {2, 2, 1}});
  const Graph g = graph_of(a);
  EXPECT_EQ(g.num_edges(), 0);
  expect_graph(g, adjacency(3, {}));
}

TEST(GraphOf, MatchesBruteForceOnEveryTestMatrix) {
  int checked = 0;
  for (const auto& file : fs::directory_iterator(LDLPGS_MATRICES)) {
    if (file.path().extension() != ".mtx" || file.path().filename() == "Pd.mtx") continue;
    SCOPED_TRACE(file.path().filename().string());
    const SymmetricCsc a = read_matrix_market(file.path().string());
    if (a.n > 1500) continue;  // the boolean matrix is n^2; bcsstk13 adds nothing new
    expect_graph(graph_of(a), adjacency_of(a));
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

TEST(SymmetricMultiply, NormAndBackwardErrorAgainstDense) {
  for (const auto& m : testing::test_matrices()) {
    if (m.a.n > 1500) continue;
    SCOPED_TRACE(m.name);
    const Eigen::MatrixXd d = testing::dense(m.a);
    const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(m.a.n, -1, 2);
    Eigen::VectorXd y(m.a.n);
    auto span = [](const Eigen::VectorXd& v) { return std::span<const double>(v.data(), v.size()); };
    symmetric_multiply(m.a, span(x), std::span<double>(y.data(), y.size()));
    EXPECT_LT((y - d * x).lpNorm<Eigen::Infinity>(), 1e-13 * (d * x).lpNorm<Eigen::Infinity>());
    const double norm = d.cwiseAbs().rowwise().sum().maxCoeff();
    EXPECT_DOUBLE_EQ(norm_inf(m.a), norm);
    // A residual of delta in every row, large against rounding in A x.
    const double delta = 1e-6 * (d * x).lpNorm<Eigen::Infinity>();
    const Eigen::VectorXd b = d * x + Eigen::VectorXd::Constant(m.a.n, delta);
    const double expected = delta / (norm * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
    EXPECT_NEAR(backward_error(m.a, span(x), span(b)), expected, 1e-6 * expected);
  }
}

}  // namespace
}  // namespace ldlpgs
