// The competitor solvers: every name, on test matrices in a random order, solves A x = b with a
// backward error near machine precision and agrees with a dense LU solve (Eigen's
// PartialPivLU, an algorithm none of them uses) within what the condition number allows;
// refactoring gives the same answer; each reports the pivot failures its algorithm has (worked
// by hand), and CHOLMOD says where; the CHOLMOD ones allocate nothing from the second solve on;
// unknown names are refused; the BLAS CHOLMOD calls is named by a file that exists.
#include "peers/competitors.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

const std::string kMatrices = LDLPGS_MATRICES;

using testing::dense;

SymmetricCsc read(const std::string& name) { return read_matrix_market(kMatrices + "/" + name); }

std::vector<int> random_perm(int n, std::mt19937& rng) {
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  return perm;
}

// ||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf): the normwise backward error of x.
double backward_error(const Eigen::MatrixXd& a, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  const double norm = a.cwiseAbs().rowwise().sum().maxCoeff();
  return (a * x - b).lpNorm<Eigen::Infinity>() /
         (norm * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
}

TEST(DirectSolvers, Names) {
  const auto names = direct_solver_names();
  ASSERT_EQ(names.size(), 4u);
  EXPECT_EQ(names[0], "cholmod");
  EXPECT_EQ(names[1], "cholmod-supernodal");
  EXPECT_EQ(names[2], "eigen-simplicial");
  EXPECT_EQ(names[3], "eigen-dense");
  const SymmetricCsc a = read("LFAT5.mtx");
  std::vector<int> perm(a.n);
  std::iota(perm.begin(), perm.end(), 0);
  for (std::string_view name : names) EXPECT_EQ(make_direct_solver(name, a, perm)->name(), name);
}

TEST(DirectSolvers, UnknownNameIsRefused) {
  const SymmetricCsc a = read("LFAT5.mtx");
  std::vector<int> perm(a.n);
  std::iota(perm.begin(), perm.end(), 0);
  try {
    make_direct_solver("mumps", a, perm);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown direct solver 'mumps' (known: cholmod, cholmod-supernodal, eigen-simplicial, "
              "eigen-dense)");
  }
}

TEST(DirectSolvers, SolveTestMatricesInARandomOrder) {
  // All these matrices are SPD, so every solver must factor them in any order. The forward
  // error of a solution with backward error eta is at most about 2 kappa eta (kappa the
  // condition number in the inf-norm); two solutions with eta < 1e-14 differ by at most
  // 4 kappa 1e-14 relative to their size.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const char* file : {"LFAT5.mtx", "can___24.mtx", "bcsstk01.mtx", "bcsstk02.mtx", "pts5ldd03.mtx",
                           "494_bus.mtx"}) {
    const SymmetricCsc a = read(file);
    const Eigen::MatrixXd d = dense(a);
    const double kappa = d.cwiseAbs().rowwise().sum().maxCoeff() *
                         d.inverse().cwiseAbs().rowwise().sum().maxCoeff();
    const std::vector<int> perm = random_perm(a.n, rng);
    Eigen::VectorXd b(a.n);
    for (int i = 0; i < a.n; ++i) b[i] = uniform(rng);
    const Eigen::VectorXd reference = d.partialPivLu().solve(b);
    ASSERT_LT(backward_error(d, reference, b), 1e-14) << file;
    for (std::string_view name : direct_solver_names()) {
      SCOPED_TRACE(std::string(file) + ", " + std::string(name));
      const auto solver = make_direct_solver(name, a, perm);
      ASSERT_TRUE(solver->factor());
      Eigen::VectorXd x = b;
      solver->solve({x.data(), static_cast<size_t>(x.size())});
      EXPECT_LT(backward_error(d, x, b), 1e-14);
      EXPECT_LE((x - reference).lpNorm<Eigen::Infinity>(),
                4 * kappa * 1e-14 * reference.lpNorm<Eigen::Infinity>())
          << "kappa " << kappa;
    }
  }
}

TEST(DirectSolvers, FactorAgainGivesTheSameSolution) {
  // A benchmark factors and solves many times: each factor() starts afresh from the matrix, so
  // the second factorization and its solutions are the first ones, bit for bit.
  const SymmetricCsc a = read("bcsstk01.mtx");
  std::mt19937 rng(3);
  const std::vector<int> perm = random_perm(a.n, rng);
  const std::vector<double> b1(a.n, 1.0);
  std::vector<double> b2(a.n);
  for (int i = 0; i < a.n; ++i) b2[i] = i % 3 - 1.0;
  for (std::string_view name : direct_solver_names()) {
    SCOPED_TRACE(std::string(name));
    const auto solver = make_direct_solver(name, a, perm);
    ASSERT_TRUE(solver->factor());
    std::vector<double> x1 = b1, x2 = b2;
    solver->solve(x1);
    solver->solve(x2);
    ASSERT_TRUE(solver->factor());
    std::vector<double> y2 = b2, y1 = b1;
    solver->solve(y2);
    solver->solve(y1);
    EXPECT_EQ(y1, x1);
    EXPECT_EQ(y2, x2);
  }
}

struct PivotCase {
  std::string name;
  SymmetricCsc a;
  std::vector<double> x;  // the exact solution for b = A x
};

TEST(DirectSolvers, PivotFailuresAreTheAlgorithms) {
  // Natural order. [1 2; 2 1] is indefinite with nonzero pivots (D = 1, -3): the LDL^T ones
  // factor it, the supernodal LL^T cannot (sqrt of -3). [1 1 0; 1 1 1; 0 1 2] is nonsingular
  // (det -1) but its second pivot is exactly 0: every factorization in the given order fails;
  // Eigen's dense LDL^T picks its own pivots (the largest diagonal first) and succeeds.
  const std::vector<PivotCase> cases = {
      {"indefinite", csc_from_triplets(2, std::vector<Triplet>{{0, 0, 1}, {1, 0, 2}, {1, 1, 1}}), {1, -2}},
      {"zero pivot", csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {2, 1, 1}, {2, 2, 2}}),
       {1, 2, -1}},
  };
  // expected[case][solver], solvers in direct_solver_names() order.
  const bool expected[2][4] = {{true, false, true, true}, {false, false, false, true}};
  for (size_t c = 0; c < cases.size(); ++c) {
    const PivotCase& pc = cases[c];
    const int n = pc.a.n;
    std::vector<int> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    const Eigen::VectorXd b = dense(pc.a) * Eigen::Map<const Eigen::VectorXd>(pc.x.data(), n);
    for (size_t s = 0; s < direct_solver_names().size(); ++s) {
      const std::string_view name = direct_solver_names()[s];
      SCOPED_TRACE(pc.name + ", " + std::string(name));
      const auto solver = make_direct_solver(name, pc.a, perm);
      EXPECT_EQ(solver->factor(), expected[c][s]);
      // failure() says why, and CHOLMOD where: every failing case stops at row 1 (the -3 of
      // the indefinite one, the 0 of the other).
      EXPECT_EQ(solver->failure().empty(), expected[c][s]) << solver->failure();
      if (!expected[c][s] && name.starts_with("cholmod")) {
        EXPECT_NE(solver->failure().find("at row 1,"), std::string::npos) << solver->failure();
      }
      if (!expected[c][s]) continue;
      Eigen::VectorXd x = b;
      solver->solve({x.data(), static_cast<size_t>(x.size())});
      for (int i = 0; i < n; ++i) EXPECT_NEAR(x[i], pc.x[i], 1e-15 * 4);
    }
  }
}

// CHOLMOD's failure() names the original row: diag(2, 0, 3) eliminated in the order 2, 0, 1 stops
// at its third column, row 1 (a mix-up of the order, its inverse or the column would say 2 or 0).
TEST(DirectSolvers, FailureNamesTheOriginalRow) {
  const SymmetricCsc a = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 2}, {1, 1, 0}, {2, 2, 3}});
  const std::vector<int> perm = {2, 0, 1};
  const auto simplicial = make_direct_solver("cholmod", a, perm);
  ASSERT_FALSE(simplicial->factor());
  EXPECT_NE(simplicial->failure().find("zero pivot (CHOLMOD status 1) at row 1, column 2 "), std::string::npos)
      << simplicial->failure();
  const auto supernodal = make_direct_solver("cholmod-supernodal", a, perm);  // (its order postordered)
  ASSERT_FALSE(supernodal->factor());
  EXPECT_NE(supernodal->failure().find("at row 1,"), std::string::npos) << supernodal->failure();
}

// Counts CHOLMOD's allocations: every CHOLMOD allocation goes through SuiteSparse_config's
// function pointers (SuiteSparse 5: SuiteSparse_malloc, _calloc, _realloc).
struct CountAllocations {
  static inline int count = 0;
  static void* malloc(size_t size) { ++count; return std::malloc(size); }
  static void* calloc(size_t n, size_t size) { ++count; return std::calloc(n, size); }
  static void* realloc(void* p, size_t size) { ++count; return std::realloc(p, size); }
  decltype(SuiteSparse_config.malloc_func) saved_malloc = SuiteSparse_config.malloc_func;
  decltype(SuiteSparse_config.calloc_func) saved_calloc = SuiteSparse_config.calloc_func;
  decltype(SuiteSparse_config.realloc_func) saved_realloc = SuiteSparse_config.realloc_func;
  CountAllocations() {
    count = 0;
    SuiteSparse_config.malloc_func = malloc;
    SuiteSparse_config.calloc_func = calloc;
    SuiteSparse_config.realloc_func = realloc;
  }
  ~CountAllocations() {
    SuiteSparse_config.malloc_func = saved_malloc;
    SuiteSparse_config.calloc_func = saved_calloc;
    SuiteSparse_config.realloc_func = saved_realloc;
  }
};

TEST(DirectSolvers, CholmodSolvesAllocateNothingAfterTheFirst) {
  // cholmod_solve2 keeps the solution and its workspace: the first solve allocates them, the
  // next ones reuse them. (cholmod_solve would allocate and free them at every call.)
  const SymmetricCsc a = read("bcsstk01.mtx");
  std::mt19937 rng(5);
  const std::vector<int> perm = random_perm(a.n, rng);
  for (std::string_view name : {"cholmod", "cholmod-supernodal"}) {
    SCOPED_TRACE(std::string(name));
    const auto solver = make_direct_solver(name, a, perm);
    ASSERT_TRUE(solver->factor());
    std::vector<double> x(a.n, 1.0);
    solver->solve(x);
    int allocations;
    {
      const CountAllocations counting;
      solver->solve(x);
      solver->solve(x);
      allocations = CountAllocations::count;
    }
    EXPECT_EQ(allocations, 0);
  }
}

TEST(DirectSolvers, BlasInUseNamesALoadedLibrary) {
  // CHOLMOD links libblas.so.3, so dgemm_ is resolved in this process whichever BLAS the system
  // chose; the path is realpath's, symlinks followed, and OpenBLAS adds its configuration after
  // " (". Which BLAS it is depends on the machine and is not asserted.
  const std::string blas = blas_in_use();
  const std::string path = blas.substr(0, std::min(blas.find(" ("), blas.find("; ")));
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.front(), '/') << blas;
  EXPECT_TRUE(std::filesystem::is_regular_file(path)) << blas;
  EXPECT_NE(std::filesystem::path(path).filename().string().find(".so"), std::string::npos) << blas;
  EXPECT_EQ(blas_in_use(), blas);  // computed once
}

}  // namespace
}  // namespace ldlpgs
