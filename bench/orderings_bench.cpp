// orderings_bench: time of every elimination ordering against graph size, per mechanism family
// (ldlpgs::family_names(), 10 .. 20000 constraints; "heavy" up to 1000, its H is dense) and on
// the test matrices (tests/data/matrices, Pd.mtx left out, blocks as --blocks auto).
//
// Only the ordering function is timed (OrderingInfo::fn on the block pattern, or on the scalar
// pattern BlockPattern::unit(a) for the -scalar orderings). The pattern, the unit pattern and the
// counters are built once per problem, outside the timed loop. Counters (scalar, as CHOLMOD counts
// them, computed once with compute_ordering + summarize):
//   blocks      blocks of the block pattern     n       rows
//   nnz_L       entries of L, diagonal included flops   CHOLMOD's flop count
//   fill_edges  block edges created by the elimination (block orderings only)
//
// Names: order/<ordering>/<family>/<constraints>, order/<ordering>/<matrix>; the scale cases
// order/<ordering>/grid/100000, .../ladder/100000 (without the -exact orderings) and
// order/<ordering>/hub-clique/1000 (a 1000-arm star's block graph).
//
// Build and run (the whole run takes a few minutes on 2 cores), medians of 5 repetitions:
//   cd /work/main && cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
//   cmake --build build -j2 --target orderings_bench
//   ./build/bin/orderings_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Add --benchmark_out=FILE.json --benchmark_out_format=json to keep the results, and
// --benchmark_filter='order/meca/grid/' (a regex) to run a subset.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bench/test_matrix_files.h"
#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

#ifndef LDLPGS_MATRICES
#error "LDLPGS_MATRICES (the test matrices directory) must be defined by the build"
#endif

namespace {

using namespace ldlpgs;

constexpr int kSizes[] = {10, 100, 1000, 10000, 20000};
constexpr int kHeavyMaxSize = 1000;  // heavy's H is dense: 20000 constraints would not fit
// Seconds per benchmark (an ordering slower than this runs once per repetition). Given as the
// default of --benchmark_min_time rather than with ->MinTime(), which would append
// "/min_time:0.050" to every name; --benchmark_min_time=T on the command line overrides it.
constexpr const char* kMinTimeFlag = "--benchmark_min_time=0.05";

// What the ordering counters need: computed once per (problem, ordering).
struct Counters {
  double nnz_L = 0;
  double flops = 0;
  std::optional<double> fill_edges;
};

struct Problem {
  SymmetricCsc a;
  BlockPattern blocks;
  Graph scalar_graph;
  std::optional<BlockPattern> unit;           // the scalar pattern, built if a scalar ordering runs
  std::map<std::string, Counters> counters;   // by ordering name
};

using MakeProblem = std::function<void(Problem&)>;

// Benchmarks run in registration order, all orderings of one problem in a row, so one problem
// is kept at a time: building it again (e.g. with --benchmark_enable_random_interleaving) is only
// slower, never wrong.
Problem& problem(const std::string& key, const MakeProblem& make) {
  static std::string current_key;
  static std::unique_ptr<Problem> current;
  if (!current || current_key != key) {
    current.reset();  // free the previous one before building the next
    auto p = std::make_unique<Problem>();
    make(*p);
    p->scalar_graph = graph_of(p->a);
    current = std::move(p);
    current_key = key;
  }
  return *current;
}

void bench_ordering(benchmark::State& state, const OrderingInfo* info, const std::string& key,
                    const MakeProblem& make) {
  Problem* p = nullptr;
  try {
    p = &problem(key, make);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (info->level == Level::scalar && !p->unit) p->unit = BlockPattern::unit(p->a);
  const BlockPattern& pattern = info->level == Level::scalar ? *p->unit : p->blocks;

  auto it = p->counters.find(std::string(info->name));
  if (it == p->counters.end()) {
    const Ordering o = compute_ordering(*info, p->blocks, p->a);
    const OrderingSummary s = summarize(o, p->blocks, p->scalar_graph);
    Counters c;
    c.nnz_L = static_cast<double>(s.nnz_L);
    c.flops = s.flops;
    if (s.block) c.fill_edges = static_cast<double>(s.block->fill_edges);
    it = p->counters.emplace(std::string(info->name), c).first;
  }

  for (auto _ : state) {
    std::vector<int> pivots = info->fn(pattern);
    benchmark::DoNotOptimize(pivots.data());
    benchmark::ClobberMemory();
  }

  const Counters& c = it->second;
  state.counters["blocks"] = p->blocks.num_blocks();
  state.counters["n"] = p->a.n;
  state.counters["nnz_L"] = c.nnz_L;
  state.counters["flops"] = c.flops;
  if (c.fill_edges) state.counters["fill_edges"] = *c.fill_edges;
}

// exact = false leaves out the explicit-graph orderings (-exact), for the scale cases where
// they take minutes.
void register_problem(const std::string& label, const std::string& key, MakeProblem make, bool exact = true) {
  auto shared = std::make_shared<MakeProblem>(std::move(make));
  for (const OrderingInfo& info : orderings()) {
    if (!exact && info.name.ends_with("-exact")) continue;
    const std::string name = "order/" + std::string(info.name) + "/" + label;
    benchmark::RegisterBenchmark(name.c_str(),
                                 [info = &info, key, shared](benchmark::State& state) {
                                   bench_ordering(state, info, key, *shared);
                                 })
        ->Unit(benchmark::kMillisecond);
  }
}

void register_families() {
  for (std::string_view family : family_names()) {
    for (int size : kSizes) {
      if (family == "heavy" && size > kHeavyMaxSize) continue;
      const std::string label = std::string(family) + "/" + std::to_string(size);
      register_problem(label, "family:" + label, [family = std::string(family), size](Problem& p) {
        p.blocks = constraint_graph(make_family(family, size));
        p.a = p.blocks.expand();
      });
    }
  }
}

// The scale targets (papers/orderings.md): a grid and a ladder of 1e5 constraints (quotient-graph
// orderings under 2 s), and a star whose hub carries 1000 arms, as its block graph: a
// 1000-clique of 3-row blocks (under 1 s; every elimination in it costs the explicit graph
// O(degree^2), so the -exact orderings are kept for comparison).
void register_scale_cases() {
  for (const char* family : {"grid", "ladder"}) {
    const std::string label = std::string(family) + "/100000";
    register_problem(
        label, "family:" + label,
        [family = std::string(family)](Problem& p) {
          p.blocks = constraint_graph(make_family(family, 100000));
          p.a = p.blocks.expand();
        },
        false);
  }
  register_problem("hub-clique/1000", "hub-clique/1000", [](Problem& p) {
    constexpr int kArms = 1000;
    std::vector<std::pair<int, int>> edges;
    for (int u = 0; u < kArms; ++u) {
      for (int v = u + 1; v < kArms; ++v) edges.emplace_back(u, v);
    }
    p.blocks = BlockPattern(std::vector<int>(kArms, 3), graph_from_edges(kArms, edges));
    p.a = p.blocks.expand();
  });
}

bool register_matrices() {
  namespace fs = std::filesystem;
  const std::vector<fs::path> files = test_matrix_files(LDLPGS_MATRICES, "orderings_bench");
  if (files.empty()) return false;
  for (const fs::path& path : files) {
    const std::string stem = path.stem().string();
    register_problem(stem, "matrix:" + path.string(), [path = path.string()](Problem& p) {
      p.a = read_matrix_market(path);
      p.blocks = BlockPattern::from_scalar(p.a, partition_auto(p.a));
    });
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  const bool has_min_time = std::any_of(args.begin() + 1, args.end(), [](const char* a) {
    return std::string_view(a).starts_with("--benchmark_min_time");
  });
  std::string min_time = kMinTimeFlag;
  if (!has_min_time) args.insert(args.begin() + 1, min_time.data());
  int args_count = static_cast<int>(args.size());
  args.push_back(nullptr);
  benchmark::Initialize(&args_count, args.data());
  if (benchmark::ReportUnrecognizedArguments(args_count, args.data())) return 1;
  register_families();
  register_scale_cases();
  if (!register_matrices()) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
