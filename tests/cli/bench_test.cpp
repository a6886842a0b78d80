// `ldlpgs bench`: its fields, each solver's failure on a singular matrix, one thread, the kernels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsBench, JsonFields) {
  const Result r = run("bench heavy:5 --dense-max 10 --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"factor_us", "solve_us", "cholmod_factor_us", "cholmod_solve_us",
                          "cholmod_supernodal_factor_us", "eigen_simplicial_factor_us"})
    EXPECT_GT(j[key].get<double>(), 0) << key;
  EXPECT_TRUE(j["eigen_dense_factor_us"].is_null());  // n > --dense-max
  EXPECT_TRUE(j["failure"].is_null());
  EXPECT_TRUE(j["cholmod_failure"].is_null());
  EXPECT_GT(j["gflops"].get<double>(), 0);
  EXPECT_EQ(j["ordering"], "best");  // the default, and the one it chose
  EXPECT_TRUE(j["chosen"].is_string());
  for (const auto& item : j.items())  // ours, and each other solver's prefixed with its name
    if (item.key().ends_with("backward_error") && !item.value().is_null()) {
      EXPECT_LE(item.value().get<double>(), 1e-14) << item.key();
    }
}

TEST(LdlpgsBench, SingularMatrixNamesEachSolversFailure) {
  const std::string f = temp_file("singular.mtx", kSingular);
  const Result r = run("bench " + f + " --json");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("zero pivot at block 1 (row 1)"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["factor_us"].is_null());
  EXPECT_NE(j["failure"].get<std::string>().find("zero pivot at block 1 (row 1)"), std::string::npos) << j["failure"];
  for (const char* key : {"cholmod_failure", "cholmod_supernodal_failure"})
    EXPECT_NE(j[key].get<std::string>().find("at row 1,"), std::string::npos) << key << " " << j[key];
  EXPECT_TRUE(j["eigen_simplicial_failure"].is_string());
  const Result text = run("bench " + f);
  EXPECT_EQ(text.code, 1);
  EXPECT_NE(text.out.find("ldlpgs               failed to factor: zero pivot at block 1 (row 1)"), std::string::npos)
      << text.out;
}

// Eigen's dense LDLT accepts diag(1e-310) and solves to NaN: a failure, not a -nan backward error.
TEST(LdlpgsBench, ANonFiniteSolutionIsAFailure) {
  const std::string f = temp_file("subnormal.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n"
                                                   "1 1 1e-310\n2 2 1e-310\n3 3 1e-310\n");
  const Result r = run("bench " + f + " --json");
  ASSERT_EQ(r.code, 0) << r.err;  // ours factors it
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NE(j["eigen_dense_failure"].get<std::string>().find("not finite"), std::string::npos) << j;
  EXPECT_TRUE(j["backward_error"].is_number()) << j;
}

// CHOLMOD supernodal's parallel regions ask for 4 threads whatever OMP_NUM_THREADS says: bench
// restarts itself under OMP_THREAD_LIMIT=1, so that every solver runs on one core, and names the
// limit after the BLAS (peers/competitors.h). A limit the user set stands.
TEST(LdlpgsBench, EverySolverRunsOnOneThread) {
  struct Limit {  // OMP_THREAD_LIMIT for the program run within the scope (popen passes environ)
    explicit Limit(const char* value) {
      if (value) setenv("OMP_THREAD_LIMIT", value, 1);
      else unsetenv("OMP_THREAD_LIMIT");
    }
    ~Limit() { unsetenv("OMP_THREAD_LIMIT"); }
  };
  std::string blas, given;
  {
    const Limit none(nullptr);
    blas = json_of("bench chain:10 --dense-max 10 --json").value("blas", "");
  }
  {
    const Limit two("2");
    given = json_of("bench chain:10 --dense-max 10 --json").value("blas", "");
  }
  EXPECT_TRUE(blas.ends_with("; OpenMP thread limit 1")) << blas;
  EXPECT_TRUE(given.ends_with("; OpenMP thread limit 2")) << given;
}

TEST(LdlpgsBench, KernelsAreNamedAndChosen) {
  const Result r = run("bench chain:10 --kernels sse2 --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["kernels"], "sse2");
  const Result a = run("bench chain:10 --json");  // auto: whichever this CPU runs best
  ASSERT_EQ(a.code, 0) << a.err << a.out;
  const std::string isa = nlohmann::json::parse(a.out)["kernels"];
  EXPECT_TRUE(isa == "sse2" || isa == "avx2") << isa;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) {
    EXPECT_EQ(isa, "avx2");  // the best this CPU runs
  }
#endif
}

// OpenBLAS pinned to kernels older than the CPU (OPENBLAS_CORETYPE=Prescott, what OpenBLAS 0.3.21
// falls back to on CPUs it does not know): bench names them and warns on stderr.
TEST(LdlpgsBench, WarnsWhenOpenBlasRunsKernelsOlderThanTheCpu) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx")) GTEST_SKIP() << "this CPU has no AVX: Prescott's kernels are not older";
  setenv("OPENBLAS_CORETYPE", "Prescott", 1);
  const Result r = run("bench chain:10 --json");
  unsetenv("OPENBLAS_CORETYPE");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const std::string core = nlohmann::json::parse(r.out)["blas_core"];
  if (core.empty()) GTEST_SKIP() << "the BLAS in use is not OpenBLAS";
  EXPECT_EQ(core, "Prescott");
  EXPECT_NE(r.err.find("OpenBLAS runs its Prescott kernels"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("OPENBLAS_CORETYPE"), std::string::npos) << r.err;
#else
  GTEST_SKIP() << "not an x86-64 build";
#endif
}

}  // namespace
}  // namespace ldlpgs::testing
