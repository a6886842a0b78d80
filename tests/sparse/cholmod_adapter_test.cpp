// The CHOLMOD adapter: cholmod_view read back by CHOLMOD itself (check, norms and a product
// against dense Eigen); from_cholmod for stype -1, 0 and +1 copies made by CHOLMOD, for unpacked
// columns with slack and for entries in the triangle the stype says to ignore; cholmod_read's
// errors; cholmod_counts against a dense symbolic elimination (the reference for the
// orderings' metrics) under identity and random permutations; and cholmod_ldl (the reference for
// factor/): L D L^T against P A P^T and x against A x = b on every test matrix, and CHOLMOD's
// verdicts on negative and zero pivots, worked by hand.
#include "ldlpgs/sparse/cholmod_adapter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/eigen_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "tests/support/temp_files.h"
#include "tests/support/test_matrices.h"

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
    EXPECT_EQ(std::string(e.what()), missing + ": cannot open file: No such file or directory");
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

// --- cholmod_ldl ----------------------------------------------------------------------------

// P A P^T, full, with (P A P^T)(k, l) = A(perm[k], perm[l]).
Eigen::SparseMatrix<double> permuted(const SymmetricCsc& a, const std::vector<int>& perm) {
  std::vector<int> inverse(a.n);
  for (int k = 0; k < a.n; ++k) inverse[perm[k]] = k;
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int r = inverse[a.row_idx[p]], c = inverse[j];
      t.emplace_back(r, c, a.values[p]);
      if (r != c) t.emplace_back(c, r, a.values[p]);
    }
  }
  Eigen::SparseMatrix<double> m(a.n, a.n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

// L D L^T from CHOLMOD's convention (the stored diagonal is D, L's unit diagonal implied),
// multiplied out in sparse arithmetic: its cost is the factorization's flops, not n^3.
Eigen::SparseMatrix<double> multiply_out(const SymmetricCsc& l) {
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd d = Eigen::VectorXd::Zero(l.n);
  for (int j = 0; j < l.n; ++j) {
    t.emplace_back(j, j, 1.0);
    for (int p = l.col_ptr[j]; p < l.col_ptr[j + 1]; ++p) {
      if (l.row_idx[p] == j) {
        d[j] = l.values[p];
      } else {
        t.emplace_back(l.row_idx[p], j, l.values[p]);
      }
    }
  }
  Eigen::SparseMatrix<double> unit(l.n, l.n);
  unit.setFromTriplets(t.begin(), t.end());
  const Eigen::SparseMatrix<double> ld = unit * d.asDiagonal();
  return Eigen::SparseMatrix<double>(ld * unit.transpose());
}

double max_abs(const Eigen::SparseMatrix<double>& m) {
  double largest = 0;
  for (int j = 0; j < m.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, j); it; ++it) largest = std::max(largest, std::abs(it.value()));
  }
  return largest;
}

// ||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf): the normwise backward error of x.
double backward_error(const SymmetricCsc& a, const std::vector<double>& x, const std::vector<double>& b) {
  const Eigen::SparseMatrix<double> full = to_eigen(a, Triangle::full);
  const Eigen::Map<const Eigen::VectorXd> xm(x.data(), a.n), bm(b.data(), a.n);
  double norm = 0;  // ||A||_inf, the largest absolute row sum (= column sum: A is symmetric)
  for (int j = 0; j < a.n; ++j) norm = std::max(norm, full.col(j).cwiseAbs().sum());
  const Eigen::VectorXd r = full * xm - bm;
  return r.lpNorm<Eigen::Infinity>() / (norm * xm.lpNorm<Eigen::Infinity>() + bm.lpNorm<Eigen::Infinity>());
}

TEST(CholmodLdl, ReconstructsPapAndSolvesOnEveryTestMatrix) {
  // Every test matrix is SPD: CHOLMOD must succeed in any order. Identity and reversed orders
  // on all; a random order (whose fill can be near dense) on the smaller ones.
  Cholmod cm;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const auto& [name, a] : test_matrices()) {
    std::vector<std::pair<std::string, std::vector<int>>> perms(1, {"identity", std::vector<int>(a.n)});
    std::iota(perms[0].second.begin(), perms[0].second.end(), 0);
    perms.push_back({"reversed", std::vector<int>(perms[0].second.rbegin(), perms[0].second.rend())});
    if (a.n <= 500) {
      perms.push_back({"random", perms[0].second});
      std::shuffle(perms.back().second.begin(), perms.back().second.end(), rng);
    }
    for (const auto& [kind, perm] : perms) {
      SCOPED_TRACE(name + ", " + kind + " order");
      std::vector<double> b(a.n);
      for (double& v : b) v = uniform(rng);
      const CholmodLdl f = cholmod_ldl(a, perm, b, cm);
      EXPECT_EQ(f.status, CHOLMOD_OK);
      EXPECT_EQ(f.minor, a.n);
      testing::expect_valid(f.l);
      // Every column starts with its diagonal (D), and L has the entries CHOLMOD's analysis
      // counted: the factor is complete and packed.
      for (int j = 0; j < a.n; ++j) {
        ASSERT_LT(f.l.col_ptr[j], f.l.col_ptr[j + 1]);
        ASSERT_EQ(f.l.row_idx[f.l.col_ptr[j]], j);
      }
      EXPECT_EQ(static_cast<double>(f.l.nnz()), cholmod_counts(a, perm, cm).lnz);
      const Eigen::SparseMatrix<double> pap = permuted(a, perm);
      const Eigen::SparseMatrix<double> diff = multiply_out(f.l) - pap;
      EXPECT_LE(max_abs(diff), 1e-12 * max_abs(pap)) << "L D L^T differs from P A P^T";
      ASSERT_EQ(static_cast<int>(f.x.size()), a.n);
      EXPECT_LT(backward_error(a, f.x, b), 1e-14);
    }
  }
}

TEST(CholmodLdl, DiagonalHoldsDNotItsSquareRoot) {
  // [4 2; 2 5] = [1 0; 0.5 1] diag(4, 4) [1 0.5; 0 1]. An LL^T would store 2 and 2 on the
  // diagonal and 1 below it.
  const SymmetricCsc a = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 4}, {1, 0, 2}, {1, 1, 5}});
  Cholmod cm;
  const CholmodLdl f = cholmod_ldl(a, std::vector<int>{0, 1}, std::vector<double>{}, cm);
  EXPECT_EQ(f.l.values, (std::vector<double>{4, 0.5, 4}));
  EXPECT_TRUE(f.x.empty());
}

TEST(CholmodLdl, NegativePivotIsAccepted) {
  // [1 2; 2 1] = [1 0; 2 1] diag(1, -3) [1 2; 0 1]: indefinite, and CHOLMOD's LDL^T takes the
  // negative pivot without complaint. b = (3, 3) gives x = (1, 1), exactly.
  const SymmetricCsc a = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 1}, {1, 0, 2}, {1, 1, 1}});
  Cholmod cm;
  const CholmodLdl f = cholmod_ldl(a, std::vector<int>{0, 1}, std::vector<double>{3, 3}, cm);
  EXPECT_EQ(f.status, CHOLMOD_OK);
  EXPECT_EQ(f.minor, 2);
  EXPECT_EQ(f.l.col_ptr, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(f.l.row_idx, (std::vector<int>{0, 1, 1}));
  EXPECT_EQ(f.l.values, (std::vector<double>{1, 2, -3}));
  EXPECT_EQ(f.x, (std::vector<double>{1, 1}));
}

TEST(CholmodLdl, ZeroPivotStopsAtThatColumn) {
  // [1 1 0; 1 1 1; 0 1 2] is nonsingular (det -1) but its second pivot is 1 - 1*1 = 0 exactly.
  // CHOLMOD reports the column and zeroes D and L from there on; no solution is given.
  const SymmetricCsc a = csc_from_triplets(
      3, std::vector<Triplet>{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {2, 1, 1}, {2, 2, 2}});
  Cholmod cm;
  const CholmodLdl f = cholmod_ldl(a, std::vector<int>{0, 1, 2}, std::vector<double>{1, 2, 3}, cm);
  EXPECT_EQ(f.status, CHOLMOD_NOT_POSDEF);
  EXPECT_EQ(f.minor, 1);
  EXPECT_TRUE(f.x.empty());
  EXPECT_EQ(f.l.col_ptr, (std::vector<int>{0, 2, 4, 5}));
  EXPECT_EQ(f.l.row_idx, (std::vector<int>{0, 1, 1, 2, 2}));
  EXPECT_EQ(f.l.values, (std::vector<double>{1, 1, 0, 0, 0}));
}

TEST(CholmodLdl, ZeroPivotColumnIsInThePermutedOrder) {
  // [1 0 1; 0 5 0; 1 0 1] is singular: rows 0 and 2 are equal. In the natural order the zero
  // pivot is the last one (1 - 1*1); eliminating row 2 second (perm 0, 2, 1) brings it to
  // column 1 of P A P^T, and minor says 1.
  const SymmetricCsc a = csc_from_triplets(
      3, std::vector<Triplet>{{0, 0, 1}, {2, 0, 1}, {1, 1, 5}, {2, 2, 1}});
  Cholmod cm;
  const CholmodLdl natural = cholmod_ldl(a, std::vector<int>{0, 1, 2}, std::vector<double>{}, cm);
  EXPECT_EQ(natural.status, CHOLMOD_NOT_POSDEF);
  EXPECT_EQ(natural.minor, 2);
  const CholmodLdl swapped = cholmod_ldl(a, std::vector<int>{0, 2, 1}, std::vector<double>{}, cm);
  EXPECT_EQ(swapped.status, CHOLMOD_NOT_POSDEF);
  EXPECT_EQ(swapped.minor, 1);
  // D = (1, 0, 0): the 5 of the last column is lost, zeroed with everything after the minor.
  EXPECT_EQ(swapped.l.values, (std::vector<double>{1, 1, 0, 0}));
}

TEST(CholmodLdl, IgnoresAndRestoresCommonSettings) {
  // Settings that would change the factor if used (LL^T when done, supernodal, postordering,
  // other orderings) must not change it, and must be left as they were.
  const SymmetricCsc a = read("bcsstk01.mtx");
  std::vector<int> perm(a.n);
  std::iota(perm.rbegin(), perm.rend(), 0);
  const std::vector<double> b(a.n, 1.0);
  Cholmod cm;
  cholmod_common* c = cm.common();
  const CholmodLdl plain = cholmod_ldl(a, perm, b, cm);
  c->final_asis = false;
  c->final_ll = true;
  c->final_super = true;
  c->supernodal = CHOLMOD_SUPERNODAL;
  c->postorder = true;
  c->nmethods = 3;
  c->method[0].ordering = CHOLMOD_AMD;
  const CholmodLdl again = cholmod_ldl(a, perm, b, cm);
  expect_equal(again.l, plain.l);
  EXPECT_EQ(again.x, plain.x);
  EXPECT_EQ(c->final_asis, 0);
  EXPECT_EQ(c->final_ll, 1);
  EXPECT_EQ(c->final_super, 1);
  EXPECT_EQ(c->supernodal, CHOLMOD_SUPERNODAL);
  EXPECT_EQ(c->postorder, 1);
  EXPECT_EQ(c->nmethods, 3);
  EXPECT_EQ(c->method[0].ordering, CHOLMOD_AMD);
}

// Matrices without stored entries: their empty arrays gave CHOLMOD null
// pointers (status -4, "invalid xtype") and n = 0 its analysis refuses; now the counts are the
// diagonal's (the analytic answer: L = I, one flop per column) and the LDL^T of an empty
// diagonal stops at its first column.
TEST(CholmodAdapter, MatricesWithoutEntries) {
  Cholmod cm;
  const SymmetricCsc none = csc_from_triplets(0, std::vector<Triplet>{});
  const CholmodCounts zero = cholmod_counts(none, std::vector<int>{}, cm);
  EXPECT_EQ(zero.lnz, 0);
  EXPECT_EQ(zero.fl, 0);
  EXPECT_EQ(cholmod_ldl(none, std::vector<int>{}, std::vector<double>{}, cm).l.n, 0);

  const SymmetricCsc empty = csc_from_triplets(5, std::vector<Triplet>{});
  const std::vector<int> perm{0, 1, 2, 3, 4};
  const CholmodCounts counts = cholmod_counts(empty, perm, cm);
  EXPECT_EQ(counts.lnz, 5);
  EXPECT_EQ(counts.fl, 5);
  const CholmodLdl ldl = cholmod_ldl(empty, perm, std::vector<double>(5, 1.0), cm);
  EXPECT_NE(ldl.status, CHOLMOD_OK);  // D = 0: not positive definite
  EXPECT_TRUE(ldl.x.empty());
}
}  // namespace
}  // namespace ldlpgs
