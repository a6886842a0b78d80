// factor_bench: time of the numeric factorization and of one solve, ldlpgs's block LDL^T side by
// side with the competitor direct solvers (peers/competitors.h: CHOLMOD simplicial and
// supernodal, Eigen's SimplicialLDLT and, for n <= 1000, Eigen's dense LDLT), on the generated
// mechanisms (H = J W J^T, every family of ldlpgs::family_names() at 22, 63, 253, 1265 and
// 3000 constraints: about 88 .. 11400 rows, the talk's sizes and beyond) and on the
// test matrices (tests/data/matrices, Pd.mtx left out: it is unsymmetric; blocks as --blocks
// auto). `ldlpgs bench` measures one problem the same way.
//
// Every solver factors the same P H P^T: P is the scalar order ldlpgs factors in (the MECA
// ordering in its elimination tree's postorder, Symbolic::perm), computed once per problem, so that all of them do the same flops at the same fill. All symbolic work
// (ordering, ldlpgs's Symbolic, CHOLMOD's analysis, permuting the matrix) is done when a problem
// is first benchmarked, outside the timed loops. Timed:
//   factor/<solver>/<problem>        DirectSolver::factor(): the numeric factorization alone
//   solve/<solver>/<problem>         one solve of a fixed right-hand side
//   factor_solve/<solver>/<problem>  both, as a physics step does them
// Counters:
//   n               rows
//   flops           the factorization's flops as CHOLMOD counts them (ldlpgs Symbolic::flops()
//                   for P): the same for every solver, a measure of the problem
//   FLOP/s          flops of the timed work per second: the factorization's flops for factor/,
//                   the solve's 4 (nnz(L) - n) + n for solve/ (a multiply-add per entry of L in
//                   each triangular solve, one multiply per row for D^-1), their sum for
//                   factor_solve/; shown as e.g. 5.1G/s
//   backward_error  ||H x - b||_inf / (||H||_inf ||x||_inf + ||b||_inf) of the solver's solution,
//                   computed once after a factor and a solve: every speed comes with its error
//
// Times are wall-clock (->UseRealTime(), hence the "/real_time" suffix of every name), rates
// included: CHOLMOD's supernodal factorization may run OpenMP threads (one since main() limits
// them, peers/competitors.h), whose time the default CPU time of the main thread would leave
// out, and `ldlpgs bench` reports wall-clock medians too.
//
// CHOLMOD's supernodal factorization is BLAS-3 on its dense fronts (dsyrk, dgemm, dpotrf) and
// runs at the speed of whichever libblas.so.3 the system's alternatives chose: the context block
// printed before the results names it ("blas", peers/competitors.h blas_in_use()). Debian's
// reference BLAS makes it several times slower than OpenBLAS (papers/factor.md); build.sh installs
// OpenBLAS's serial build. Ours, CHOLMOD simplicial and Eigen call no BLAS.
//
// Ours runs the kernels the CPU allows (context "kernels": avx2 or sse2, factor/passes.h); where
// that is AVX2, "ldlpgs-sse2" times the same factorization with the SSE2 build of the kernels.
//
// Names end in the problem (<family>-<constraints> or the matrix's file name), so a regex such
// as --benchmark_filter='heavy-22|chain-63' selects problems and 'factor/ldlpgs/' a solver.
//
// Build and run (the whole program takes a few minutes on 2 cores), medians of 5 repetitions:
//   cd /work/main && cmake -S . -B build && cmake --build build -j2 --target factor_bench
//   ./build/bin/factor_bench
// --benchmark_out=FILE.json --benchmark_out_format=json keeps the results.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bench/test_matrix_files.h"
#include "peers/competitors.h"
#include "peers/ldlpgs_solver.h"
#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/mechanism_matrix.h"
#include "ldlpgs/sparse/partition.h"

#ifndef LDLPGS_MATRICES
#error "LDLPGS_MATRICES (the test matrices directory) must be defined by the build"
#endif

namespace {

using namespace ldlpgs;

constexpr int kConstraints[] = {22, 63, 253, 1265, 3000};
// heavy's H is dense: at 1265 constraints (n about 5000, 4e10 flops) one factorization takes
// 6 s for ldlpgs and about 17 s for each CHOLMOD and Eigen sparse solver, minutes per
// repetition. `ldlpgs bench heavy:1265` measures it once.
constexpr int kHeavyMaxConstraints = 253;
// Eigen's dense LDLT does n^3 / 3 flops whatever the sparsity: at n = 5000 seconds per call.
constexpr int kDenseMaxRows = 1000;
constexpr std::string_view kDense = "eigen-dense";
constexpr const char* kOrdering = "meca";

// Defaults given as flags rather than with ->MinTime() and ->Repetitions(), which would append
// "/min_time:0.050/repeats:5" to every name; any of them on the command line overrides its
// default (e.g. --benchmark_repetitions=1 for a quick look). A benchmark slower than min_time runs
// once per repetition, so the large problems cost only their 5 calls.
constexpr const char* kDefaultFlags[] = {"--benchmark_min_time=0.05", "--benchmark_repetitions=5",
                                         "--benchmark_report_aggregates_only=true"};

// A solver ready to be timed on one problem: symbolic work done, factored once.
struct Prepared {
  std::unique_ptr<DirectSolver> solver;
  bool ok = false;  // its factor() succeeded (a failure is reported by every benchmark of it)
  double backward_error = NAN;
};

struct Problem {
  std::string name;
  SymmetricCsc a;
  BlockPattern blocks;
  std::vector<double> b;  // the right-hand side every solver solves (size a.n)
  // Built by the problem's first benchmark, so that a filtered run prepares only what it times:
  std::optional<Ordering> ordering;
  std::vector<int> perm;  // the scalar order ours factors in (Symbolic::perm), every solver's
  double factor_flops = 0, solve_flops = 0;
  std::map<std::string, Prepared, std::less<>> solvers;  // by solver name
};

// Benchmarks hold pointers to their problem: a deque never moves its elements, and the problems
// live until the program ends.
std::deque<Problem>& problems() {
  static std::deque<Problem> all;
  return all;
}

Prepared prepare(std::unique_ptr<DirectSolver> solver, const Problem& p) {
  Prepared s;
  s.solver = std::move(solver);
  s.ok = s.solver->factor();
  if (s.ok) {
    std::vector<double> x = p.b;
    s.solver->solve(x);
    s.backward_error = backward_error(p.a, x, p.b);
  }
  return s;
}

// "ldlpgs-sse2": ours with the baseline's kernels (set_kernel_isa), registered where the default
// ones are AVX2, so that one run compares the two builds of the same factorization.
constexpr std::string_view kSse2 = "ldlpgs-sse2";

Prepared& prepared(Problem& p, std::string_view solver) {
  if (solver == kSse2) solver = "ldlpgs";
  if (!p.ordering) {
    p.ordering = compute_ordering(find_ordering(kOrdering), p.blocks, p.a);
    auto ours = std::make_unique<LdlpgsSolver>(p.a, p.blocks, *p.ordering);
    const Symbolic& sym = ours->symbolic();
    p.perm.assign(sym.perm().begin(), sym.perm().end());
    p.factor_flops = sym.flops();
    p.solve_flops = 4.0 * static_cast<double>(sym.nnz_l() - sym.num_rows()) + sym.num_rows();
    p.solvers.emplace("ldlpgs", prepare(std::move(ours), p));
  }
  auto it = p.solvers.find(solver);
  if (it == p.solvers.end()) {
    it = p.solvers.emplace(std::string(solver), prepare(make_direct_solver(solver, p.a, p.perm), p))
             .first;
  }
  return it->second;
}

enum class Phase { factor, solve, factor_solve };

void bench(benchmark::State& state, Problem* p, const std::string& solver, Phase phase) {
  Prepared* s = nullptr;
  try {
    s = &prepared(*p, solver);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (!s->ok) {
    state.SkipWithError(("the factorization failed: " + s->solver->failure()).c_str());
    return;
  }
  std::vector<double> x(p->a.n);
  DirectSolver& d = *s->solver;
  if (solver == kSse2) set_kernel_isa("sse2");
  for (auto _ : state) {
    if (phase != Phase::solve && !d.factor()) {
      state.SkipWithError("the factorization failed where its first call succeeded");
      break;
    }
    if (phase != Phase::factor) {
      // solve() overwrites its argument, so b is copied in at every iteration. Pausing the timer
      // around the copy would cost more than a small solve; the O(n) copy is timed instead, for
      // every solver alike.
      std::copy(p->b.begin(), p->b.end(), x.begin());
      d.solve(x);
      benchmark::DoNotOptimize(x.data());
    }
    benchmark::ClobberMemory();
  }
  set_kernel_isa("auto");

  const double timed_flops =
      (phase != Phase::solve ? p->factor_flops : 0) + (phase != Phase::factor ? p->solve_flops : 0);
  state.counters["n"] = p->a.n;
  state.counters["flops"] = p->factor_flops;
  state.counters["FLOP/s"] = benchmark::Counter(timed_flops, benchmark::Counter::kIsIterationInvariantRate,
                                                benchmark::Counter::kIs1000);
  state.counters["backward_error"] = s->backward_error;
  // The console prints counters with SI prefixes (3.3e-17 as "33a"): the label shows the error
  // in the usual notation, the counter keeps it exactly for --benchmark_out.
  char label[32];
  std::snprintf(label, sizeof label, "backward_error %.1e", s->backward_error);
  state.SetLabel(label);
}

// The right-hand side `ldlpgs bench` solves, so that both report the same errors.
std::vector<double> rhs(int n) {
  std::vector<double> b(n);
  for (int i = 0; i < n; ++i) b[i] = 1.0 + 0.5 * std::sin(i);
  return b;
}

void register_problem(Problem&& made) {
  Problem& p = problems().emplace_back(std::move(made));
  p.b = rhs(p.a.n);
  std::vector<std::string> solvers = {"ldlpgs"};
  if (std::string_view(kernel_isa()) != "sse2") solvers.emplace_back(kSse2);
  for (std::string_view name : direct_solver_names()) {
    if (name != kDense || p.a.n <= kDenseMaxRows) solvers.emplace_back(name);
  }
  constexpr std::pair<const char*, Phase> kPhases[] = {
      {"factor", Phase::factor}, {"solve", Phase::solve}, {"factor_solve", Phase::factor_solve}};
  for (const auto& [phase_name, phase] : kPhases) {
    for (const std::string& solver : solvers) {
      const std::string name = std::string(phase_name) + "/" + solver + "/" + p.name;
      benchmark::RegisterBenchmark(name.c_str(), [problem = &p, solver, phase = phase](benchmark::State& state) {
        bench(state, problem, solver, phase);
      })
          ->Unit(benchmark::kMicrosecond)
          ->UseRealTime();
    }
  }
}

// Matrices and mechanisms are built at registration: the dense solver is registered only for
// small n, known once the matrix is. Everything else waits for the problem's first benchmark.
void register_families() {
  for (std::string_view family : family_names()) {
    for (int m : kConstraints) {
      if (family == "heavy" && m > kHeavyMaxConstraints) continue;
      const BodyGraph mechanism = make_family(family, m);
      Problem p;
      p.name = std::string(family) + "-" + std::to_string(m);
      p.a = mechanism_matrix(mechanism);
      p.blocks = constraint_graph(mechanism);
      register_problem(std::move(p));
    }
  }
}

bool register_matrices() {
  namespace fs = std::filesystem;
  const std::vector<fs::path> files = test_matrix_files(LDLPGS_MATRICES, "factor_bench");
  if (files.empty()) return false;
  for (const fs::path& path : files) {
    Problem p;
    p.name = path.filename().string();
    try {
      p.a = read_matrix_market(path.string());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "factor_bench: %s\n", e.what());
      return false;
    }
    p.blocks = BlockPattern::from_scalar(p.a, partition_auto(p.a));
    register_problem(std::move(p));
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  limit_openmp_to_one_thread(argv);
  std::vector<char*> args(argv, argv + argc);
  std::vector<std::string> defaults;
  for (std::string_view flag : kDefaultFlags) {
    const std::string_view key = flag.substr(0, flag.find('='));
    const bool given = std::any_of(args.begin() + 1, args.end(), [&](const char* a) {
      const std::string_view arg(a);
      return arg.starts_with(key) && (arg.size() == key.size() || arg[key.size()] == '=');
    });
    if (!given) defaults.emplace_back(flag);
  }
  for (std::string& flag : defaults) args.push_back(flag.data());
  int args_count = static_cast<int>(args.size());
  args.push_back(nullptr);
  benchmark::Initialize(&args_count, args.data());
  if (benchmark::ReportUnrecognizedArguments(args_count, args.data())) return 1;
  try {
    register_families();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "factor_bench: %s\n", e.what());
    return 1;
  }
  if (!register_matrices()) return 1;
  benchmark::AddCustomContext("blas", blas_in_use());
  benchmark::AddCustomContext("blas_core", blas_core().empty() ? "none" : blas_core());
  if (const std::string warning = blas_core_warning(); !warning.empty()) std::fprintf(stderr, "factor_bench: %s\n", warning.c_str());
  benchmark::AddCustomContext("kernels", kernel_isa());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
