// BlockLDLT, the Eigen-style facade: its solutions against Eigen's own SimplicialLDLT (an
// independent factorization) on the test matrices x orderings, its L, D and P against the
// matrix they must reproduce, and one named test per misuse (every build, Release included).
#include "ldlpgs/factor/block_ldlt.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cctype>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "ldlpgs/sparse/eigen_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "tests/support/temp_files.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

struct Case {
  std::string matrix, ordering;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.matrix << " " << c.ordering; }

std::vector<Case> cases(int max_n) {
  std::vector<Case> out;
  for (const auto& m : testing::test_matrices())
    if (m.a.n <= max_n)
      for (const char* ordering : {"meca", "meca-w", "amd", "metis-scalar"}) out.push_back({m.name, ordering});
  return out;
}

const SymmetricCsc& matrix(const std::string& name) {
  for (const auto& m : testing::test_matrices())
    if (m.name == name) return m.a;
  throw std::runtime_error("no test matrix " + name);
}

class BlockLDLTHarness : public ::testing::TestWithParam<Case> {};
class BlockLDLTDense : public ::testing::TestWithParam<Case> {};  // small enough for dense products

// Both factorizations are backward stable: ours (no regularization) must reach a normwise
// backward error within 10x of Eigen's SimplicialLDLT on the same b, or 1e-15.
TEST_P(BlockLDLTHarness, SolvesAsEigenSimplicialLDLTDoes) {
  const SymmetricCsc& a = matrix(GetParam().matrix);
  const SpMat lower = to_eigen(a, Triangle::lower);
  BlockLDLTOptions options{.ordering = GetParam().ordering};
  options.factor.regularization = 0;
  BlockLDLT solver(lower, options);
  ASSERT_EQ(solver.info(), Eigen::Success) << solver.factor_info().message();
  const SpMat full = to_eigen(a, Triangle::full);
  const Eigen::VectorXd x0 = Eigen::VectorXd::LinSpaced(a.n, -1, 1);
  const Eigen::VectorXd b = full * x0;
  const Eigen::VectorXd x = solver.solve(b);

  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> eigen(lower);
  ASSERT_EQ(eigen.info(), Eigen::Success);
  const Eigen::VectorXd xe = eigen.solve(b);
  // Backward error of ours at most a small multiple of Eigen's (and of u).
  auto backward = [&](const Eigen::VectorXd& y) {
    return (b - full * y).lpNorm<Eigen::Infinity>() /
           (testing::dense(a).cwiseAbs().rowwise().sum().maxCoeff() * y.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
  };
  EXPECT_LE(backward(x), std::max(10 * backward(xe), 1e-15));
}

// P (A + eps diag A) P^T = L D L^T entry for entry, and matrixL is unit lower triangular.
TEST_P(BlockLDLTDense, FactorsReproduceTheMatrix) {
  const SymmetricCsc& a = matrix(GetParam().matrix);
  BlockLDLTOptions options{.ordering = GetParam().ordering};
  options.factor.regularization = 1e-8;
  BlockLDLT solver(to_eigen(a, Triangle::lower), options);
  ASSERT_EQ(solver.info(), Eigen::Success);
  Eigen::MatrixXd h = testing::dense(a);
  h.diagonal() *= 1 + 1e-8;
  const Eigen::MatrixXd l = Eigen::MatrixXd(solver.matrixL());
  EXPECT_TRUE(l.isLowerTriangular());
  EXPECT_TRUE(l.diagonal().isOnes());
  const Eigen::MatrixXd p = solver.permutationP().toDenseMatrix().cast<double>();
  const Eigen::MatrixXd ldl = l * solver.vectorD().asDiagonal() * l.transpose();
  EXPECT_LE((p * h * p.transpose() - ldl).cwiseAbs().maxCoeff(), 1e-12 * h.cwiseAbs().maxCoeff());
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.matrix + "_" + info.param.ordering;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}
INSTANTIATE_TEST_SUITE_P(TestMatrices, BlockLDLTHarness, ::testing::ValuesIn(cases(2500)), case_name);
INSTANTIATE_TEST_SUITE_P(TestMatrices, BlockLDLTDense, ::testing::ValuesIn(cases(500)), case_name);

TEST(BlockLDLT, ManyRightHandSidesAreColumnsSolvedOneByOne) {
  const SymmetricCsc& a = matrix("bcsstk01.mtx");
  BlockLDLT solver(to_eigen(a, Triangle::lower));
  ASSERT_EQ(solver.info(), Eigen::Success);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(a.n, 3);
  const Eigen::MatrixXd x = solver.solve(b);
  for (int j = 0; j < 3; ++j) {
    const Eigen::VectorXd xj = solver.solve(b.col(j));
    EXPECT_EQ((x.col(j) - xj).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(BlockLDLT, ComputeIsAnalyzePatternThenFactorizeAndFactorizeReusesTheAnalysis) {
  const SymmetricCsc& a = matrix("can___24.mtx");
  SpMat lower = to_eigen(a, Triangle::lower);
  BlockLDLT solver;
  solver.analyzePattern(lower);
  EXPECT_EQ(solver.info(), Eigen::InvalidInput);  // analyzed, not factored
  const Symbolic* analysis = &solver.symbolic();
  lower *= 2;  // same pattern, other values
  solver.factorize(lower);
  EXPECT_EQ(&solver.symbolic(), analysis);
  ASSERT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.n);
  const SpMat full = lower.selfadjointView<Eigen::Lower>();
  EXPECT_LE((full * solver.solve(b) - b).lpNorm<Eigen::Infinity>(), 1e-10);
}

TEST(BlockLDLT, GivenBlockSizesAreThePartition) {
  const SymmetricCsc& a = matrix("bcsstk01.mtx");  // 48 rows: 16 blocks of 3
  BlockLDLT solver(to_eigen(a, Triangle::lower), {.block_sizes = std::vector<int>(16, 3)});
  ASSERT_EQ(solver.info(), Eigen::Success);
  EXPECT_EQ(solver.symbolic().num_pivots(), 16);
  EXPECT_EQ(solver.symbolic().max_size(), 3);
}

TEST(BlockLDLT, UpperEntriesAreIgnoredAsEigenDoes) {
  const SymmetricCsc& a = matrix("bcsstk01.mtx");
  BlockLDLT lower(to_eigen(a, Triangle::lower)), full(to_eigen(a, Triangle::full));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.n);
  EXPECT_EQ((lower.solve(b) - full.solve(b)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(BlockLDLT, OrderingsAreCallableOnAnEigenMatrix) {
  const SymmetricCsc& a = matrix("can___24.mtx");
  const Ordering o = compute_ordering("amd", to_eigen(a, Triangle::full));
  EXPECT_EQ(o.name, "amd");
  std::vector<int> sorted = o.perm;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < a.n; ++i) EXPECT_EQ(sorted[i], i);
}

// Misuse: one test per kind.
SpMat small() { return to_eigen(csc_from_triplets(3, std::vector<Triplet>{{0, 0, 4}, {1, 1, 4}, {2, 2, 4}, {1, 0, 1}}), Triangle::lower); }

TEST(BlockLDLTMisuse, NonSquareMatrixThrows) {
  SpMat rect(3, 4);
  rect.insert(0, 0) = 1;
  BlockLDLT solver;
  EXPECT_THROW(solver.compute(rect), ArgumentError);
  EXPECT_THROW(compute_ordering("meca", rect), ArgumentError);
}

TEST(BlockLDLTMisuse, FactorizeOfAnotherPatternOrSizeThrows) {
  BlockLDLT solver(small());
  SpMat other = small();
  other.insert(2, 0) = 1;
  EXPECT_THROW(solver.factorize(other), ArgumentError);
  SpMat bigger(4, 4);
  bigger.setIdentity();
  EXPECT_THROW(solver.factorize(bigger), ArgumentError);
  EXPECT_EQ(solver.info(), Eigen::Success);  // the earlier factorization still stands
}

TEST(BlockLDLTMisuse, RightHandSideOfTheWrongSizeThrows) {
  BlockLDLT solver(small());
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(2)), ArgumentError);
  EXPECT_THROW(solver.solve(Eigen::MatrixXd::Ones(4, 2)), ArgumentError);
}

TEST(BlockLDLTMisuse, SolveOrFactorizeBeforeAnalysisThrows) {
  BlockLDLT solver;
  EXPECT_EQ(solver.info(), Eigen::InvalidInput);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(3)), ArgumentError);
  EXPECT_THROW(solver.factorize(small()), ArgumentError);
  solver.analyzePattern(small());
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(3)), ArgumentError);
}

TEST(BlockLDLTMisuse, UnknownOrderingThrowsNamingIt) {
  BlockLDLT solver({.ordering = "mecca"});
  try {
    solver.analyzePattern(small());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mecca"), std::string::npos) << e.what();
  }
}

TEST(BlockLDLTMisuse, NanEntryIsANumericalIssueNamingTheRow) {
  SpMat a = small();
  a.coeffRef(2, 2) = std::numeric_limits<double>::quiet_NaN();
  BlockLDLT solver(a);
  EXPECT_EQ(solver.info(), Eigen::NumericalIssue);
  EXPECT_EQ(solver.factor_info().status, FactorStatus::not_finite);
  EXPECT_EQ(solver.factor_info().row, 2);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(3)), ArgumentError);
}

TEST(BlockLDLTMisuse, PartitionThatDoesNotCoverTheRowsThrows) {
  const std::string path = testing::temp_path("two.blocks");
  std::ofstream(path) << "1\n1\n";  // 2 rows of 3
  BlockLDLT solver({.blocks = path});
  EXPECT_THROW(solver.analyzePattern(small()), InputError);
  BlockLDLT zero({.blocks = "0"});
  EXPECT_THROW(zero.analyzePattern(small()), InputError);
  BlockLDLT sizes({.block_sizes = {2, 2}});  // 4 rows of 3
  EXPECT_THROW(sizes.analyzePattern(small()), ArgumentError);
  EXPECT_THROW(compute_ordering("meca", small(), std::vector<int>{1, 1}), ArgumentError);
}

}  // namespace
}  // namespace ldlpgs
