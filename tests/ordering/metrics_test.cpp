// scalar_counts and block_costs against a brute-force symbolic factorization: a dense boolean
// matrix eliminated column by column (the definition of L's pattern, with no tree tricks).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs {
namespace {

// Column counts of L (diagonal included) for P A P^T, by dense symbolic elimination.
std::vector<int64_t> dense_column_counts(const Graph& g, std::span<const int> perm) {
  const int n = g.n;
  std::vector<int> pinv(n);
  for (int k = 0; k < n; ++k) pinv[perm[k]] = k;
  std::vector<uint8_t> m(static_cast<size_t>(n) * n, 0);
  for (int v = 0; v < n; ++v) {
    for (int u : g.neighbors(v)) m[pinv[v] * n + pinv[u]] = 1;
  }
  std::vector<int64_t> counts(n, 1);
  for (int k = 0; k < n; ++k) {
    std::vector<int> below;
    for (int i = k + 1; i < n; ++i) {
      if (m[i * n + k]) below.push_back(i);
    }
    counts[k] += static_cast<int64_t>(below.size());
    for (int i : below) {
      for (int j : below) m[i * n + j] = 1;
    }
  }
  return counts;
}

void expect_counts_match(const Graph& g, std::span<const int> perm) {
  const std::vector<int64_t> counts = dense_column_counts(g, perm);
  int64_t lnz = 0;
  double fl = 0;
  for (int64_t c : counts) {
    lnz += c;
    fl += static_cast<double>(c * c);
  }
  const ScalarCounts s = scalar_counts(g, perm);
  EXPECT_EQ(s.nnz_L, lnz);
  EXPECT_EQ(s.flops, fl);
}

TEST(ScalarCounts, EqualDenseSymbolicElimination) {
  std::mt19937 rng(3);
  for (const char* f : {"LFAT5.mtx", "can___24.mtx", "bcsstk01.mtx", "pts5ldd03.mtx", "494_bus.mtx"}) {
    const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES) + "/" + f);
    const Graph g = graph_of(a);
    std::vector<int> perm(a.n);
    std::iota(perm.begin(), perm.end(), 0);
    expect_counts_match(g, perm);
    std::shuffle(perm.begin(), perm.end(), rng);
    expect_counts_match(g, perm);
    expect_counts_match(g, compute_ordering(find_ordering("amd-scalar"), BlockPattern::unit(a), a).perm);
  }
}

TEST(ScalarCounts, FlopsAreTheLdlCount) {
  // CHOLMOD's fl = sum of squared column counts = sum c_j (c_j + 2) + n, c_j strictly below.
  const SymmetricCsc a = read_matrix_market(std::string(LDLPGS_MATRICES "/bcsstk01.mtx"));
  const Graph g = graph_of(a);
  std::vector<int> perm(a.n);
  std::iota(perm.begin(), perm.end(), 0);
  const std::vector<int64_t> counts = dense_column_counts(g, perm);
  double ldl = a.n;
  for (int64_t c : counts) ldl += static_cast<double>((c - 1) * (c + 1));
  EXPECT_EQ(scalar_counts(g, perm).flops, ldl);
}

TEST(BlockCosts, EqualDenseSymbolicEliminationOfDenseBlocks) {
  // The block factor's costs are the scalar costs of the matrix with every block dense, and
  // its nnz is at least that of the scalar factor.
  for (std::string_view family : family_names()) {
    const BlockPattern p = constraint_graph(make_family(family, 30, 9));
    const SymmetricCsc dense = p.expand();
    for (const char* name : {"natural", "mda", "meca-w", "metis"}) {
      const Ordering o = compute_ordering(find_ordering(name), p, dense);
      const BlockCosts b = block_costs(p, o.pivots, o.elimination);
      const std::vector<int64_t> counts = dense_column_counts(graph_of(dense), o.perm);
      int64_t lnz = 0;
      double fl = 0;
      for (int64_t c : counts) {
        lnz += c;
        fl += static_cast<double>(c * c);
      }
      EXPECT_EQ(b.nnz_L, lnz) << family << " " << name;
      EXPECT_EQ(b.flops, fl) << family << " " << name;
      EXPECT_EQ(b.fill_edges, o.elimination.fill_edges);
    }
  }
}

TEST(BlockCosts, SinglePivotIsTheTalksCostModel) {
  // One pivot of size d above a block of size h: LDL(N) + L = E N^-1 + S -= E L^T, then the
  // last block's own LDL.
  for (int d = 1; d <= 6; ++d) {
    for (int h = 1; h <= 6; ++h) {
      const BlockPattern p(std::vector<int>{d, h}, graph_from_edges(2, std::vector<std::pair<int, int>>{{0, 1}}));
      const Elimination e = eliminate(p, std::vector<int>{0, 1});
      const BlockCosts b = block_costs(p, std::vector<int>{0, 1}, e);
      const double ldl_d = d * (d + 1) * (2 * d + 1) / 6.0, ldl_h = h * (h + 1) * (2 * h + 1) / 6.0;
      EXPECT_EQ(b.flops, ldl_d + h * d * (d + 1) + d * h * h + ldl_h);
      EXPECT_EQ(b.nnz_L, d * (d + 1) / 2 + h * d + h * (h + 1) / 2);
    }
  }
}

}  // namespace
}  // namespace ldlpgs
