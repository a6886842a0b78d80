// The CHOLMOD adapter: cholmod_view read back by CHOLMOD itself (check, norms and a product
// against dense Eigen); from_cholmod for stype -1, 0 and +1 copies made by CHOLMOD, for unpacked
// columns with slack and for entries in the triangle the stype says to ignore; cholmod_read's
// errors; and cholmod_counts against a dense symbolic elimination (the reference for the
// orderings' metrics) under identity and random permutations.
#include "sparse/cholmod_adapter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "sparse/block_pattern.h"
#include "sparse/error.h"
#include "sparse/families.h"
#include "sparse/matrix_market.h"
#include "tests/temp_files.h"
#include "tests/test_matrices.h"

namespace ldlpgs {
namespace {

const std::string kMatrices = LDLPGS_MATRICES;

using testing::dense;
using testing::expect_equal;
using testing::Named;
using testing::test_matrices;

SymmetricCsc read(const std::string& name) { return read_matrix_market(kMatrices + "/" + name); }

// Owns a cholmod_sparse that CHOLMOD allocated.
struct Owned {
  cholmod_sparse* s;
  Cholmod& cm;
  ~Owned() { cholmod_free_sparse(&s, cm.common()); }
};

// --- cholmod_view ---------------------------------------------------------------------------

TEST(CholmodView, PointsIntoTheMatrix) {
  const SymmetricCsc a = read("LFAT5.mtx");
  const cholmod_sparse v = cholmod_view(a);
  EXPECT_EQ(v.p, a.col_ptr.data());
  EXPECT_EQ(v.i, a.row_idx.data());
  EXPECT_EQ(v.x, a.values.data());
  EXPECT_EQ(v.nrow, 14u);
  EXPECT_EQ(v.ncol, 14u);
  EXPECT_EQ(v.stype, -1);
}

TEST(CholmodView, CholmodReadsItBackOnEveryTestMatrix) {
  // CHOLMOD's own checker accepts the view, and CHOLMOD's 1-norm, inf-norm and product A*X
  // (it expands the symmetric lower triangle itself) match the dense full matrix.
  Cholmod cm;
  ASSERT_GE(test_matrices().size(), 11u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const auto& [name, a] : test_matrices()) {
    SCOPED_TRACE(name);
    cholmod_sparse v = cholmod_view(a);
    EXPECT_EQ(cholmod_check_sparse(&v, cm.common()), 1);
    const Eigen::MatrixXd d = dense(a);
    const double norm1 = d.cwiseAbs().colwise().sum().maxCoeff();
    EXPECT_NEAR(cholmod_norm_sparse(&v, 1, cm.common()), norm1, 1e-13 * norm1);
    EXPECT_NEAR(cholmod_norm_sparse(&v, 0, cm.common()), norm1, 1e-13 * norm1);  // symmetric

    const int k = 2;
    cholmod_dense* x = cholmod_allocate_dense(a.n, k, a.n, CHOLMOD_REAL, cm.common());
    cholmod_dense* y = cholmod_zeros(a.n, k, CHOLMOD_REAL, cm.common());
    ASSERT_TRUE(x && y);
    Eigen::Map<Eigen::MatrixXd> xm(static_cast<double*>(x->x), a.n, k);
    for (int c = 0; c < k; ++c) {
      for (int r = 0; r < a.n; ++r) xm(r, c) = uniform(rng);
    }
    double alpha[2] = {1, 0}, beta[2] = {0, 0};
    ASSERT_EQ(cholmod_sdmult(&v, 0, alpha, beta, x, y, cm.common()), 1);
    const Eigen::MatrixXd expected = d * xm;
    const Eigen::Map<Eigen::MatrixXd> ym(static_cast<double*>(y->x), a.n, k);
    EXPECT_LE((ym - expected).cwiseAbs().maxCoeff(), 1e-13 * norm1)
        << "CHOLMOD's A*X differs from the dense product";
    cholmod_free_dense(&x, cm.common());
    cholmod_free_dense(&y, cm.common());
  }
}

// --- from_cholmod ---------------------------------------------------------------------------

TEST(FromCholmod, EveryStypeOnEveryTestMatrix) {
  // CHOLMOD makes each storage from the view: a plain copy (stype -1), both triangles
  // (stype 0), the upper triangle by copy and by transpose (stype +1). All must give a back.
  Cholmod cm;
  for (const auto& [name, a] : test_matrices()) {
    SCOPED_TRACE(name);
    cholmod_sparse v = cholmod_view(a);
    const Owned lower{cholmod_copy_sparse(&v, cm.common()), cm};
    const Owned both{cholmod_copy(&v, 0, 1, cm.common()), cm};
    const Owned upper{cholmod_copy(&v, 1, 1, cm.common()), cm};
    const Owned transposed{cholmod_transpose(&v, 1, cm.common()), cm};
    ASSERT_TRUE(lower.s && both.s && upper.s && transposed.s);
    ASSERT_EQ(lower.s->stype, -1);
    ASSERT_EQ(both.s->stype, 0);
    ASSERT_EQ(upper.s->stype, 1);
    ASSERT_EQ(transposed.s->stype, 1);
    // Sanity of the inputs: the unsymmetric copy holds both triangles.
    int64_t diagonal = 0;
    for (int j = 0; j < a.n; ++j) {
      for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) diagonal += a.row_idx[p] == j;
    }
    EXPECT_EQ(cholmod_nnz(both.s, cm.common()), 2 * a.nnz() - diagonal);
    expect_equal(from_cholmod(*lower.s, cm), a);
    expect_equal(from_cholmod(*both.s, cm), a);
    expect_equal(from_cholmod(*upper.s, cm), a);
    expect_equal(from_cholmod(*transposed.s, cm), a);
  }
}

// A 3 x 3 cholmod_sparse over caller-owned arrays (nz empty means packed).
cholmod_sparse raw(std::vector<int>& p, std::vector<int>& nz, std::vector<int>& i,
                   std::vector<double>& x, int stype) {
  cholmod_sparse s{};
  s.nrow = s.ncol = 3;
  s.nzmax = i.size();
  s.p = p.data();
  s.nz = nz.empty() ? nullptr : nz.data();
  s.i = i.data();
  s.x = x.data();
  s.stype = stype;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 0;
  s.packed = nz.empty();
  return s;
}

// The matrix the hand-built cases below encode: [1 2 0; 2 3 4; 0 4 5].
SymmetricCsc expected_3x3() {
  return csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {1, 0, 2}, {1, 1, 3}, {2, 1, 4},
                                                   {2, 2, 5}});
}

TEST(FromCholmod, UnpackedColumnsSlackIsNotRead) {
  // Each column has room for 3 entries but holds nz[j]; the slack holds plausible lower
  // entries (value 99) that must not be copied. Column 1 is unsorted.
  std::vector<int> p = {0, 3, 6, 9}, nz = {2, 2, 1};
  std::vector<int> i = {0, 1, 2, 2, 1, 2, 2, 0, 0};
  std::vector<double> x = {1, 2, 99, 4, 3, 99, 5, 99, 99};
  Cholmod cm;
  cholmod_sparse s = raw(p, nz, i, x, -1);
  ASSERT_EQ(cholmod_check_sparse(&s, cm.common()), 1);
  expect_equal(from_cholmod(s, cm), expected_3x3());
}

TEST(FromCholmod, EntriesOutsideTheStypeTriangleAreIgnored) {
  Cholmod cm;
  {
    // stype -1 also holding upper entries (99): CHOLMOD ignores them, so must we.
    std::vector<int> p = {0, 2, 5, 8}, nz;
    std::vector<int> i = {0, 1, 0, 1, 2, 0, 1, 2};
    std::vector<double> x = {1, 2, 99, 3, 4, 99, 99, 5};
    cholmod_sparse s = raw(p, nz, i, x, -1);
    expect_equal(from_cholmod(s, cm), expected_3x3());
    // CHOLMOD agrees: its own copy to full storage drops them too.
    const Owned full{cholmod_copy(&s, 0, 1, cm.common()), cm};
    EXPECT_EQ(cholmod_norm_sparse(full.s, 1, cm.common()), 9.0);  // column 1: 2 + 3 + 4
  }
  {
    // stype +1 holding lower entries (99): only the upper triangle counts, transposed.
    std::vector<int> p = {0, 2, 4, 6}, nz;
    std::vector<int> i = {0, 2, 0, 1, 2, 1};
    std::vector<double> x = {1, 99, 2, 3, 5, 4};
    cholmod_sparse s = raw(p, nz, i, x, 1);
    expect_equal(from_cholmod(s, cm), expected_3x3());
  }
}

TEST(FromCholmod, UnsymmetricStorageGivesItsLowerTriangle) {
  // stype 0 with an upper triangle that disagrees (7, 8): the header promises the lower one.
  std::vector<int> p = {0, 2, 5, 7}, nz;
  std::vector<int> i = {0, 1, 0, 1, 2, 1, 2};
  std::vector<double> x = {1, 2, 7, 3, 4, 8, 5};
  Cholmod cm;
  cholmod_sparse s = raw(p, nz, i, x, 0);
  expect_equal(from_cholmod(s, cm), expected_3x3());
}

// --- cholmod_read -----------------------------------------------------------------------------

TEST(CholmodRead, Errors) {
  Cholmod cm;
  const std::string missing = ::testing::TempDir() + "ldlpgs_no_such_file.mtx";
  try {
    cholmod_read(missing, cm);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), missing + ": cannot open file");
  }
  const std::string rectangular = testing::temp_file(
      "rect.mtx", "%%MatrixMarket matrix coordinate real general\n2 3 2\n1 1 1\n2 3 1\n");
  try {
    cholmod_read(rectangular, cm);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), rectangular + ": not a real square matrix");
  }
  cm.common()->print = 0;  // CHOLMOD would print its own complaint about the junk file
  EXPECT_THROW(cholmod_read(testing::temp_file("junk.mtx", "not a matrix\n"), cm), InputError);
}

TEST(CholmodRead, SmallFile) {
  Cholmod cm;
  const std::string path = testing::temp_file(
      "small.mtx",
      "%%MatrixMarket matrix coordinate real symmetric\n3 3 5\n1 1 1\n2 1 2\n2 2 3\n3 2 4\n3 3 5\n");
  expect_equal(cholmod_read(path, cm), expected_3x3());
}

// --- cholmod_counts -------------------------------------------------------------------------

// The reference: eliminate a boolean dense copy of P A P^T in order. Column k of L holds the
// diagonal and every row i > k still coupled to k; eliminating k couples all of those rows
// pairwise (fill). lnz = sum of column counts, fl = sum of their squares (CHOLMOD's rule).
CholmodCounts symbolic_counts(const SymmetricCsc& a, const std::vector<int>& perm) {
  const int n = a.n;
  std::vector<int> inverse(n);
  for (int k = 0; k < n; ++k) inverse[perm[k]] = k;
  std::vector<std::vector<char>> m(n, std::vector<char>(n, 0));
  for (int j = 0; j < n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int r = inverse[a.row_idx[p]], c = inverse[j];
      m[r][c] = m[c][r] = 1;
    }
  }
  double lnz = 0, fl = 0;
  for (int k = 0; k < n; ++k) {
    std::vector<int> below;
    for (int i = k + 1; i < n; ++i) {
      if (m[i][k]) below.push_back(i);
    }
    for (int x : below) {
      for (int y : below) m[x][y] = 1;
    }
    const double count = 1.0 + static_cast<double>(below.size());
    lnz += count;
    fl += count * count;
  }
  return {lnz, fl};
}

TEST(CholmodCounts, ArrowByHand) {
  // Arrow: row 0 coupled to all of 1..4. Hub first: everything fills, counts 5,4,3,2,1 ->
  // lnz 15, fl 55. Hub last: columns 1,1,... no fill, counts 2,2,2,2,1 -> lnz 9, fl 17.
  std::vector<Triplet> t;
  for (int i = 0; i < 5; ++i) t.push_back({i, i, 10});
  for (int i = 1; i < 5; ++i) t.push_back({i, 0, -1});
  const SymmetricCsc a = csc_from_triplets(5, t);
  Cholmod cm;
  const CholmodCounts first = cholmod_counts(a, std::vector<int>{0, 1, 2, 3, 4}, cm);
  EXPECT_EQ(first.lnz, 15);
  EXPECT_EQ(first.fl, 55);
  const CholmodCounts last = cholmod_counts(a, std::vector<int>{1, 2, 3, 4, 0}, cm);
  EXPECT_EQ(last.lnz, 9);
  EXPECT_EQ(last.fl, 17);
  // The reference agrees with the hand count, so it can tell the two orders apart.
  EXPECT_EQ(symbolic_counts(a, {0, 1, 2, 3, 4}).lnz, 15);
  EXPECT_EQ(symbolic_counts(a, {1, 2, 3, 4, 0}).fl, 17);
}

TEST(CholmodCounts, MatchesDenseSymbolicElimination) {
  std::vector<Named> cases;
  for (const char* name : {"LFAT5.mtx", "can___24.mtx", "bcsstk01.mtx"}) cases.push_back({name, read(name)});
  // Expanded mechanisms: dense blocks of 1..6 rows, every family.
  for (std::string_view family : family_names()) {
    cases.push_back({"expanded " + std::string(family),
                     constraint_graph(make_family(family, 20, 4)).expand()});
  }
  Cholmod cm;
  std::mt19937 rng(2024);
  for (const auto& [name, a] : cases) {
    std::vector<std::vector<int>> perms(1, std::vector<int>(a.n));
    std::iota(perms[0].begin(), perms[0].end(), 0);
    for (int k = 0; k < 3; ++k) {
      perms.push_back(perms[0]);
      std::shuffle(perms.back().begin(), perms.back().end(), rng);
    }
    for (size_t k = 0; k < perms.size(); ++k) {
      SCOPED_TRACE(name + (k == 0 ? ", identity" : ", random permutation " + std::to_string(k)));
      const CholmodCounts expected = symbolic_counts(a, perms[k]);
      const CholmodCounts got = cholmod_counts(a, perms[k], cm);
      EXPECT_EQ(got.lnz, expected.lnz);
      EXPECT_EQ(got.fl, expected.fl);
    }
  }
}

TEST(CholmodCounts, IgnoresAndRestoresCommonSettings) {
  // Settings that would change the analysis if used (supernodal, postordering, several
  // orderings tried) must not change the counts, and must be left as they were.
  const SymmetricCsc a = read("can___24.mtx");
  std::vector<int> perm(a.n);
  std::iota(perm.rbegin(), perm.rend(), 0);
  Cholmod cm;
  cholmod_common* c = cm.common();
  const CholmodCounts plain = cholmod_counts(a, perm, cm);
  c->supernodal = CHOLMOD_SUPERNODAL;
  c->postorder = true;
  c->nmethods = 3;
  c->method[0].ordering = CHOLMOD_AMD;
  const CholmodCounts again = cholmod_counts(a, perm, cm);
  EXPECT_EQ(again.lnz, plain.lnz);
  EXPECT_EQ(again.fl, plain.fl);
  EXPECT_EQ(again.lnz, symbolic_counts(a, perm).lnz);
  EXPECT_EQ(c->supernodal, CHOLMOD_SUPERNODAL);
  EXPECT_EQ(c->postorder, 1);
  EXPECT_EQ(c->nmethods, 3);
  EXPECT_EQ(c->method[0].ordering, CHOLMOD_AMD);
}

}  // namespace
}  // namespace ldlpgs
