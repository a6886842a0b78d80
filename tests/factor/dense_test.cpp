// factor/dense.cpp: the blocked LDL^T of a wide supernode's node block, whose panels run
// LAPACK's Cholesky where they are positive definite and the LDL^T triple loop where not. Checked
// against independent references: the reconstruction L D L^T against A, and the inertia against
// the signs of A's eigenvalues (Sylvester's law of inertia) from Eigen's dense eigensolver.
#include "ldlpgs/factor/dense.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <vector>

extern "C" void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);

namespace ldlpgs {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Result {
  int bad;
  Matrix l, d;  // unit-lower L and D from the factored block
  std::vector<double> inv_d;
};

Result factor(const Matrix& a, double floor = 1e-300) {
  const int n = static_cast<int>(a.rows());
  Matrix f = a;
  f.triangularView<Eigen::StrictlyUpper>().setConstant(std::nan(""));  // only the lower triangle is read
  std::vector<double> floors(n, floor), inv_d(n, 0), w(static_cast<size_t>(n) * dense::kPanel);
  Result r{dense::ldl_blocked(f.data(), n, n, floors.data(), inv_d.data(), w.data()), Matrix::Identity(n, n),
           Matrix::Zero(n, n), inv_d};
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) r.l(i, j) = f(i, j);
    r.d(i, i) = f(i, i);
  }
  return r;
}

// A = V V^T + n I (positive definite) with V n x n standard normal, or with the signs of the
// diagonal given: diagonally dominant, so an unpivoted LDL^T exists and is stable.
Matrix spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Matrix v(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) v(i, j) = g(rng);
  return v * v.transpose() + n * Matrix::Identity(n, n);
}

Matrix dominant(const std::vector<double>& signs, unsigned seed) {
  const int n = static_cast<int>(signs.size());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Matrix a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) a(i, j) = a(j, i) = u(rng);
  for (int i = 0; i < n; ++i) a(i, i) = signs[i] * (2 * n);
  return a;
}

void expect_factors(const Matrix& a, const Result& r) {
  ASSERT_EQ(r.bad, -1);
  const Matrix back = r.l * r.d * r.l.transpose();
  EXPECT_LE((back - a).norm() / a.norm(), 1e-14 * a.rows());
  for (int j = 0; j < a.rows(); ++j) EXPECT_DOUBLE_EQ(r.inv_d[j] * r.d(j, j), 1.0) << j;
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Matrix>(a).eigenvalues();
  EXPECT_EQ((r.d.diagonal().array() < 0).count(), (eig.array() < 0).count());
}

// Sizes around the panel width: one panel, a partial one, several.
TEST(Dense, PositiveDefiniteBlocksByCholeskyPanels) {
  for (int n : {1, 5, dense::kPanel - 1, dense::kPanel, dense::kPanel + 1, 2 * dense::kPanel + 3, 300}) {
    SCOPED_TRACE(n);
    const Matrix a = spd(n, static_cast<unsigned>(n));
    expect_factors(a, factor(a));
  }
}

// The positive definite panel is LAPACK's: for one panel D_j is exactly the square of dpotrf's
// Lc_jj (computed here on the same block), which the LDL^T loop does not reproduce bit for bit
// (its pivots are a_jj - sum l_jk^2 d_k, not squares of square roots).
TEST(Dense, PositiveDefinitePanelIsLapacksCholesky) {
  const int n = dense::kPanel;
  const Matrix a = spd(n, 11);
  Matrix lc = a;
  int info = 0;
  dpotrf_("U", &n, lc.data(), &n, &info);  // row-major lower = column-major upper
  ASSERT_EQ(info, 0);
  const Result r = factor(a);
  ASSERT_EQ(r.bad, -1);
  for (int j = 0; j < n; ++j) EXPECT_EQ(r.d(j, j), lc(j, j) * lc(j, j)) << j;
}

// Negative pivots in the second panel only, in the first only, in every panel: the panels that
// are positive definite and those that are not mix in one factorization.
TEST(Dense, IndefinitePanelsFallBackToTheLdltLoop) {
  const int n = 3 * dense::kPanel + 10;
  for (const std::vector<int>& negative : std::vector<std::vector<int>>{
           {dense::kPanel + 3}, {0}, {5, dense::kPanel + 7, 2 * dense::kPanel, 3 * dense::kPanel + 9}, {n - 1}}) {
    std::vector<double> signs(n, 1.0);
    for (int k : negative) signs[k] = -1;
    SCOPED_TRACE(negative.front());
    const Matrix a = dominant(signs, static_cast<unsigned>(negative.size()));
    const Result r = factor(a);
    expect_factors(a, r);
    for (int k = 0; k < n; ++k) EXPECT_EQ(r.d(k, k) < 0, signs[k] < 0) << k;
  }
}

// A positive semidefinite block whose pivot k is zero in exact arithmetic (row k of V repeats row
// k - 1): the first pivot at or below the floor is reported, whether in a panel Cholesky would
// take or not, and a pivot above the floor is not.
TEST(Dense, ZeroPivotIsReportedWhereverItFalls) {
  const int n = 2 * dense::kPanel + 20;
  for (int k : {1, dense::kPanel - 1, dense::kPanel, dense::kPanel + 30, n - 1}) {
    SCOPED_TRACE(k);
    std::mt19937 rng(static_cast<unsigned>(k));
    std::normal_distribution<double> g;
    Matrix v(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) v(i, j) = g(rng);
    v.row(k) = v.row(k - 1);
    const Matrix a = v * v.transpose();
    EXPECT_EQ(factor(a, 1e-8 * n).bad, k);
    EXPECT_EQ(factor(spd(n, 7), 1e-8 * n).bad, -1);
  }
}

// A NaN or an infinity in the block is reported at its pivot, not factored into L.
TEST(Dense, NonFinitePivotIsReported) {
  const int n = 2 * dense::kPanel + 5;
  for (int k : {0, 10, dense::kPanel + 2}) {
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
      Matrix a = spd(n, 3);
      a(k, k) = bad;
      EXPECT_EQ(factor(a).bad, k) << bad;
    }
  }
}

}  // namespace
}  // namespace ldlpgs
