// ldlpgs bench MATRIX: median time of the numeric factorization and of one solve for our block
// LDL^T and, on the same matrix and scalar permutation, CHOLMOD (simplicial and supernodal),
// Eigen's SimplicialLDLT and, for small matrices, Eigen's dense LDLT; each with the backward
// error its solution reached. Symbolic work is done before any timing. It names the BLAS that
// CHOLMOD supernodal calls (blas_in_use()), which decides that solver's speed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "apps/commands.h"
#include "apps/compare.h"
#include "apps/options.h"
#include "peers/competitors.h"
#include "peers/ldlpgs_solver.h"
#include "peers/median.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

namespace {

int mapped_supernodes(const Symbolic& s) {
  int count = 0;
  for (int t = 0; t < s.num_supernodes(); ++t) count += s.supernode_mapped(t);
  return count;
}

struct Timing {
  std::string name;
  bool ok = false;
  std::string failure;  // DirectSolver::failure() when !ok
  double factor_us = NAN, solve_us = NAN, backward_error = NAN;
};

// Median of repeated calls of f, in microseconds: at least 5 calls and 0.2 s, at most 10000,
// after 0.1 s of untimed calls (at least one). Without the warm-up the solver timed first (ours,
// right after the orderings) ran 15-25 % slower for its first 0.1-0.3 s on the 2-core EPYC VM of
// papers/factor.md, and so in its whole 0.2 s window: chain:1265 70 us against 57-59 us with the
// warm-up or after a 0.3 s sleep, loop:1265 100 against 80, as in factor_bench and a stand-alone
// loop; the solvers timed after it did not change (Eigen simplicial 186-189 us either way).
template <class F>
double median_us(F&& f) {
  using Clock = std::chrono::steady_clock;
  const auto warm = Clock::now();
  do f();
  while (Clock::now() - warm < std::chrono::milliseconds(100));
  std::vector<double> us;
  double total = 0;
  while (us.size() < 10000 && (us.size() < 5 || total < 2e5)) {
    const auto start = Clock::now();
    f();
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    total += us.back();
  }
  return median(std::move(us));
}

Timing time_solver(DirectSolver& s, const SymmetricCsc& a) {
  Timing t;
  t.name = s.name();
  if (!(t.ok = s.factor())) {
    t.failure = s.failure();
    return t;
  }
  std::vector<double> b(a.n), x(a.n);
  for (int i = 0; i < a.n; ++i) b[i] = 1.0 + 0.5 * std::sin(i);
  x = b;
  s.solve(x);
  t.backward_error = backward_error(a, x, b);
  // A solver may accept a pivot whose inverse overflows: Eigen's dense LDLT on diag(1e-310)
  // reported success and solved to inf - inf = NaN, which bench printed as -nan and exit 0.
  if (!std::isfinite(t.backward_error)) {
    t.ok = false;
    t.failure = "the solution is not finite (a pivot's inverse overflowed)";
    return t;
  }
  t.factor_us = median_us([&] { s.factor(); });
  t.solve_us = median_us([&] {
    std::copy(b.begin(), b.end(), x.begin());
    s.solve(x);
  });
  return t;
}

// The bench options.
struct BenchOptions {
  ProblemArgs problem;
  std::string ordering = "best";
  int dense_max = 1000;
  std::string kernels = "auto";
  SymbolicOptions symbolic;
  bool json = false;
};

// The symbolic phase's tuning (factor/symbolic.h, SymbolicOptions), as bench's flags.
void add_symbolic_options(CLI::App* cmd, SymbolicOptions* symbolic) {
  cmd->add_flag("--postorder,!--no-postorder", symbolic->postorder,
               "Factor in the weighted postorder of the ordering's elimination tree (the same fill and flops)")
      ->capture_default_str();
  cmd->add_option("--supernode-min-rows", symbolic->supernode_min_rows,
                  "Rows from which a run of nested pivots is one supernode (0: none)")
      ->capture_default_str()
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  cmd->add_option("--supernode-min-front", symbolic->supernode_min_front,
                  "Rows of L's column (the supernode's and those below) from which it is one supernode")
      ->capture_default_str()
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  cmd->add_option("--small-supernode-max-rows", symbolic->small_supernode_max_rows,
                  "Rows of the small supernodes a run of nested pivots not made one supernode is cut into (1: none)")
      ->capture_default_str()
      ->check(integer_in(1, 1 << 20));
  cmd->add_option("--relax-max-zeros", symbolic->relax_max_zeros,
                  "Explicit zeros (a fraction of the entries below its diagonal) a small supernode may store to take "
                  "pivots that do not nest (0: none)")
      ->capture_default_str()
      ->check(finite_in(0, 1));
  cmd->add_option("--blas-min-rows", symbolic->blas_min_rows, "Rows from which a supernode is eliminated with BLAS (0: never)")
      ->capture_default_str()
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  cmd->add_option("--rsi-max-per-entry", symbolic->rsi_max_per_entry,
                  "RSI indices per entry of L above which a supernode scatters through a relative map (0: always, "
                  "negative: never)")
      ->capture_default_str()
      ->check(finite_in(-HUGE_VAL));
  cmd->add_option("--rsi-min-entries", symbolic->rsi_min_entries,
                  "RSI indices the budget of --rsi-max-per-entry always allows (unless that is 0)")
      ->capture_default_str()
      ->check(integer_in(0, std::numeric_limits<int64_t>::max()));
}

// One bench run: ours first, then every other direct solver in the order ours factors in.
struct BenchRun {
  Problem problem;
  Ordering ordering;
  std::unique_ptr<LdlpgsSolver> ours;
  double flops = 0;
  std::string blas;
  std::vector<Timing> timings;  // ours first

  const Timing* find(std::string_view name) const {
    for (const Timing& t : timings)
      if (t.name == name) return &t;
    return nullptr;
  }
};

BenchRun run_bench(const BenchOptions& o) {
  try {
    set_kernel_isa(o.kernels);
  } catch (const ArgumentError& e) {
    throw InputError("--kernels " + o.kernels + ": " + e.what());
  }
  const OrderingInfo& info = find_ordering(o.ordering);
  BenchRun run;
  run.problem = load_problem(o.problem.spec, o.problem.blocks, o.problem.max_block, o.problem.split_blocks);
  const Problem& p = run.problem;
  run.ordering = compute_ordering(info, p.blocks, p.a);
  run.ours = std::make_unique<LdlpgsSolver>(p.a, p.blocks, run.ordering, o.symbolic);
  run.flops = run.ours->symbolic().flops();
  run.blas = blas_in_use();  // before any timing: it may pin OpenBLAS's threads
  if (const std::string warning = blas_core_warning(); !warning.empty()) std::fprintf(stderr, "ldlpgs bench: %s\n", warning.c_str());
  // each solver is timed for at least 0.2 s, and a large matrix's factorizations take seconds
  auto timed = [&](DirectSolver& s) {
    if (p.a.n >= kProgressDimension) progress("bench", p.name + ": " + std::string(s.name()));
    return time_solver(s, p.a);
  };
  run.timings.push_back(timed(*run.ours));
  for (std::string_view name : direct_solver_names()) {
    if (name == "eigen-dense" && p.a.n > o.dense_max) continue;
    run.timings.push_back(timed(*make_direct_solver(name, p.a, run.ours->symbolic().perm())));
  }
  return run;
}

void print_bench_json(const BenchRun& run) {
  const Problem& p = run.problem;
  const Timing& mine = run.timings.front();
  const Symbolic& symbolic = run.ours->symbolic();
  nlohmann::json j = {{"matrix", p.name}, {"n", p.a.n}, {"blocks", p.blocks.num_blocks()},
                      {"ordering", run.ordering.name}, {"chosen", run.ordering.chosen}, {"flops", run.flops},
                      {"gflops", number_or_null(run.flops / (mine.factor_us * 1e3))},
                      {"symbolic_bytes", symbolic.memory_bytes()},
                      {"rsi_entries", symbolic.rsi_size()}, {"supernodes", symbolic.num_supernodes()}, {"mapped_supernodes", mapped_supernodes(symbolic)},
                      {"blas", run.blas}, {"blas_core", blas_core()}, {"kernels", kernel_isa()}};
  // ours unprefixed, every other solver's fields prefixed with its name (null: not run)
  std::vector<std::string_view> names = {mine.name};
  names.insert(names.end(), direct_solver_names().begin(), direct_solver_names().end());
  for (std::string_view name : names) {
    std::string prefix(name);
    std::replace(prefix.begin(), prefix.end(), '-', '_');
    prefix += '_';
    if (name == mine.name) prefix.clear();
    const Timing* t = run.find(name);
    j[prefix + "factor_us"] = t ? number_or_null(t->factor_us) : nlohmann::json(nullptr);
    j[prefix + "solve_us"] = t ? number_or_null(t->solve_us) : nlohmann::json(nullptr);
    j[prefix + "backward_error"] = t ? number_or_null(t->backward_error) : nlohmann::json(nullptr);
    j[prefix + "failure"] = t && !t->ok ? nlohmann::json(t->failure) : nlohmann::json(nullptr);
  }
  print_json(json_header("bench", std::move(j)));
}

void print_bench_table(const BenchRun& run) {
  const Problem& p = run.problem;
  const Timing& mine = run.timings.front();
  const Symbolic& symbolic = run.ours->symbolic();
  std::printf("%s: n = %d, %d blocks, ordering %s, %.0f flops, %d supernodes, symbolic phase holds %lld bytes\n",
              p.name.c_str(), p.a.n, p.blocks.num_blocks(), shown_name(run.ordering).c_str(), run.flops,
              symbolic.num_supernodes(), static_cast<long long>(symbolic.memory_bytes()));
  std::printf("BLAS (ours for supernodes, CHOLMOD supernodal): %s; OpenBLAS core: %s; our kernels: %s\n", run.blas.c_str(),
              blas_core().empty() ? "none" : blas_core().c_str(), kernel_isa());
  std::printf("%-20s %12s %12s %12s %14s %16s\n", "solver", "factor us", "solve us", "GFlop/s",
              "backward err", "fact+solve ratio");
  for (const Timing& t : run.timings) {
    if (!t.ok) {
      std::printf("%-20s failed to factor: %s\n", t.name.c_str(), t.failure.c_str());
      continue;
    }
    std::printf("%-20s %12.2f %12.2f %12.3f %14.1e", t.name.c_str(), t.factor_us, t.solve_us,
                run.flops / (t.factor_us * 1e3), t.backward_error);
    if (mine.ok) std::printf(" %15.2fx\n", (t.factor_us + t.solve_us) / (mine.factor_us + mine.solve_us));
    else std::printf(" %16s\n", "-");
  }
  std::printf("(medians; ratio = the solver's factor + solve time over ldlpgs's)\n");
}

}  // namespace

Command add_bench_command(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Time the block LDL^T against CHOLMOD and Eigen on one matrix");
  add_problem_options(cmd, &o->problem);
  add_ordering_option(cmd, &o->ordering, "Ordering name (every solver factors in the order ours does: its scalar permutation, postordered unless --no-postorder)");
  cmd->add_option("--dense-max", o->dense_max, "Largest dimension Eigen's dense LDLT is timed on")
      ->capture_default_str()
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  cmd->add_option("--kernels", o->kernels, "Our kernels: auto (the best this CPU runs), sse2, avx2 or avx512 (factor/passes.h)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "sse2", "avx2", "avx512"}));
  add_symbolic_options(cmd, &o->symbolic);
  add_json_flag(cmd, &o->json);
  return [o] {
    const BenchRun run = run_bench(*o);
    if (o->json) print_bench_json(run);
    else print_bench_table(run);
    // A matrix our factorization refuses is a numerical failure, not bad input: exit 1, and the
    // pivot it stopped at on stderr (the table and the JSON say it too).
    const Timing& mine = run.timings.front();
    if (!mine.ok)
      std::fprintf(stderr, "ldlpgs: %s: the factorization failed: %s\n", run.problem.name.c_str(), mine.failure.c_str());
    return mine.ok ? 0 : 1;
  };
}

}  // namespace ldlpgs::cli
