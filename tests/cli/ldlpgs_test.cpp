// The command-line program, run as a user runs it: outputs checked against the library and
// CHOLMOD, and one named test per kind of bad input (one-line message naming the file, line
// and problem; exit code 2; no crash).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "ldlpgs/version.h"
#include "tests/support/temp_files.h"

namespace ldlpgs {
namespace {

using testing::temp_file;
using testing::temp_path;

struct Result {
  int code;
  std::string out, err;
};

Result run(const std::string& args) {
  const std::string err_path = temp_path("stderr.txt");
  const std::string cmd = std::string(LDLPGS_BIN) + " " + args + " 2>" + err_path;
  Result r{};
  FILE* pipe = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  while (size_t got = fread(buf.data(), 1, buf.size(), pipe)) r.out.append(buf.data(), got);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(err_path);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

const std::string kMatrices = LDLPGS_MATRICES;

// Bad input: exit code 2, one line on stderr that contains every fragment.
void expect_input_error(const std::string& args, std::initializer_list<std::string> fragments) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not one line: " << r.err;
  for (const std::string& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "'" << f << "' not in: " << r.err;
}

nlohmann::json json_of(const std::string& args) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

TEST(LdlpgsOrder, JsonEqualsLibraryAndCholmod) {
  const std::string file = kMatrices + "/bcsstk01.mtx";
  const Result r = run("order " + file + " --json --cholmod --ordering mda,meca,amd-scalar");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["matrix"], "bcsstk01.mtx");
  EXPECT_EQ(j["n"], 48);
  const SymmetricCsc a = read_matrix_market(file);
  const BlockPattern blocks = BlockPattern::from_scalar(a, partition_auto(a));
  EXPECT_EQ(j["blocks"], blocks.num_blocks());
  ASSERT_EQ(j["results"].size(), 3u);
  Cholmod cm;
  for (const auto& row : j["results"]) {
    const Ordering o = compute_ordering(find_ordering(row["ordering"].get<std::string>()), blocks, a);
    const CholmodCounts c = cholmod_counts(a, o.perm, cm);
    EXPECT_EQ(row["nnz_L"].get<double>(), c.lnz);
    EXPECT_EQ(row["flops"].get<double>(), c.fl);
    EXPECT_EQ(row["cholmod_nnz_L"].get<double>(), c.lnz);
    EXPECT_EQ(row["cholmod_flops"].get<double>(), c.fl);
    for (const char* key : {"block_fill_edges", "block_flops", "ordering_ms"}) EXPECT_TRUE(row.contains(key)) << key;
  }
  EXPECT_TRUE(j["results"][2]["block_flops"].is_null()) << "a scalar ordering has no block costs";
}

// --split-blocks (papers/orderings.md, "Block partitions that see inside blocks"): an exported
// scene stores its coupling blocks dense, about half of them exact zeros; the flag orders the
// matrix without them on refined blocks. Checked against the library's own pieces and CHOLMOD's
// counts, and verify agrees with CHOLMOD on it.
TEST(LdlpgsOrder, SplitBlocksOrdersTheNonzeroPatternOnRefinedBlocks) {
  const std::string mtx = temp_path("split.mtx"), blocks = temp_path("split.blocks");
  ASSERT_EQ(run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks).code, 0);
  const nlohmann::json whole = json_of("order " + mtx + " --blocks " + blocks + " --ordering meca-w --json");
  const nlohmann::json split = json_of("order " + mtx + " --blocks " + blocks + " --split-blocks --ordering meca-w --json");
  const SymmetricCsc stored = read_matrix_market(mtx);
  const SymmetricCsc a = without_zeros(stored);
  ASSERT_LT(a.nnz(), stored.nnz()) << "the export stores no exact zero: nothing to split";
  const BlockPattern refined = BlockPattern::from_scalar(a, partition_refine(a, read_partition(blocks, a.n)));
  EXPECT_EQ(split["blocks"], refined.num_blocks());
  EXPECT_GT(split["blocks"].get<int>(), whole["blocks"].get<int>());
  Cholmod cm;
  const CholmodCounts c = cholmod_counts(a, compute_ordering(find_ordering("meca-w"), refined, a).perm, cm);
  EXPECT_EQ(split["results"][0]["flops"].get<double>(), c.fl);
  EXPECT_LT(c.fl, whole["results"][0]["flops"].get<double>());
  const Result v = run("verify " + mtx + " --blocks " + blocks + " --split-blocks");
  EXPECT_EQ(v.code, 0) << v.out << v.err;
}

TEST(LdlpgsOrder, PermOutWritesEachPermutation) {
  const std::string dir = temp_path("perms");
  const Result r = run("order " + kMatrices + "/can___24.mtx --blocks 2 --ordering natural,metis --perm-dir " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"natural", "metis"}) {
    std::ifstream in(dir + "/" + name + ".perm");
    std::vector<int> perm;
    for (int x; in >> x;) perm.push_back(x);
    std::vector<int> sorted = perm;
    std::sort(sorted.begin(), sorted.end());
    ASSERT_EQ(sorted.size(), 24u) << name;
    for (int i = 0; i < 24; ++i) EXPECT_EQ(sorted[i], i);
    if (std::string(name) == "natural") {
      EXPECT_EQ(perm, sorted);
    }
    // Uniform blocks of 2: each block's rows stay together, in order.
    for (size_t k = 0; k < perm.size(); k += 2) EXPECT_EQ(perm[k] + 1, perm[k + 1]);
  }
}

TEST(LdlpgsOrder, TablePrintsEveryOrdering) {
  const Result r = run("order " + kMatrices + "/LFAT5.mtx");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const OrderingInfo& o : orderings()) {
    std::string line = "\n";  // (not "\n" + string: GCC 12 -O3 warns falsely there, bug 105329)
    line += o.name;
    line += " ";
    EXPECT_NE(r.out.find(line), std::string::npos) << o.name;
  }
}

TEST(LdlpgsOrder, HelpOnEverySubcommand) {
  for (const char* sub : {"", "order", "report", "verify", "bench", "step", "export", "spy", "sweep"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

TEST(LdlpgsVerify, JsonAgreesWithCholmod) {
  const Result r = run("verify " + kMatrices + "/bcsstk01.mtx --ordering amd --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"nnz_L", "cholmod_nnz_L", "flops", "cholmod_flops", "L_rel_diff", "D_rel_diff", "x_rel_diff",
                          "backward_error", "cholmod_backward_error", "ok"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["ok"].get<bool>());
  EXPECT_EQ(j["nnz_L"], j["cholmod_nnz_L"]);  // auto blocks of bcsstk01 are single rows
  EXPECT_EQ(j["ordering"], "amd");
  EXPECT_LE(j["L_rel_diff"].get<double>(), 1e-10);
  EXPECT_LE(j["backward_error"].get<double>(), 1e-14);
}

TEST(LdlpgsVerify, GeneratedMechanismTable) {
  const Result r = run("verify heavy:10");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("agree"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("heavy-10"), std::string::npos) << r.out;
}

TEST(LdlpgsVerify, DisagreementBeyondToleranceExitsOne) {
  // No tolerance at all: rounding alone makes the factors differ.
  const Result r = run("verify " + kMatrices + "/bcsstk02.mtx --tolerance 0 --per-condition 0");
  EXPECT_EQ(r.code, 1) << r.err << r.out;
  EXPECT_NE(r.out.find("DISAGREE"), std::string::npos) << r.out;
}

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

// A singular matrix is a numerical failure, not bad input (exit 1, not 2): diag(2, 0, 3) stops
// every sparse solver at row 1 whatever the order, and each says so in its own words (ours and
// CHOLMOD naming the row; tests/peers/competitors_test.cpp and numeric_test.cpp check the row in an
// order that is not the identity).
const char kSingular[] = "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 2\n2 2 0\n3 3 3\n";

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

TEST(LdlpgsVerify, SingularMatrixIsNotVerified) {
  const std::string f = temp_file("singular.mtx", kSingular);
  const Result r = run("verify " + f);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "");  // CHOLMOD's own warning is its status, not a line on stderr
  EXPECT_NE(r.out.find("NOT VERIFIED: ours failed (above); CHOLMOD stopped at a zero pivot in row 1"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << "differences of nothing compared: " << r.out;
  const Result json = run("verify " + f + " --json");
  EXPECT_EQ(json.code, 1);
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["status"], "zero pivot");
  EXPECT_EQ(j["cholmod_row"], 1);
  EXPECT_FALSE(j["ok"].get<bool>());
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

TEST(LdlpgsStep, JsonFieldsOnABuiltInScene) {
  const Result r = run("step heavy-chain-10-1000 --steps 50 --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"steps", "solver", "iterations", "solve_us", "position_error_max_m", "angular_error_max_rad",
                          "velocity_residual_max", "energy_initial_j", "energy_final_j"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["steps"], 50);
  EXPECT_EQ(j["solver"], "ldl-pgs");
  EXPECT_GT(j["solve_us"].get<double>(), 0);
  EXPECT_LT(j["position_error_max_m"].get<double>(), 1e-3);
}

TEST(LdlpgsStep, TraceHasOneRowPerStepAndBody) {
  const std::string trace = temp_path("trace.csv");
  const Result r = run("step pendulum --steps 7 --solver direct --trace-file " + trace);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  std::ifstream in(trace);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "step,time,body,x,y,z,qw,qx,qy,qz,fx,fy,fz,tx,ty,tz");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  const Result j = run("step pendulum --steps 1 --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(rows, 8 * nlohmann::json::parse(j.out)["bodies"].get<int>());  // steps 0..7, every body
}

// A driven scene says what drives it: the crank's torque in the text, the JSON and the trace.
TEST(LdlpgsStep, PrintsAndTracesTheScenesLoads) {
  const Result text = run("step driven-crank --steps 3");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("applied loads         1 bodies, largest force 0 N, largest torque 1 N m"), std::string::npos)
      << text.out;
  const Result j = run("step driven-crank --steps 3 --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(nlohmann::json::parse(j.out)["loaded_bodies"], 1);
  EXPECT_EQ(nlohmann::json::parse(j.out)["applied_torque_max_nm"], 1.0);
  const std::string trace = temp_path("crank.csv");
  ASSERT_EQ(run("step driven-crank --steps 1 --trace-file " + trace).code, 0);
  std::ifstream in(trace);
  std::string line;
  bool torque = false;
  while (std::getline(in, line)) torque = torque || line.find(",0,0,0,0,0,1") != std::string::npos;
  EXPECT_TRUE(torque) << "no trace row carries the crank's torque (0, 0, 1) N m";
}

TEST(LdlpgsExport, MatrixVerifiesAgainstCholmod) {
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  const Result r = run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const SymmetricCsc h = read_matrix_market(mtx);
  const std::vector<int> sizes = read_partition(blocks, h.n);
  EXPECT_EQ(h.n, 200);  // the talk's tracked vehicle: 40 hinges, dim(H) = 200
  EXPECT_EQ(sizes.size(), 40u);
  const Result v = run("verify " + mtx + " --blocks " + blocks + " --json");
  ASSERT_EQ(v.code, 0) << v.err << v.out;
  EXPECT_TRUE(nlohmann::json::parse(v.out)["ok"].get<bool>());
}

TEST(LdlpgsBadInput, UnknownScene) { expect_input_error("step no-such-scene", {"no-such-scene", "built-in"}); }

TEST(LdlpgsBadInput, UnknownKernels) { expect_input_error("bench chain:10 --kernels avx512", {"--kernels", "avx512"}); }
TEST(LdlpgsBadInput, SmallSupernodeRowsBelowOne) {
  expect_input_error("bench chain:10 --small-supernode-max-rows 0", {"--small-supernode-max-rows", "must be an integer in [1, 1048576]"});
}

TEST(LdlpgsBadInput, RelaxMaxZerosOutsideZeroToOne) {
  expect_input_error("bench chain:10 --relax-max-zeros 1.5", {"--relax-max-zeros", "must be a finite number in [0, 1]"});
}

TEST(LdlpgsBadInput, DirectSolverOnAContactScene) {
  expect_input_error("step pyramid-2 --solver direct", {"direct", "body \"ground\"", "shapes"});
}
TEST(LdlpgsBadInput, UnknownFrictionCone) {
  expect_input_error("step box-stack-1000 --friction-cone cone", {"--friction-cone", "cone", "disk pyramid"});
}
TEST(LdlpgsBadInput, UnknownContactSchedule) {
  expect_input_error("step box-stack-1000 --contact-schedule fast", {"--contact-schedule", "fast", "block-gs"});
}
TEST(LdlpgsBadInput, FactorContactsAfterNegative) {
  expect_input_error("step box-stack-1000 --factor-contacts-after -1", {"--factor-contacts-after"});
}
TEST(LdlpgsBadInput, UnknownSolver) { expect_input_error("step pendulum --solver magic", {"--solver", "magic", "ldl-pgs"}); }

TEST(LdlpgsBadInput, DirectOnInequalities) {
  expect_input_error("step ragdoll --solver direct", {"direct", "ragdoll", "angular_limit"});
}

TEST(LdlpgsBadInput, NonPositiveTimestep) { expect_input_error("step pendulum --timestep -1", {"--timestep"}); }

TEST(LdlpgsBadInput, SceneWithUnknownBody) {
  const std::string path = temp_file("bad.json", R"({"name": "bad", "bodies": [{"name": "a", "mass": 1,
    "inertia": [1, 1, 1], "position": [0, 0, 0]}], "constraints": [{"type": "ball", "bodies": ["a", "ghost"],
    "anchor": [0, 0, 0]}]})");
  expect_input_error("step " + path, {"bad.json", "constraints[0]", "ghost"});
}

TEST(LdlpgsBadInput, SceneWithZeroMass) {
  const std::string path = temp_file("zero.json", R"({"name": "z", "bodies": [{"name": "a", "mass": 0,
    "inertia": [1, 1, 1], "position": [0, 0, 0]}], "constraints": []})");
  expect_input_error("export " + path + " --matrix-file x.mtx --blocks-file x.blocks", {"zero.json", "bodies[0]", "mass"});
}

TEST(LdlpgsBadInput, UnknownFamily) {
  expect_input_error("verify wheel:10", {"wheel", "chain"});
}

TEST(LdlpgsBadInput, BadConstraintCount) {
  expect_input_error("bench chain:-3", {"chain:-3", "positive"});
}

TEST(LdlpgsBadInput, VerifyUnsymmetricMatrix) {
  expect_input_error("verify " + kMatrices + "/Pd.mtx", {"Pd.mtx:", "not symmetric"});
}

TEST(LdlpgsBadInput, MissingFile) {
  expect_input_error("order /nonexistent/m.mtx", {"/nonexistent/m.mtx", "cannot open"});
}

TEST(LdlpgsBadInput, MalformedMatrixMarket) {
  const std::string f = temp_file("bad.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 x\n2 2 1\n");
  expect_input_error("order " + f, {f + ":3:"});
}

TEST(LdlpgsBadInput, TruncatedMatrixMarket) {
  const std::string f = temp_file("short.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 1\n2 2 1\n");
  expect_input_error("order " + f, {f, "3"});
}

TEST(LdlpgsBadInput, UnsymmetricMatrix) {
  expect_input_error("order " + kMatrices + "/Pd.mtx", {"Pd.mtx:", "not symmetric"});
}

TEST(LdlpgsBadInput, NanValue) {
  const std::string f = temp_file("nan.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 nan\n2 2 1\n");
  expect_input_error("order " + f, {f + ":3:"});
}

TEST(LdlpgsBadInput, BlockFileDoesNotSumToN) {
  const std::string blocks = temp_file("blocks.txt", "6\n6\n6\n");
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks, {blocks, "18", "48"});
}

TEST(LdlpgsBadInput, BlockFileBadLine) {
  const std::string blocks = temp_file("blocks.txt", "6\nsix\n");
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks, {blocks + ":2:"});
}

TEST(LdlpgsBadInput, ZeroBlockSize) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --blocks 0", {"0"});
}

TEST(LdlpgsBadInput, UnknownOrdering) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --ordering mda,colamd", {"colamd", "meca"});
}

TEST(LdlpgsBadInput, NegativeCertifyTimeLimit) {
  expect_input_error("order chain:5 --certify --certify-time-limit-s -1", {"--certify-time-limit-s"});
}

TEST(LdlpgsBadInput, UnknownOption) {
  expect_input_error("order " + kMatrices + "/bcsstk01.mtx --frobnicate", {"frobnicate"});
}

TEST(LdlpgsBadInput, ReportMatricesDirectoryMissing) {
  expect_input_error("report --matrices /nonexistent/dir --sizes 10", {"/nonexistent/dir"});
}

// ---- spy ----

namespace spy_test {

// `ldlpgs spy ARGS --json-file FILE`, FILE parsed.
nlohmann::json spy(const std::string& args) {
  const std::string out = temp_path("spy.json");
  const Result r = run("spy " + args + " --json-file " + out);
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  EXPECT_NE(r.out.find("dim(H)"), std::string::npos) << r.out;
  std::ifstream in(out);
  return nlohmann::json::parse(in);
}

using BlockSet = std::set<std::pair<int, int>>;  // (row, column) block pairs, pivot order

BlockSet h_blocks(const nlohmann::json& j) {
  BlockSet h;
  for (const auto& b : j["H_blocks"]) h.insert({b[0].get<int>(), b[1].get<int>()});
  return h;
}

// The file checked against itself and against a brute-force elimination game on its own H:
// pivots, sizes, density, L = H plus fill (a fill block is exactly a block of L not in H), and nnz(L)
// and flops as metrics.h counts them for dense blocks, column by column.
void expect_consistent(const nlohmann::json& j) {
  const std::vector<int> sizes = j["block_sizes"].get<std::vector<int>>();
  const int np = static_cast<int>(sizes.size()), dim = j["n"].get<int>();
  // a scalar ordering (amd-scalar, metis-scalar) pivots on single rows
  EXPECT_EQ(j["ordering"].get<std::string>().ends_with("-scalar") ? dim : j["constraints"].get<int>(), np);
  int rows = 0;
  for (int size : sizes) rows += size;
  EXPECT_EQ(rows, dim);
  std::vector<int> pivots = j["pivots"].get<std::vector<int>>();
  std::sort(pivots.begin(), pivots.end());
  for (int k = 0; k < np; ++k) EXPECT_EQ(pivots[k], k) << "pivots is not a permutation";

  const BlockSet h = h_blocks(j);
  EXPECT_EQ(h.size(), j["H_blocks"].size()) << "duplicate H blocks";
  int64_t entries = 0;
  std::vector<std::set<int>> below(np);  // row blocks below the diagonal, per column
  for (int k = 0; k < np; ++k) EXPECT_TRUE(h.count({k, k})) << "no diagonal block " << k;
  for (const auto& [i, k] : h) {
    ASSERT_TRUE(i >= k && i < np) << i << ", " << k;
    entries += (i == k ? 1 : 2) * int64_t{sizes[i]} * sizes[k];
    if (i != k) below[k].insert(i);
  }
  EXPECT_NEAR(j["density"].get<double>(), static_cast<double>(entries) / (double(dim) * dim), 1e-15);

  BlockSet expected;  // the elimination game: a pivot's neighbours after it become a clique
  int64_t nnz = 0;
  double flops = 0;
  for (int k = 0; k < np; ++k) {
    expected.insert({k, k});
    int64_t height = 0;
    for (int i : below[k]) {
      expected.insert({i, k});
      height += sizes[i];
      for (int l : below[k])
        if (l > i) below[i].insert(l);
    }
    const int64_t d = sizes[k];
    nnz += d * (d + 1) / 2 + height * d;
    flops += static_cast<double>(d * (d + 1) * (2 * d + 1) / 6 + height * d * (d + 1) + d * height * height);
  }
  BlockSet l;
  int64_t fill = 0;
  for (const auto& b : j["L_blocks"]) {
    const int i = b[0].get<int>(), k = b[1].get<int>();
    const bool is_fill = b[2].get<bool>();
    l.insert({i, k});
    EXPECT_EQ(is_fill, !h.count({i, k})) << "L block " << i << ", " << k;
    fill += is_fill;
  }
  EXPECT_EQ(l.size(), j["L_blocks"].size()) << "duplicate L blocks";
  for (const auto& b : h) EXPECT_TRUE(l.count(b)) << "H block " << b.first << ", " << b.second << " not in L";
  EXPECT_EQ(l, expected);
  EXPECT_EQ(j["fill_blocks"].get<int64_t>(), fill);
  EXPECT_EQ(j["nnz_L"].get<int64_t>(), nnz);
  EXPECT_EQ(j["flops"].get<double>(), flops);
}

}  // namespace spy_test

TEST(LdlpgsSpy, FieldsAndConsistencyOnEveryTalkScene) {
  for (const char* args : {"mechanism-50 --no-shatter", "mechanism-50", "tracked-vehicle", "multi-wheeled-vehicle",
                           "multi-wheeled-vehicle --no-shatter", "multi-wheeled-vehicle --shards 10",
                           "tracked-vehicle --ordering amd", "four-bar --ordering amd-scalar"}) {
    SCOPED_TRACE(args);
    const nlohmann::json j = spy_test::spy(args);
    for (const char* key : {"scene", "shattered", "constraints", "n", "density", "flops", "nnz_L", "ordering",
                            "pivots", "block_sizes", "H_blocks", "L_blocks"})
      EXPECT_TRUE(j.contains(key)) << key;
    spy_test::expect_consistent(j);
  }
}

TEST(LdlpgsSpy, MechanismFiftyHasTheTalksSize) {
  const nlohmann::json j = spy_test::spy("mechanism-50 --no-shatter");
  EXPECT_EQ(j["scene"], "mechanism-50");
  EXPECT_FALSE(j["shattered"].get<bool>());
  EXPECT_EQ(j["constraints"], 50);  // the talk's: 50 constraints, dim(H) = 246, 12% dense
  EXPECT_EQ(j["n"], 246);
  EXPECT_NEAR(j["density"].get<double>(), 0.12, 0.005);
  EXPECT_EQ(j["ordering"], "best");
  EXPECT_TRUE(j["chosen"].is_string());
}

TEST(LdlpgsSpy, TrackedVehicleAgainstExportAndCholmod) {
  // H's blocks are those of the exported matrix, renumbered by the pivots; nnz(L) and flops are
  // CHOLMOD's for the scalar permutation they expand to (H's blocks are dense).
  const nlohmann::json j = spy_test::spy("tracked-vehicle --no-shatter");
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  const Result r = run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  const SymmetricCsc a = read_matrix_market(mtx);
  const std::vector<int> sizes = read_partition(blocks, a.n);
  ASSERT_EQ(j["n"].get<int>(), a.n);
  std::vector<int> block_of_row, first_row;
  for (size_t b = 0; b < sizes.size(); ++b) {
    first_row.push_back(static_cast<int>(block_of_row.size()));
    block_of_row.insert(block_of_row.end(), sizes[b], static_cast<int>(b));
  }
  const std::vector<int> pivots = j["pivots"].get<std::vector<int>>();
  ASSERT_EQ(pivots.size(), sizes.size());
  std::vector<int> position(pivots.size()), perm;
  for (size_t k = 0; k < pivots.size(); ++k) {
    position[pivots[k]] = static_cast<int>(k);
    EXPECT_EQ(j["block_sizes"][k].get<int>(), sizes[pivots[k]]);
    for (int r = 0; r < sizes[pivots[k]]; ++r) perm.push_back(first_row[pivots[k]] + r);
  }
  spy_test::BlockSet from_matrix;
  int64_t full = 0;
  for (int c = 0; c < a.n; ++c)
    for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p) {
      const int i = position[block_of_row[a.row_idx[p]]], k = position[block_of_row[c]];
      from_matrix.insert({std::max(i, k), std::min(i, k)});
      full += a.row_idx[p] == c ? 1 : 2;
    }
  EXPECT_EQ(spy_test::h_blocks(j), from_matrix);
  EXPECT_DOUBLE_EQ(j["density"].get<double>(), static_cast<double>(full) / (double(a.n) * a.n));
  Cholmod cm;
  const CholmodCounts c = cholmod_counts(a, perm, cm);
  EXPECT_EQ(j["nnz_L"].get<double>(), c.lnz);
  EXPECT_EQ(j["flops"].get<double>(), c.fl);
}

TEST(LdlpgsSpy, WholeMultiWheeledVehicleIsDense) {
  const nlohmann::json j = spy_test::spy("multi-wheeled-vehicle --no-shatter");
  EXPECT_FALSE(j["shattered"].get<bool>());
  EXPECT_TRUE(j["shatter_threshold"].is_null());
  EXPECT_EQ(j["constraints"], 20);
  EXPECT_EQ(j["n"], 88);
  EXPECT_EQ(j["density"].get<double>(), 1.0);
  EXPECT_EQ(j["H_blocks"].size(), 20u * 21 / 2);  // every pair of wheels shares the chassis
  EXPECT_EQ(j["fill_blocks"], 0);                  // a dense matrix has nothing to fill
}

TEST(LdlpgsSpy, ShatteringTheMultiWheeledVehicle) {
  const nlohmann::json whole = spy_test::spy("multi-wheeled-vehicle --no-shatter");
  const nlohmann::json chosen = spy_test::spy("multi-wheeled-vehicle");  // --shatter 20: k by flops
  EXPECT_TRUE(chosen["shattered"].get<bool>());
  EXPECT_EQ(chosen["shatter_threshold"], 20);
  EXPECT_EQ(chosen["shattered_bodies"], 1);  // the chassis, of 88 rows; a wheel has 4 or 5
  const int welds = chosen["welds"].get<int>();
  EXPECT_EQ(chosen["constraints"].get<int>(), 20 + welds);
  EXPECT_EQ(chosen["n"].get<int>(), 88 + 6 * welds);
  EXPECT_LT(chosen["density"].get<double>(), 1.0);
  EXPECT_LT(chosen["flops"].get<double>(), whole["flops"].get<double>() / 4);
  // the talk's shattered vehicle: 29 constraints, dim(H) 142, density 17.5%: ten shards
  const nlohmann::json ten = spy_test::spy("multi-wheeled-vehicle --shards 10");
  EXPECT_EQ(ten["welds"], 9);
  EXPECT_EQ(ten["constraints"], 29);
  EXPECT_EQ(ten["n"], 142);
  EXPECT_NEAR(ten["density"].get<double>(), 0.175, 0.0005);
}

TEST(LdlpgsSpy, SceneOutIsTheMechanismSpied) {
  const std::string scene = temp_path("shattered.json"), mtx = temp_path("s.mtx"), blocks = temp_path("s.blocks");
  const nlohmann::json j = spy_test::spy("multi-wheeled-vehicle --shards 10 --scene-file " + scene);
  const Result r = run("export " + scene + " --no-shatter --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  const SymmetricCsc a = read_matrix_market(mtx);
  EXPECT_EQ(a.n, j["n"].get<int>());
  EXPECT_EQ(read_partition(blocks, a.n).size(), j["block_sizes"].size());
  const Result help = run("spy --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--no-shatter"), std::string::npos);
}

// Shattering is on by default in step and export too (apps/shatter_args.h).

// The trace names the scene's own bodies, shattered or not, and they move alike: the shards'
// whole_body against the whole body, 0.2 s of direct steps. Bound: 1e-4 m, what
// tests/physics/shatter_test.cpp measures and bounds for this vehicle over a whole second (6.5e-5 m).
TEST(LdlpgsStep, ShatteredSceneTracesTheScenesBodies) {
  const std::string whole = temp_path("whole.csv"), shattered = temp_path("shattered.csv");
  const Result a = run("step multi-wheeled-vehicle --solver direct --steps 20 --no-shatter --trace-file " + whole + " --json");
  const Result b = run("step multi-wheeled-vehicle --solver direct --steps 20 --trace-file " + shattered + " --json");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  const nlohmann::json ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja["shattered_bodies"], 0);
  EXPECT_EQ(jb["shattered_bodies"], 1);  // the chassis
  EXPECT_EQ(jb["bodies"].get<int>(), 21 + jb["welds"].get<int>());
  std::ifstream ta(whole), tb(shattered);
  std::string la, lb;
  int rows = 0;
  double largest = 0;
  while (std::getline(ta, la)) {
    ASSERT_TRUE(std::getline(tb, lb)) << "the shattered trace is shorter";
    if (rows++ == 0) continue;  // header
    std::vector<std::string> fa, fb;
    std::stringstream sa(la), sb(lb);
    for (std::string f; std::getline(sa, f, ',');) fa.push_back(f);
    for (std::string f; std::getline(sb, f, ',');) fb.push_back(f);
    ASSERT_EQ(fa.size(), 16u);
    ASSERT_EQ(fb.size(), 16u);
    EXPECT_EQ(fa[2], fb[2]);  // the same body
    for (int x = 3; x < 6; ++x) largest = std::max(largest, std::abs(std::stod(fa[x]) - std::stod(fb[x])));
  }
  EXPECT_FALSE(std::getline(tb, lb)) << "the shattered trace is longer";
  EXPECT_EQ(rows, 1 + 21 * 21);  // steps 0..20, the scene's 21 bodies
  std::printf("largest coordinate difference of a body, shattered against whole, 20 steps: %.3e m\n", largest);
  EXPECT_LT(largest, 1e-4);
}

// export writes the H that step factors: shattered by default, the talk's 142 with --shards 10,
// the dense 88 x 88 with --no-shatter; each verifies against CHOLMOD.
TEST(LdlpgsExport, ShatterOptions) {
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  for (auto [options, dim] : std::vector<std::pair<std::string, int>>{{"--no-shatter", 88}, {"--shards 10", 142}, {"", -1}}) {
    const Result r = run("export multi-wheeled-vehicle " + options + " --matrix-file " + mtx + " --blocks-file " + blocks);
    ASSERT_EQ(r.code, 0) << r.err;
    const SymmetricCsc h = read_matrix_market(mtx);
    const std::vector<int> sizes = read_partition(blocks, h.n);
    if (dim > 0) {
      EXPECT_EQ(h.n, dim) << options;
    } else {
      EXPECT_EQ(h.n, 88 + 6 * (static_cast<int>(sizes.size()) - 20)) << "default: 20 constraints and welds";
    }
    const Result v = run("verify " + mtx + " --blocks " + blocks + " --json");
    ASSERT_EQ(v.code, 0) << v.err << v.out;
    EXPECT_TRUE(nlohmann::json::parse(v.out)["ok"].get<bool>()) << options;
  }
}

TEST(LdlpgsBadInput, StepShardsOutOfRange) {
  expect_input_error("step multi-wheeled-vehicle --shards 65", {"--shards", "must be an integer in [2, 64]"});
}

TEST(LdlpgsBadInput, ExportShatterThresholdBelowOne) {
  expect_input_error("export mechanism-50 --shatter 0 --matrix-file x.mtx --blocks-file x.blocks", {"--shatter"});
}

// ---- sweep and report ----

nlohmann::json sweep_points(const std::string& args) {
  const std::string file = temp_path("sweep.json");
  const Result r = run("sweep " + args + " --json-file " + file);
  EXPECT_EQ(r.code, 0) << r.err;
  std::ifstream in(file);
  return nlohmann::json::parse(in)["points"];
}

const nlohmann::json& point(const nlohmann::json& points, const std::string& solver, int iterations) {
  for (const auto& p : points)
    if (p["solver"] == solver && p["iterations"] == iterations) return p;
  ADD_FAILURE() << solver << " " << iterations << " not in the sweep";
  return points[0];
}

// The sweep's runs are the step command's: the same scene, solver and steps (1 s of 10 ms steps)
// give the same largest error; a run the sweep calls an energy blow-up gains energy in the step
// command too (one PGS sweep a step pumps energy into the chain: -245 J to 8114 J). More PGS
// sweeps bring the error down.
TEST(LdlpgsSweep, PointsAreTheStepCommandsRuns) {
  const nlohmann::json points = sweep_points("--cases chain-10 --iterations 1,64");
  ASSERT_EQ(points.size(), 7u);  // pgs, block-gs, ldl-pgs at two counts, direct
  for (const auto& p : points) {
    const std::string solver = p["solver"].get<std::string>(), iterations = std::to_string(p["iterations"].get<int>());
    const Result r = run("step chain-10 --no-shatter --steps 100 --json --solver " + solver + " --iterations " + iterations);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const double e0 = j["energy_initial_j"].get<double>(), e1 = j["energy_final_j"].get<double>();
    if (p["failure"] == "energy") {
      EXPECT_GT(e1 - e0, 100) << solver << " " << iterations;
    }
    if (!p["failed"].get<bool>()) {
      EXPECT_DOUBLE_EQ(p["position_error_max_m"].get<double>(), j["position_error_max_m"].get<double>()) << solver << " " << iterations;
    }
  }
  EXPECT_TRUE(point(points, "pgs", 1)["failed"].get<bool>());
  EXPECT_LT(point(points, "pgs", 64)["position_error_m"].get<double>(), 1e-6);
  EXPECT_LT(point(points, "ldl-pgs", 1)["position_error_m"].get<double>(), 1e-6);
}

// A 1:1000 load tears a PGS chain apart at 4 sweeps (energy blow-up: the sweep marks it failed)
// and LDL-PGS holds it at one; raising the ratio breaks PGS first.
TEST(LdlpgsSweep, FailuresAndStability) {
  const nlohmann::json points = sweep_points("--cases heavy-chain-10-1000 --iterations 1,4");
  EXPECT_TRUE(point(points, "pgs", 4)["failed"].get<bool>());
  EXPECT_TRUE(point(points, "pgs", 4)["position_error_m"].is_null());
  EXPECT_FALSE(point(points, "ldl-pgs", 1)["failed"].get<bool>());
  EXPECT_LT(point(points, "ldl-pgs", 1)["position_error_m"].get<double>(), 1e-6);
  const Result r = run("sweep --cases chain-10 --iterations 1 --seconds 0.5 --stability");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| chain-10 | ldl-pgs | 10 |"), std::string::npos) << r.out;
}

TEST(LdlpgsReport, WritesTheReportDirectory) {
  const std::string dir = temp_path("report"), matrices = temp_path("matrices");
  std::filesystem::create_directories(matrices);
  std::filesystem::copy_file(kMatrices + "/bcsstk01.mtx", matrices + "/bcsstk01.mtx",
                             std::filesystem::copy_options::overwrite_existing);
  const Result r = run("report --sizes 12 --cases chain-10,four-bar --matrices " + matrices + " --out-dir " + dir +
                       " --no-figures");
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(dir + "/index.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string index = ss.str();
  for (const char* section : {"## 1. Orderings", "## 2. The block LDL^T against CHOLMOD", "## 3. The talk's figures",
                              "## 4. Speed against error", "## 5. Where each solver breaks", "bcsstk01.mtx", "chain-12",
                              "| four-bar | ldl-pgs |"})
    EXPECT_NE(index.find(section), std::string::npos) << section;
  EXPECT_NE(r.err.find("report [5/5]"), std::string::npos) << "no progress line: " << r.err;
  EXPECT_LT(index.find("## Key findings"), index.find("## 1. Orderings")) << "the findings open the report";
  for (const char* paper : {"papers/orderings.md", "papers/factor.md", "papers/speed-vs-error.md"})
    EXPECT_NE(index.find(paper), std::string::npos) << paper;
  for (const char* table : {"orderings", "verification", "sweep", "stability"}) {
    std::ifstream json(dir + "/data/" + table + ".json");
    const nlohmann::json rows = nlohmann::json::parse(json)["records"];
    EXPECT_FALSE(rows.empty()) << table;
    // the CSV: a header and one line per row
    std::ifstream csv(dir + "/data/" + table + ".csv");
    int lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, static_cast<int>(rows.size()) + 1) << table;
  }
}

// A matrix a solver refuses is not verified, and said so: not a disagreement, no NaN in the table.
TEST(LdlpgsReport, ARefusedMatrixIsNotVerified) {
  const std::string dir = temp_path("report-refused"), matrices = temp_path("matrices-refused");
  std::filesystem::create_directories(matrices);
  std::filesystem::copy_file(temp_file("singular.mtx", kSingular), matrices + "/singular.mtx",
                             std::filesystem::copy_options::overwrite_existing);
  const Result r = run("report --sizes 10 --cases four-bar --ordering meca --matrices " + matrices + " --out-dir " +
                       dir + " --no-figures");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.out.find("NOT ALL AGREE: 1 not verified (a solver refused the matrix)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("disagree"), std::string::npos) << r.out;
  const size_t row = r.out.find("singular.mtx     best");
  ASSERT_NE(row, std::string::npos) << r.out;
  const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
  EXPECT_NE(line.find("NOT VERIFIED"), std::string::npos) << line;
  EXPECT_EQ(line.find("nan"), std::string::npos) << line;
  std::ifstream in(dir + "/index.md");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("| singular.mtx | best | - | - | - | - | - | - | - | **not verified** |"), std::string::npos);
  EXPECT_NE(ss.str().find("problems agree within max(1e-10, eps cond_1); the largest relative difference of L, D or x is "), std::string::npos);
  EXPECT_NE(ss.str().find("; 1 not verified (a solver refused the matrix) (`"), std::string::npos);
}

// Number options: NaN, infinities and values out of range are refused in one short line naming
// the option (CLI11's own checks let nan through and spelt out DBL_MAX in 310 digits).
TEST(LdlpgsBadInput, BenchNumberOptionsOutOfRange) {
  expect_input_error("bench chain:10 --relax-max-zeros nan", {"--relax-max-zeros", "finite number in [0, 1]"});
  expect_input_error("bench chain:10 --rsi-max-per-entry inf", {"--rsi-max-per-entry", "finite number"});
  const Result r = run("bench chain:10 --supernode-min-rows -1");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.err.size(), 120u) << r.err;
  EXPECT_NE(r.err.find("--supernode-min-rows: '-1': must be an integer in [0, "), std::string::npos) << r.err;
}

TEST(LdlpgsBadInput, VerifyToleranceNotFinite) {
  expect_input_error("verify chain:10 --backward-tolerance inf", {"--backward-tolerance", ">= 0"});
  expect_input_error("verify chain:10 --tolerance nan", {"--tolerance"});
  expect_input_error("verify chain:10 --per-condition -1", {"--per-condition"});
}

// 0 and -1 had been read as "the default" (the scene's timestep, 8 iterations, shards by flops).
TEST(LdlpgsBadInput, StepZeroTimestep) { expect_input_error("step pendulum --timestep 0", {"--timestep", "> 0"}); }
TEST(LdlpgsBadInput, StepNegativePostStabilize) {
  expect_input_error("step pendulum --post-stabilize -1", {"--post-stabilize"});
}
TEST(LdlpgsBadInput, ZeroShards) {
  expect_input_error("spy chain-10 --shards 0 --json-file " + temp_path("x.json"), {"--shards", "[2, 64]"});
}

// nan, inf and 1e308 had run one step each and said "failed: energy" with exit 0.
TEST(LdlpgsBadInput, SweepSecondsOutOfRange) {
  for (const char* s : {"nan", "0", "1e308"}) expect_input_error(std::string("sweep --cases chain-10 --seconds ") + s, {"--seconds"});
}

// 1e308 s overflowed the step count (0 steps, NaN printed); 1e-300 s is less than one step.
TEST(LdlpgsBadInput, PeersSecondsOutsideTheSteps) {
  expect_input_error("peers pendulum --seconds 1e308", {"--seconds", "at most 10^6"});
  expect_input_error("peers pendulum --seconds 1e-300", {"--seconds", "at least 1"});
}

// A full disk shows only when the stream flushes: these had exited 0 with an empty file.
TEST(LdlpgsBadInput, WriteToAFullDevice) {
  expect_input_error("spy chain-10 --json-file /dev/full", {"/dev/full", "cannot write"});
  expect_input_error("step pendulum --steps 3 --trace-file /dev/full", {"/dev/full", "cannot write"});
  expect_input_error("export chain-10 --matrix-file " + temp_path("full.mtx") + " --blocks-file /dev/full",
                     {"/dev/full", "cannot write"});
}

// A generated mechanism has one block per constraint: a partition given for it had been ignored.
TEST(LdlpgsBadInput, PartitionOptionsOnAGeneratedMechanism) {
  expect_input_error("order grid:10 --blocks 0", {"grid:10", "--blocks 0"});
  expect_input_error("verify grid:10 --max-block 3", {"grid:10", "--max-block"});
}

// export had written a 0 x 0 matrix that order then refused.
TEST(LdlpgsBadInput, ExportWithoutEqualityConstraints) {
  const std::string scene = temp_file("no-constraints.json", R"({"name": "empty", "bodies": [], "constraints": []})");
  expect_input_error("export " + scene + " --matrix-file " + temp_path("e.mtx") + " --blocks-file " + temp_path("e.blocks"),
                     {"no equality constraints"});
}

// Standard output on a full disk: found only when flushed at the end, and had been exit 0.
TEST(LdlpgsBadInput, StandardOutputOnAFullDevice) {
  expect_input_error("order chain:10 --json >/dev/full", {"cannot write standard output"});
}

TEST(LdlpgsBadInput, ReportEmptyOutDir) {
  expect_input_error("report --sizes 10 --cases pendulum --no-figures --out-dir ''", {"--out-dir"});
}

TEST(LdlpgsBadInput, SweepUnknownScene) { expect_input_error("sweep --cases no-such-scene", {"no-such-scene"}); }

TEST(LdlpgsBadInput, SweepZeroIterations) { expect_input_error("sweep --cases chain-10 --iterations 0", {"--iterations"}); }

TEST(LdlpgsBadInput, ReportUnknownCase) {
  expect_input_error("report --sizes 12 --cases no-such-scene --no-figures --out-dir " + temp_path("r"), {"no-such-scene"});
}

TEST(LdlpgsBadInput, ReportUnwritableDirectory) {
  expect_input_error("report --sizes 12 --out-dir /proc/no-such-report --no-figures", {"/proc/no-such-report"});
}

TEST(LdlpgsBadInput, SpyUnknownScene) { expect_input_error("spy no-such-scene --json-file x.json", {"no-such-scene"}); }

TEST(LdlpgsBadInput, SpyShatterThresholdBelowOne) {
  expect_input_error("spy mechanism-50 --shatter 0 --json-file " + temp_path("x.json"), {"--shatter"});
}

TEST(LdlpgsBadInput, SpyShardsOutOfRange) {
  expect_input_error("spy multi-wheeled-vehicle --shards 1 --json-file " + temp_path("x.json"), {"--shards", "must be an integer in [2, 64]"});
}

TEST(LdlpgsBadInput, SpyShatterAndNoShatter) {
  expect_input_error("spy mechanism-50 --shatter 5 --no-shatter --json-file " + temp_path("x.json"),
                     {"--shatter", "--no-shatter"});
}

TEST(LdlpgsBadInput, SpyUnwritableOutput) {
  expect_input_error("spy pendulum --out /nonexistent/dir/spy.json", {"/nonexistent/dir/spy.json", "cannot write"});
}

TEST(LdlpgsBadInput, SpySceneWithoutEqualityConstraints) {
  const std::string path = temp_file("ropes.json", R"({"name": "ropes", "bodies": [{"name": "post", "static": true,
    "position": [0, 0, 0]}, {"name": "bob", "mass": 1, "inertia": [1, 1, 1], "position": [0, -1, 0]}],
    "constraints": [{"type": "rope", "bodies": ["post", "bob"], "anchors": [[0, 0, 0], [0, -1, 0]]}]})");
  expect_input_error("spy " + path + " --out " + temp_path("x.json"), {"ropes.json", "no equality constraints"});
}

// MJCF models (physics/mjcf.h): step and export load them by their .xml extension, and say once
// on stderr what was dropped. Built with MuJoCo (build.sh requires it and libmujoco-samples'
// models), or refusing every MJCF file without it.
#ifdef LDLPGS_HAVE_MUJOCO

const std::string kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";

TEST(LdlpgsStep, MjcfHumanoid) {
  ASSERT_TRUE(std::filesystem::exists(kHumanoid)) << kHumanoid << " missing (libmujoco-samples)";
  const Result r = run("step " + kHumanoid + " --no-shatter --steps 50 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line of what was dropped: " << r.err;
  EXPECT_NE(r.err.find("dropped: 21 actuators"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("geoms"), std::string::npos) << "every geom of the humanoid is a shape: " << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["bodies"], 17) << "16 bodies and the world";
  EXPECT_LT(j["position_error_max_m"].get<double>(), 1e-6) << "falling at rest";
}

TEST(LdlpgsExport, MjcfHumanoid) {
  ASSERT_TRUE(std::filesystem::exists(kHumanoid)) << kHumanoid << " missing (libmujoco-samples)";
  const std::string mtx = temp_path("humanoid.mtx"), blocks = temp_path("humanoid.blocks");
  const Result r = run("export " + kHumanoid + " --no-shatter --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  // The equality rows: 6 x 16 bodies - 27 degrees of freedom (MuJoCo's nv) = 69.
  EXPECT_EQ(read_matrix_market(mtx).n, 69);
}

TEST(LdlpgsBadInput, StepMjcfWithAConstructWeCannotRepresent) {
  const std::string path = temp_file("slides.xml", R"(<mujoco><worldbody><body name="box"><joint type="slide" axis="1 0 0"/>
    <joint type="slide" axis="0 1 0"/><geom size=".1"/></body></worldbody></mujoco>)");
  expect_input_error("step " + path, {"slides.xml", "body \"box\"", "2 slides"});
}

TEST(LdlpgsBadInput, ExportUnparsableMjcf) {
  const std::string path = temp_file("broken.xml", "<mujoco><worldbody>");
  expect_input_error("export " + path + " --matrix-file x.mtx --blocks-file x.blocks", {"broken.xml", "MuJoCo cannot load it"});
}

#else

TEST(LdlpgsBadInput, MjcfWithoutMuJoCo) {
  const std::string path = temp_file("model.xml", "<mujoco/>");
  expect_input_error("step " + path, {"model.xml", "need MuJoCo"});
}

#endif

// ---- the command-line vocabulary (docs/cli.md, "Command-line vocabulary") ----

namespace vocabulary_test {

struct Field {
  std::string name, type;                // name: dotted for a member of an object (inertia.positive)
  std::vector<std::string> in, was;      // commands that must print it; the names it replaces
};

std::string strip(std::string s) {
  std::erase(s, '`');
  const size_t b = s.find_first_not_of(' '), e = s.find_last_not_of(' ');
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char by) {
  std::vector<std::string> parts;
  std::stringstream ss(s);
  for (std::string part; std::getline(ss, part, by);)
    if (!strip(part).empty()) parts.push_back(strip(part));
  return parts;
}

// The field table of docs/cli.md's vocabulary section: rows | `field` | type | in | was |.
std::vector<Field> read_vocabulary() {
  std::ifstream in(std::string(LDLPGS_TESTDATA) + "/../../docs/cli.md");
  std::vector<Field> fields;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("## ")) inside = line == "## Command-line vocabulary";
    if (!inside || !line.starts_with("| `")) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string cell; std::getline(ss, cell, '|');) cells.push_back(cell);
    if (cells.size() != 4) continue;  // the table of old option spellings has two columns
    fields.push_back({strip(cells[0]), strip(cells[1]), split(cells[2], ' '), split(cells[3], ',')});
  }
  return fields;
}

bool has_type(const nlohmann::json& v, const std::string& type) {
  if (type == "integer") return v.is_number_integer();
  if (type == "integer?") return v.is_number_integer() || v.is_null();
  if (type == "number") return v.is_number();
  if (type == "number?") return v.is_number() || v.is_null();
  if (type == "string") return v.is_string();
  if (type == "string?") return v.is_string() || v.is_null();
  if (type == "boolean") return v.is_boolean();
  if (type == "object") return v.is_object();
  ADD_FAILURE() << "the vocabulary names an unknown type " << type;
  return false;
}

// The output and the records of its lists (order's results, peers' engines, sweep's points).
std::vector<const nlohmann::json*> records(const nlohmann::json& j) {
  std::vector<const nlohmann::json*> all = {&j};
  for (const auto& [key, value] : j.items())
    if (value.is_array())
      for (const nlohmann::json& x : value)
        if (x.is_object()) all.push_back(&x);
  return all;
}

const nlohmann::json* lookup(const nlohmann::json& o, const std::string& dotted) {
  const nlohmann::json* at = &o;
  for (const std::string& key : split(dotted, '.')) {
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
  }
  return at;
}

void expect_vocabulary(const std::string& command, const nlohmann::json& j, const std::vector<Field>& vocabulary) {
  ASSERT_TRUE(j.is_object()) << command;
  EXPECT_EQ(j.value("ldlpgs_version", ""), ldlpgs::kVersion) << command;
  for (const Field& f : vocabulary) {
    bool found = false;
    for (const nlohmann::json* r : records(j)) {
      if (const nlohmann::json* v = lookup(*r, f.name)) {
        found = true;
        EXPECT_TRUE(has_type(*v, f.type)) << command << ": " << f.name << " = " << v->dump() << ", not " << f.type;
      }
      for (const std::string& old : f.was) EXPECT_FALSE(r->contains(old)) << command << ": " << old << " is now " << f.name;
    }
    if (std::find(f.in.begin(), f.in.end(), command) != f.in.end()) {
      EXPECT_TRUE(found) << command << " has no " << f.name << " (docs/cli.md says it does)";
    }
  }
}

TEST(LdlpgsVocabulary, TheReadmeStatesIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  ASSERT_GT(vocabulary.size(), 30u);
  for (const Field& f : vocabulary) {
    EXPECT_FALSE(f.in.empty()) << f.name;
    nlohmann::json probe = nullptr;
    has_type(probe, f.type);  // fails on a type the test does not know
  }
}

TEST(LdlpgsVocabulary, EverySubcommandsJsonSpeaksIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  ASSERT_FALSE(vocabulary.empty());
  const std::string m = kMatrices + "/bcsstk01.mtx", mtx = temp_path("v.mtx"), blocks = temp_path("v.blocks");
  const std::pair<std::string, std::string> runs[] = {
      {"order", "order " + m + " --cholmod --ordering meca,amd-scalar --certify --json"},
      {"verify", "verify " + m + " --json"},
      {"bench", "bench chain:10 --dense-max 100 --json"},
      {"step", "step four-bar --steps 20 --json"},
      {"export", "export four-bar --matrix-file " + mtx + " --blocks-file " + blocks + " --json"},
      {"spy", "spy four-bar --json"},
      {"sweep", "sweep --cases four-bar --iterations 1 --seconds 0.1 --json"},
      {"peers", "peers pendulum --seconds 0.05 --json"},
  };
  for (const auto& [command, args] : runs) {
    const nlohmann::json j = json_of(args);
    EXPECT_EQ(j.value("command", ""), command);
    expect_vocabulary(command, j, vocabulary);
  }
  // report: its tables as data, one record per row
  const std::string dir = temp_path("vocabulary-report"), empty = temp_path("no-matrices");
  std::filesystem::create_directories(empty);
  const Result r = run("report --sizes 10 --cases four-bar --ordering meca,amd --matrices " + empty + " --out-dir " + dir +
                       " --no-figures");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* table : {"orderings", "verification", "sweep", "stability"}) {
    std::ifstream in(dir + "/data/" + table + ".json");
    expect_vocabulary("report", nlohmann::json::parse(in), vocabulary);
  }
}

// A matrix the solvers refuse: the same fields, null where nothing was measured.
TEST(LdlpgsVocabulary, ASingularMatrixSpeaksIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  const std::string f = temp_file("singular.mtx", kSingular);
  for (const char* command : {"bench", "verify"}) {
    const Result r = run(std::string(command) + " " + f + " --json");
    EXPECT_EQ(r.code, 1) << command << ": " << r.err;
    expect_vocabulary(command, nlohmann::json::parse(r.out), vocabulary);
  }
}

TEST(LdlpgsVocabulary, Version) {
  const Result r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find(ldlpgs::kVersion), std::string::npos) << r.out;
}

TEST(LdlpgsVocabulary, NoOrUnknownSubcommandPrintsTheUsage) {
  const Result none = run("");
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("Usage"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("no subcommand given"), std::string::npos) << none.err;
  const Result unknown = run("verfy x.mtx");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("Usage"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("unknown subcommand 'verfy'; did you mean verify?"), std::string::npos) << unknown.err;
}

TEST(LdlpgsVocabulary, MisspeltOptionNamesTheNearest) {
  expect_input_error("verify " + kMatrices + "/bcsstk01.mtx --orderin amd",
                     {"ldlpgs verify: unknown option --orderin; did you mean --ordering?"});
  expect_input_error("step pendulum --jsn", {"ldlpgs step: unknown option --jsn; did you mean --json?"});
}

TEST(LdlpgsVocabulary, ListsAreCommaSeparated) {
  expect_input_error("sweep --cases four-bar chain-10", {"comma-separated", "--cases four-bar,chain-10"});
}

TEST(LdlpgsVocabulary, OldSpellings) {
  // kept: the same output as the new name
  EXPECT_EQ(json_of("order " + kMatrices + "/can___24.mtx --orderings amd --json")["results"][0]["ordering"], "amd");
  const std::string spy = temp_path("old-spy.json");
  ASSERT_EQ(run("spy four-bar --out " + spy).code, 0);
  std::ifstream in(spy);
  EXPECT_EQ(nlohmann::json::parse(in)["scene"], "four-bar");
  // refused, naming the new one: their meaning changed
  expect_input_error("export four-bar --matrix-file " + temp_path("o.mtx") + " --blocks " + temp_path("o.blocks"),
                     {"--blocks is now --blocks-file"});
  expect_input_error("sweep --cases four-bar --json " + temp_path("o.json"), {"--json-file"});
}

TEST(LdlpgsVocabulary, OrderTakesAGeneratedMechanism) {
  const nlohmann::json j = json_of("order grid:20 --ordering meca --json");
  EXPECT_EQ(j["matrix"], "grid-20");
  EXPECT_EQ(j["blocks"], 20);
}

TEST(LdlpgsVocabulary, OrderOnALargeMatrixPrintsProgress) {
  const Result r = run("order chain:1400 --ordering meca,amd");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("ldlpgs order: chain-1400: meca"), std::string::npos) << r.err;
}

TEST(LdlpgsVocabulary, BenchOnALargeMatrixPrintsProgress) {
  const Result r = run("bench chain:1400 --dense-max 10 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* solver : {"ldlpgs", "cholmod", "eigen-simplicial"})
    EXPECT_NE(r.err.find(std::string("ldlpgs bench: chain-1400: ") + solver), std::string::npos) << r.err;
}

}  // namespace vocabulary_test

// Robustness, one test per class of finding. Each failed on the main of 0c33819.

// Class 1: matrices without stored entries aborted in CHOLMOD (terminate, status -4).
TEST(LdlpgsRobust, MatricesWithoutEntriesDoNotAbort) {
  const std::string empty0 = temp_file("empty0.mtx", "%%MatrixMarket matrix coordinate real symmetric\n0 0 0\n");
  const std::string empty5 = temp_file("empty5.mtx", "%%MatrixMarket matrix coordinate real symmetric\n5 5 0\n");
  for (const char* command : {"verify", "bench", "order --cholmod"}) {
    expect_input_error(std::string(command) + " " + empty0, {empty0, "0 x 0"});
    // All zero: singular, so verify and bench report it (exit 1 or 0), never abort.
    const Result r = run(std::string(command) + " " + empty5);
    EXPECT_TRUE(r.code == 0 || r.code == 1) << command << ": exit " << r.code << "\n" << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  }
}

// Class 3: a size line declaring 2^31 - 1 rows overflowed n + 1 and ended in length_error; 30M
// rows took 1.6 GB; a family size of 2e9 ended in bad_alloc. Now refused before allocating.
TEST(LdlpgsRobust, DeclaredSizesBeyondTheLimitsAreRefusedBeforeAllocating) {
  const std::string huge = temp_file("huge.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2147483647 2147483647 1\n1 1 1\n");
  const std::string big = temp_file("big.mtx", "%%MatrixMarket matrix coordinate real symmetric\n30000000 30000000 1\n1 1 1\n");
  for (const char* command : {"order", "verify"}) {
    expect_input_error(std::string(command) + " " + huge, {huge + ":2", "rows", "limit", "--no-size-limits"});
    expect_input_error(std::string(command) + " " + big, {big + ":2", "30000000 rows"});
  }
  expect_input_error("verify chain:2000000000", {"chain", "2000000000 constraints", "limit"});
  // The global flag is accepted (matrix_market_test checks that lifted limits read the file).
  EXPECT_EQ(run("--no-size-limits order " + kMatrices + "/can___24.mtx --ordering natural").code, 0);
}

// Class 8: a JSON syntax error echoed the whole token (a 1 MB line, a 1 MB message) and raw
// control bytes; a NUL inside a matrix entry cut the message short.
TEST(LdlpgsRobust, MessagesAreOneBoundedPrintableLine) {
  std::string token(1 << 20, 'x');
  token[5] = '\x01';
  const std::string json = temp_file("long.json", "{\"name\": \"" + token);  // unterminated string
  Result r = run("step " + json);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 600);
  for (char c : r.err.substr(0, r.err.size() - 1)) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);

  static const char kNul[] = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\0x\n2 2 1\n";
  const std::string nul = temp_file("nul.mtx", std::string(kNul, sizeof(kNul) - 1));
  r = run("order " + nul);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("\\x00"), std::string::npos) << r.err;  // escaped, and the message goes on after it
}

// Readers, numerics and messages

// Class 8: order printed nnz(A) as 2 nnz - n, which assumes a stored diagonal: -5 for an empty
// 5 x 5, 1 for a 3 x 3 with one diagonal and one off-diagonal entry (it has 3).
TEST(LdlpgsRobust, OrderCountsTheEntriesOfTheFullMatrix) {
  const std::string empty5 = temp_file("empty5.mtx", "%%MatrixMarket matrix coordinate real symmetric\n5 5 0\n");
  Result r = run("order " + empty5 + " --ordering natural");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nnz(A) = 0\n"), std::string::npos) << r.out;
  const std::string partial = temp_file("partial.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 2\n3 1 1\n");
  r = run("order " + partial + " --ordering natural");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nnz(A) = 3\n"), std::string::npos) << r.out;
  // A full diagonal: bcsstk01 stores 224 entries below and on its 48-entry diagonal.
  r = run("order " + kMatrices + "/bcsstk01.mtx --ordering natural");
  const SymmetricCsc a = read_matrix_market(kMatrices + "/bcsstk01.mtx");
  EXPECT_NE(r.out.find("nnz(A) = " + std::to_string(2 * a.nnz() - a.n) + "\n"), std::string::npos) << r.out;
}

// Class 8: the blocks file reader copied the offending line raw and whole into its message, which
// main's last-resort cut ended mid-quote at 400 characters; the reader quotes it escaped and
// bounded itself, and main keeps those escapes (it doubled their backslashes: \\x01).
TEST(LdlpgsRobust, BlocksFileMessagesAreOneBoundedPrintableLine) {
  std::string junk = "6\n\x01\x02" + std::string(100000, '9') + std::string("\0\x80\r", 3) + "\n";
  const std::string blocks = temp_file("junk.blocks", junk);
  const Result r = run("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks);
  EXPECT_EQ(r.code, 2) << r.err.substr(0, 300);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 600);
  EXPECT_NE(r.err.find(blocks + ":2: "), std::string::npos) << r.err.substr(0, 600);
  EXPECT_NE(r.err.find("got '\\x01\\x02999"), std::string::npos) << r.err;
  EXPECT_TRUE(r.err.ends_with("...'\n")) << r.err;  // the reader's own cut, the quote closed
  for (char c : r.err.substr(0, r.err.size() - 1)) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);
}

// A diagonal or 2 x 2 matrix as a Matrix Market file, values to full precision.
std::string small_matrix(const std::string& name, std::initializer_list<std::array<double, 3>> entries, int n) {
  std::string text = "%%MatrixMarket matrix coordinate real symmetric\n" + std::to_string(n) + " " +
                     std::to_string(n) + " " + std::to_string(entries.size()) + "\n";
  for (const auto& [i, j, v] : entries) {
    char line[80];
    std::snprintf(line, sizeof line, "%d %d %.17g\n", static_cast<int>(i), static_cast<int>(j), v);
    text += line;
  }
  return temp_file(name, text);
}

// Class 6: 1e-314 factored "ok" and solved to NaN, a positive definite 2 x 2 at 1e-320 was "not
// finite, pivot -inf"; CHOLMOD solves both, and verify now agrees with it.
TEST(LdlpgsRobust, VerifyAtTheEdgesOfDouble) {
  for (const std::string& m : {small_matrix("tiny1.mtx", {{1, 1, 1e-314}}, 1),
                               small_matrix("tiny2.mtx", {{1, 1, 2e-320}, {2, 2, 2e-320}, {2, 1, 1e-320}}, 2),
                               small_matrix("huge2.mtx", {{1, 1, 2e307}, {2, 2, 2e307}, {2, 1, 1e307}}, 2)}) {
    const Result r = run("verify " + m + " --json");
    EXPECT_EQ(r.code, 0) << m << "\n" << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["status"], "ok") << m;
    EXPECT_TRUE(j["verifiable"].get<bool>()) << m;
    // cond_1 is 1 and 3 (Hager's estimate is a lower bound): not inf as ||A^-1|| alone is at 1e-314.
    const double cond = j["condition_estimate"].get<double>();
    EXPECT_TRUE(cond >= 1 && cond <= 3 + 1e-12) << m << ": " << cond;
  }
}

// Class 6: a condition estimate that overflowed made the tolerance inf, and verify printed "agree"
// (x 5.27 off); a finite one above 1 / eps makes a tolerance of 1 or more that checks no digit.
TEST(LdlpgsRobust, VerifyNeverAgreesOnAToleranceThatChecksNothing) {
  for (int e : {500, 750}) {  // cond_1 = 2^1000 (tolerance 2e285), 2^1500 (estimate inf)
    const double big = std::ldexp(1.0, e);
    const std::string m = small_matrix("cond" + std::to_string(e) + ".mtx", {{1, 1, big}, {2, 2, 1 / big}}, 2);
    Result r = run("verify " + m);
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("CANNOT VERIFY"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("agree"), std::string::npos) << r.out;
    r = run("verify " + m + " --json");
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_FALSE(j["verifiable"].get<bool>());
  }
}

// Physics-side classes. Each failed on the main of 0241fc1 (the old program: exit 0
// with a negative timestep, NaN in the trace and in H.mtx, a scene spy wrote that step refused,
// exit 0 on a chain 48.9 m apart).
#ifdef LDLPGS_HAVE_MUJOCO
// Class 4: MJCF is checked before and after MuJoCo: a negative timestep was stepped ("5 steps of
// -0.01 s", exit 0); MuJoCo's massless world body was written as -nan in the trace.
TEST(LdlpgsRobust, MjcfTimestepAndTraceOfTheWorld) {
  const std::string body = R"(<worldbody><body name="arm"><joint axis="1 0 0" pos="0 0 1"/><geom size=".1"/></body></worldbody>)";
  const std::string negative = temp_file("negative.xml", "<mujoco><option timestep=\"-0.01\"/>" + body + "</mujoco>");
  expect_input_error("step " + negative + " --steps 5", {"negative.xml: option timestep", "-0.01"});
  const std::string trace = temp_path("world.csv");
  const std::string model = temp_file("model.xml", "<mujoco>" + body + "</mujoco>");
  ASSERT_EQ(run("step " + model + " --steps 2 --trace-file " + trace).code, 0);
  std::ifstream in(trace);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\n0,0,world,0,0,0,1,0,0,0"), std::string::npos) << text.substr(0, 300);
  EXPECT_EQ(text.find("nan"), std::string::npos) << text.substr(0, 300);
}
#endif

// Class 5: export wrote NaN and inf into H.mtx with exit 0 (a mass of 1e-320, an anchor at
// 1e155, a coordinate of 1e308), which verify then refused. Now exit 2 naming the body or
// constraint, and no matrix written.
TEST(LdlpgsRobust, ExportNeverWritesNonFiniteEntries) {
  auto scene = [](const char* mass, const char* position, const char* anchor) {
    std::string s = R"({"bodies": [{"name": "ground", "static": true, "position": [0, 0, 0]}, {"name": "bob", "mass": )";
    s += mass;
    s += R"(, "inertia": [1, 1, 1], "position": [)";
    s += position;
    s += R"(, 0, 0]}], "constraints": [{"type": "ball", "bodies": ["ground", "bob"], "anchor": [)";
    s += anchor;
    s += ", 0, 0]}]}";
    return s;
  };
  const std::pair<std::string, std::string> cases[] = {
      {scene("1e-320", "1", "0"), "body \"bob\": mass 1e-320"},
      {scene("1", "1", "1e155"), "constraint 0 (ball between body \"ground\" and body \"bob\"): anchor 1e+155"},
      {scene("1", "1e308", "0"), "body \"bob\": position 1e+308"}};
  for (const auto& [text, words] : cases) {
    const std::string path = temp_file("overflow.json", text), mtx = temp_path("overflow.mtx");
    expect_input_error("export " + path + " --matrix-file " + mtx + " --blocks-file " + temp_path("o.blocks"),
                       {"overflow.json: " + words});
    EXPECT_FALSE(std::filesystem::exists(mtx));
  }
}

// Class 7: a user's body named "chassis#1" shared its name with a shard, so the scene spy
// --scene-out wrote was refused by step ("duplicate body name").
TEST(LdlpgsRobust, SpySceneOfAShatteredMechanismSteps) {
  std::ifstream in(std::string(LDLPGS_TESTDATA) + "/../../physics/scenes/multi-wheeled-vehicle.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  for (const char* name : {"chassis#1", "chassis#2"})
    scene["bodies"].push_back({{"name", name}, {"mass", 1}, {"inertia", {1, 1, 1}}, {"position", {0, 9, 0}}});
  const std::string path = temp_file("named.json", scene.dump()), out = temp_path("shattered.json");
  const Result spy = run("spy " + path + " --scene-out " + out + " --json-file " + temp_path("spy.json"));
  ASSERT_EQ(spy.code, 0) << spy.err;
  const Result step = run("step " + out + " --no-shatter --steps 3");
  EXPECT_EQ(step.code, 0) << step.err;
}

// Class 10: a mass ratio of 1e12 ended every solver's 5 m heavy chain 48.9 m apart in 1000
// steps, and PGS's 100-link chain 5.15 m (6e17 m later on), all with exit 0. Now exit 1 naming
// the step and the error against the mechanism's size; within the supported range, exit 0.
TEST(LdlpgsRobust, MassRatioBeyondTheSupportedRangeExitsOne) {
  for (const char* solver : {"direct", "ldl-pgs", "pgs", "block-gs"}) {
    const Result r = run(std::string("step heavy-chain-10-1e12 --steps 1000 --json --solver ") + solver);
    EXPECT_EQ(r.code, 1) << solver << ": " << r.err;
    EXPECT_NE(r.err.find("it came apart"), std::string::npos) << r.err;
    EXPECT_NE(nlohmann::json::parse(r.out)["failure"].get<std::string>().find("size 4.75 m"), std::string::npos);
  }
  const Result hundred = run("step heavy-chain-100-1e12 --steps 200 --solver pgs");
  EXPECT_EQ(hundred.code, 1) << hundred.err;
  EXPECT_NE(hundred.err.find("it came apart"), std::string::npos) << hundred.err;
  const Result supported = run("step heavy-chain-10-1e6 --steps 1000 --json");
  EXPECT_EQ(supported.code, 0) << supported.err;
  EXPECT_TRUE(nlohmann::json::parse(supported.out)["failure"].is_null());
}

// On the talk's tracked vehicle meca gives 41,400 block flops; best chooses meca-w's
// 38,300, and --certify proves no block order has fewer.
TEST(LdlpgsOrder, CertifiesTheTrackedVehicle) {
  const std::string mtx = temp_path("tracked.mtx"), blocks = temp_path("tracked.blocks");
  ASSERT_EQ(run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks).code, 0);
  const std::string order = "order " + mtx + " --blocks " + blocks + " --orderings best,meca --certify";
  const nlohmann::json j = json_of(order + " --json");
  ASSERT_EQ(j["results"].size(), 2u);
  const nlohmann::json& best = j["results"][0];
  EXPECT_EQ(best["ordering"], "best");
  EXPECT_EQ(best["chosen"], "meca-w");
  EXPECT_EQ(best["block_flops"], 38300);
  EXPECT_TRUE(best["certified_optimal"].get<bool>());
  EXPECT_EQ(best["lower_bound_block_flops"], 38300);
  EXPECT_EQ(j["results"][1]["block_flops"], 41400);
  EXPECT_FALSE(j["results"][1]["certified_optimal"].get<bool>());
  EXPECT_TRUE(j["optimum_proved"].get<bool>());
  const Result text = run(order);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("certificate: optimum 38300 block flops"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("optimal: best (meca-w)\n"), std::string::npos) << text.out;
}

// On a closed loop of 40 constraints the certificate's optimum is below every ordering's: its
// order is a row of its own, written by --perm-dir like the others.
TEST(LdlpgsOrder, CertifyAddsTheOptimalOrderNoOrderingReached) {
  const std::string dir = temp_path("loop-perms");
  const nlohmann::json j = json_of("order loop:40 --ordering best,meca --certify --json --perm-dir " + dir);
  ASSERT_EQ(j["results"].size(), 3u);
  const nlohmann::json& optimal = j["results"][2];
  EXPECT_EQ(optimal["ordering"], "optimal");
  EXPECT_EQ(optimal["chosen"], "certify");
  EXPECT_TRUE(optimal["certified_optimal"].get<bool>());
  EXPECT_TRUE(j["optimum_proved"].get<bool>());
  EXPECT_EQ(optimal["block_flops"], j["lower_bound_block_flops"]);
  EXPECT_LT(optimal["block_flops"].get<double>(), j["results"][0]["block_flops"].get<double>());
  EXPECT_FALSE(j["results"][0]["certified_optimal"].get<bool>());
  std::ifstream perm(dir + "/optimal.perm");
  std::vector<int> rows;
  for (int r; perm >> r;) rows.push_back(r);
  EXPECT_NO_THROW(check_permutation(rows, j["n"].get<int>(), "optimal.perm"));
  const Result text = run("order loop:40 --ordering best --certify");
  EXPECT_NE(text.out.find("optimal: optimal (certify)\n"), std::string::npos) << text.out;
}

// Out of time: a lower bound, below the orderings' flops, and nothing certified.
TEST(LdlpgsOrder, CertifyOutOfTimeGivesALowerBound) {
  const nlohmann::json j = json_of("order grid:200 --ordering best --certify --certify-time-limit-s 0 --json");
  EXPECT_FALSE(j["optimum_proved"].get<bool>());
  EXPECT_LT(j["lower_bound_block_flops"].get<double>(), j["results"][0]["block_flops"].get<double>());
  EXPECT_FALSE(j["results"][0]["certified_optimal"].get<bool>());
}

}  // namespace

}  // namespace ldlpgs
