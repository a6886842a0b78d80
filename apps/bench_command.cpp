// ldlpgs bench MATRIX: median time of the numeric factorization and of one solve for our block
// LDL^T and, on the same matrix and scalar permutation, CHOLMOD (simplicial and supernodal),
// Eigen's SimplicialLDLT and, for small matrices, Eigen's dense LDLT; each with the backward
// error its solution reached. Symbolic work is done before any timing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <utility>

#include "apps/commands.h"
#include "apps/compare.h"
#include "bench/ldlpgs_solver.h"
#include "bench/median.h"

namespace ldlpgs::cli {

namespace {

struct Timing {
  std::string name;
  bool ok = false;
  double factor_us = NAN, solve_us = NAN, backward_error = NAN;
};

// Median of repeated calls of f, in microseconds: at least 5 calls and 0.2 s, at most 10000.
template <class F>
double median_us(F&& f) {
  std::vector<double> us;
  double total = 0;
  while (us.size() < 10000 && (us.size() < 5 || total < 2e5)) {
    const auto start = std::chrono::steady_clock::now();
    f();
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    total += us.back();
  }
  return median(std::move(us));
}

Timing time_solver(DirectSolver& s, const SymmetricCsc& a) {
  Timing t;
  t.name = s.name();
  if (!(t.ok = s.factor())) return t;
  std::vector<double> b(a.n), x(a.n);
  for (int i = 0; i < a.n; ++i) b[i] = 1.0 + 0.5 * std::sin(i);
  x = b;
  s.solve(x);
  t.backward_error = backward_error(a, x, b);
  t.factor_us = median_us([&] { s.factor(); });
  t.solve_us = median_us([&] {
    std::copy(b.begin(), b.end(), x.begin());
    s.solve(x);
  });
  return t;
}

nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace

Command add_bench_command(CLI::App& app) {
  struct Options {
    std::string matrix, blocks = "auto", ordering = "meca";
    int max_block = 6, dense_max = 1000;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("bench", "Time the block LDL^T against CHOLMOD and Eigen on one matrix");
  cmd->add_option("matrix", o->matrix, "Matrix Market file (symmetric), or FAMILY:CONSTRAINTS for a generated "
                                       "mechanism with H = J W J^T values (e.g. heavy:22)")->required();
  cmd->add_option("--blocks", o->blocks, "Block partition: auto, N (uniform) or a file of block sizes")->capture_default_str();
  cmd->add_option("--max-block", o->max_block, "Largest block --blocks auto forms")->capture_default_str();
  cmd->add_option("--ordering", o->ordering, "Ordering name (all solvers use its scalar permutation)")->capture_default_str();
  cmd->add_option("--dense-max", o->dense_max, "Largest dimension Eigen's dense LDLT is timed on")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of a table");
  return [o] {
    const OrderingInfo& info = find_ordering(o->ordering);
    const Problem p = load_problem(o->matrix, o->blocks, o->max_block);
    const Ordering ordering = compute_ordering(info, p.blocks, p.a);
    auto ours = std::make_unique<LdlpgsSolver>(p.a, p.blocks, ordering);
    const double flops = ours->symbolic().flops();
    std::vector<Timing> timings = {time_solver(*ours, p.a)};
    for (std::string_view name : direct_solver_names()) {
      if (name == "eigen-dense" && p.a.n > o->dense_max) continue;
      timings.push_back(time_solver(*make_direct_solver(name, p.a, ordering.perm), p.a));
    }
    auto find = [&](std::string_view name) -> const Timing* {
      for (const Timing& t : timings)
        if (t.name == name) return &t;
      return nullptr;
    };
    const Timing& mine = timings.front();
    const double gflops = flops / (mine.factor_us * 1e3);
    if (o->json) {
      nlohmann::json j = {{"matrix", p.name}, {"n", p.a.n}, {"blocks", p.blocks.num_blocks()},
                          {"ordering", ordering.name}, {"flops", flops}, {"gflops", number(gflops)},
                          {"symbolic_bytes", ours->symbolic().memory_bytes()},
                          {"rsi_entries", ours->symbolic().rsi_size()}};
      auto field = [&](const char* key, std::string_view name, double Timing::*member) {
        const Timing* t = find(name);
        j[key] = t ? number(t->*member) : nlohmann::json(nullptr);
      };
      field("ldlpgs_factor_us", "ldlpgs", &Timing::factor_us);
      field("ldlpgs_solve_us", "ldlpgs", &Timing::solve_us);
      field("cholmod_factor_us", "cholmod", &Timing::factor_us);
      field("cholmod_solve_us", "cholmod", &Timing::solve_us);
      field("cholmod_supernodal_factor_us", "cholmod-supernodal", &Timing::factor_us);
      field("cholmod_supernodal_solve_us", "cholmod-supernodal", &Timing::solve_us);
      field("eigen_simplicial_factor_us", "eigen-simplicial", &Timing::factor_us);
      field("eigen_simplicial_solve_us", "eigen-simplicial", &Timing::solve_us);
      field("eigen_dense_factor_us", "eigen-dense", &Timing::factor_us);
      field("eigen_dense_solve_us", "eigen-dense", &Timing::solve_us);
      nlohmann::json errors;
      for (const Timing& t : timings) errors[t.name] = number(t.backward_error);
      j["backward_error"] = errors;
      std::cout << j.dump(2) << '\n';
    } else {
      std::printf("%s: n = %d, %d blocks, ordering %s, %.0f flops, symbolic phase holds %lld bytes\n", p.name.c_str(),
                  p.a.n, p.blocks.num_blocks(), ordering.name.c_str(), flops,
                  static_cast<long long>(ours->symbolic().memory_bytes()));
      std::printf("%-20s %12s %12s %12s %14s %16s\n", "solver", "factor us", "solve us", "GFlop/s",
                  "backward err", "fact+solve ratio");
      for (const Timing& t : timings) {
        if (!t.ok) {
          std::printf("%-20s failed to factor\n", t.name.c_str());
          continue;
        }
        std::printf("%-20s %12.2f %12.2f %12.3f %14.1e %15.2fx\n", t.name.c_str(), t.factor_us, t.solve_us,
                    flops / (t.factor_us * 1e3), t.backward_error,
                    (t.factor_us + t.solve_us) / (mine.factor_us + mine.solve_us));
      }
      std::printf("(medians; ratio = the solver's factor + solve time over ldlpgs's)\n");
    }
    return mine.ok ? 0 : 1;
  };
}

}  // namespace ldlpgs::cli
