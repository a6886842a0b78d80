// factor/dense.cpp: a wide supernode's elimination, its node block by panels that run LAPACK's
// Cholesky where they are positive definite and the LDL^T triple loop where not, alone and with
// the rows below it. Checked
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
using ColumnMajor = Eigen::MatrixXd;  // a node block's layout (dense.h)

struct Result {
  int bad;
  Matrix l, d;  // unit-lower L and D from the factored block
  std::vector<double> inv_d;
};

// The node block alone: factor_supernode as a supernode with no rows below.
Result factor(const Matrix& a, double floor = 1e-300) {
  const int n = static_cast<int>(a.rows());
  ColumnMajor f = a;
  f.triangularView<Eigen::StrictlyUpper>().setConstant(std::nan(""));  // only the lower triangle is read
  std::vector<double> floors(n, floor), inv_d(n, 0), w(static_cast<size_t>(n) * dense::kPanel);
  const int bad = dense::factor_supernode(f.data(), n, 0, floors.data(), inv_d.data(), w.data());
  Result r{bad, Matrix::Identity(n, n), Matrix::Zero(n, n), inv_d};
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
  ColumnMajor lc = a;
  int info = 0;
  dpotrf_("L", &n, lc.data(), &n, &info);
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
    EXPECT_EQ(factor(a, 1e-8 * n).bad, k);  // (dpotrf may pass the pivot; its floor may not)
    EXPECT_EQ(factor(spd(n, 7), 1e-8 * n).bad, -1);
  }
}

// A NaN or an infinity in the block is reported at its pivot (off the diagonal, at its row's),
// not factored into L.
TEST(Dense, NonFinitePivotIsReported) {
  const int n = 2 * dense::kPanel + 5;
  for (int k : {0, 10, dense::kPanel + 2}) {
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
      Matrix a = spd(n, 3);
      a(k, k) = bad;
      EXPECT_EQ(factor(a).bad, k) << bad;
      a(k, k) = n;  // off the diagonal, it poisons the pivot of its row
      a(n - 1, k) = a(k, n - 1) = bad;
      EXPECT_EQ(factor(a).bad, n - 1) << bad;
    }
  }
}

// Other supernodes' updates, written row-major lower (kernels.h) into the node block's other
// triangle, are added to its column-major lower triangle, diagonal untouched (both layouts share
// it), across tile edges.
TEST(Dense, FoldAddsTheRowMajorUpdatesToTheColumnMajorBlock) {
  for (int d : {1, 31, 32, 70}) {
    SCOPED_TRACE(d);
    const Matrix a = Matrix::Random(d, d), u = Matrix::Random(d, d);
    std::vector<double> block(static_cast<size_t>(d) * d);
    Eigen::Map<ColumnMajor> node(block.data(), d, d);
    Eigen::Map<Matrix> updates(block.data(), d, d);
    node = a.triangularView<Eigen::Lower>();
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < i; ++j) updates(i, j) = u(i, j);
    dense::fold_updates(block.data(), d);
    for (int j = 0; j < d; ++j) {
      EXPECT_EQ(node(j, j), a(j, j)) << j;
      for (int i = j + 1; i < d; ++i) EXPECT_EQ(node(i, j), a(i, j) + u(i, j)) << i << ", " << j;
    }
  }
}

// A supernode (factor_supernode): the node block A (d x d) followed by the h rows E below it.
// Checked against Eigen: L D L^T = A, Y D L^T = E and C = E A^-1 E^T (the Schur update). A
// positive definite node of one panel is LAPACK's Cholesky of the whole block (D_j exactly the
// square of dpotrf's Lc_jj); wider nodes are its panels, indefinite ones the LDL^T loop's.
TEST(Dense, SupernodeGivesLYAndTheSchurUpdate) {
  struct Case {
    int d, h;
    bool definite;
  };
  for (const Case& k : {Case{9, 11, true}, Case{12, 4, false}, Case{20, 7, true}, Case{101, 9, true}, Case{dense::kPanel + 6, 30, false}, Case{dense::kPanel + 6, 0, true},
                        Case{803, 5, true}}) {
    SCOPED_TRACE(testing::Message() << k.d << " x " << k.h << (k.definite ? " definite" : " indefinite"));
    const int d = k.d, h = k.h;
    std::vector<double> signs(d, 1.0);
    if (!k.definite) signs[d / 2] = -1;
    const Matrix a = k.definite ? spd(d, 5) : dominant(signs, 5);
    Matrix e = Matrix::Random(h, d);
    // The node block column-major, E row-major after it (dense.h).
    std::vector<double> block(static_cast<size_t>(d) * (d + h));
    Eigen::Map<ColumnMajor> node(block.data(), d, d);
    Eigen::Map<Matrix> below(block.data() + static_cast<size_t>(d) * d, h, d);
    node = a;
    node.triangularView<Eigen::StrictlyUpper>().setConstant(std::nan(""));
    below = e;
    std::vector<double> floors(d, 1e-300), inv_d(d, 0);
    std::vector<double> w(std::max(static_cast<size_t>(h) * d + static_cast<size_t>(h) * h, static_cast<size_t>(d) * dense::kPanel));
    ASSERT_EQ(dense::factor_supernode(block.data(), d, h, floors.data(), inv_d.data(), w.data()), -1);
    Matrix l = Matrix::Identity(d, d), dm = Matrix::Zero(d, d);
    for (int i = 0; i < d; ++i) {
      for (int j = 0; j < i; ++j) l(i, j) = node(i, j);
      dm(i, i) = node(i, i);
      EXPECT_DOUBLE_EQ(inv_d[i] * dm(i, i), 1.0) << i;
    }
    EXPECT_LE((l * dm * l.transpose() - a).norm() / a.norm(), 1e-14 * d);
    if (k.definite && d <= dense::kPanel) {
      ColumnMajor lc = a;
      int info = 0;
      dpotrf_("L", &d, lc.data(), &d, &info);
      ASSERT_EQ(info, 0);
      for (int j = 0; j < d; ++j) EXPECT_EQ(dm(j, j), lc(j, j) * lc(j, j)) << j;
    }
    if (h == 0) continue;
    const Matrix y = below;
    EXPECT_LE((y * dm * l.transpose() - e).norm() / e.norm(), 1e-13);
    const Matrix c_ref = e * a.ldlt().solve(Matrix(e.transpose()));
    const Eigen::Map<const Matrix> c(w.data() + static_cast<size_t>(h) * d, h, h);
    EXPECT_LE((Matrix(c.triangularView<Eigen::Lower>()) - Matrix(c_ref.triangularView<Eigen::Lower>())).norm() / c_ref.norm(),
              1e-12);
  }
}

}  // namespace
}  // namespace ldlpgs
