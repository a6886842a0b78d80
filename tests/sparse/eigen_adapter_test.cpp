// to_eigen (full and lower) against a dense matrix read straight from the CSC arrays, with the
// explicit-zero structure kept; from_eigen ignoring the upper triangle, accepting an
// uncompressed matrix; and from_eigen(to_eigen(a)) == a on every test matrix.
#include "ldlpgs/sparse/eigen_adapter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <string>
#include <vector>

#include "ldlpgs/sparse/matrix_market.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

using testing::expect_equal;
using testing::test_matrices;

// The reference: a dense matrix filled from the arrays, lower triangle or both.
Eigen::MatrixXd dense(const SymmetricCsc& a, bool full) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(a.n, a.n);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      d(a.row_idx[p], j) = a.values[p];
      if (full) d(j, a.row_idx[p]) = a.values[p];
    }
  }
  return d;
}

int64_t diagonal_entries(const SymmetricCsc& a) {
  int64_t k = 0;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) k += a.row_idx[p] == j;
  }
  return k;
}

TEST(ToEigen, HandBuilt) {
  // [4 -1 0; -1 5 2; 0 2 0], (2,2) not stored; the dense matrices are written out by hand.
  const SymmetricCsc a =
      csc_from_triplets(3, std::vector<Triplet>{{0, 0, 4}, {1, 0, -1}, {1, 1, 5}, {2, 1, 2}});
  Eigen::MatrixXd full(3, 3), lower(3, 3);
  full << 4, -1, 0, -1, 5, 2, 0, 2, 0;
  lower << 4, 0, 0, -1, 5, 0, 0, 2, 0;
  EXPECT_EQ(Eigen::MatrixXd(to_eigen(a)), full);
  EXPECT_EQ(Eigen::MatrixXd(to_eigen(a, Triangle::full)), full);
  EXPECT_EQ(Eigen::MatrixXd(to_eigen(a, Triangle::lower)), lower);
}

TEST(ToEigen, ExplicitZeroIsKept) {
  // A stored zero is structure (it is an edge for the orderings); Eigen must keep it.
  const SymmetricCsc a = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 1}, {1, 0, 0.0}});
  EXPECT_EQ(to_eigen(a, Triangle::lower).nonZeros(), 2);
  EXPECT_EQ(to_eigen(a, Triangle::full).nonZeros(), 3);
  expect_equal(from_eigen(to_eigen(a)), a);
}

TEST(ToEigen, EveryTestMatrixAgainstDense) {
  ASSERT_GE(test_matrices().size(), 11u);
  for (const auto& [name, a] : test_matrices()) {
    SCOPED_TRACE(name);
    const Eigen::SparseMatrix<double> full = to_eigen(a, Triangle::full);
    const Eigen::SparseMatrix<double> lower = to_eigen(a, Triangle::lower);
    ASSERT_EQ(full.rows(), a.n);
    ASSERT_EQ(full.cols(), a.n);
    EXPECT_EQ(lower.nonZeros(), a.nnz());
    EXPECT_EQ(full.nonZeros(), 2 * a.nnz() - diagonal_entries(a));
    if (a.n <= 1500) {  // dense 2003^2 twice for bcsstk13 would only repeat the small ones
      EXPECT_TRUE(Eigen::MatrixXd(full) == dense(a, true));
      EXPECT_TRUE(Eigen::MatrixXd(lower) == dense(a, false));
    }
    const Eigen::SparseMatrix<double> transposed = full.transpose();
    EXPECT_EQ((full - transposed).norm(), 0.0) << "full matrix not symmetric";
  }
}

TEST(FromEigen, RoundTripOnEveryTestMatrix) {
  for (const auto& [name, a] : test_matrices()) {
    SCOPED_TRACE(name);
    expect_equal(from_eigen(to_eigen(a, Triangle::full)), a);
    expect_equal(from_eigen(to_eigen(a, Triangle::lower)), a);
  }
}

TEST(FromEigen, UpperTriangleIsIgnored) {
  // The upper entries disagree with the lower ones on purpose: only the lower ones count.
  Eigen::MatrixXd d(3, 3);
  d << 1, 9, 9, 2, 3, 9, 0, 4, 5;
  const SymmetricCsc a = from_eigen(d.sparseView());
  EXPECT_EQ(a.col_ptr, (std::vector<int>{0, 2, 4, 5}));
  EXPECT_EQ(a.row_idx, (std::vector<int>{0, 1, 1, 2, 2}));
  EXPECT_EQ(a.values, (std::vector<double>{1, 2, 3, 4, 5}));
}

TEST(FromEigen, UncompressedMatrix) {
  // insert() without makeCompressed() leaves slack in every column; it must not be read.
  Eigen::SparseMatrix<double> m(4, 4);
  m.reserve(Eigen::VectorXi::Constant(4, 3));
  m.insert(3, 0) = 7;
  m.insert(0, 0) = 1;
  m.insert(2, 2) = 3;
  m.insert(0, 3) = 8;  // upper: ignored
  m.insert(3, 3) = 4;
  ASSERT_FALSE(m.isCompressed());
  const SymmetricCsc a = from_eigen(m);
  EXPECT_EQ(a.col_ptr, (std::vector<int>{0, 2, 2, 3, 4}));
  EXPECT_EQ(a.row_idx, (std::vector<int>{0, 3, 2, 3}));
  EXPECT_EQ(a.values, (std::vector<double>{1, 7, 3, 4}));
}

TEST(FromEigen, Empty) {
  const SymmetricCsc a = from_eigen(Eigen::SparseMatrix<double>(0, 0));
  EXPECT_EQ(a.n, 0);
  EXPECT_EQ(a.nnz(), 0);
  const SymmetricCsc z = from_eigen(Eigen::SparseMatrix<double>(3, 3));
  EXPECT_EQ(z.col_ptr, std::vector<int>(4, 0));
}

}  // namespace
}  // namespace ldlpgs
