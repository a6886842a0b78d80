// How the tie-breaking of MDA and MECA changes the block flops of the factorization: the
// measurement behind the defaults in ordering/mda.cpp and ordering/meca.cpp. Prints a Markdown
// table (papers/orderings.md quotes it):
//   build/bin/tie_breaking > /tmp/tie_breaking.md
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

using namespace ldlpgs;

namespace {

struct Variant {
  const char* name;
  std::vector<int> (*fn)(const BlockPattern&, bool, TieBreak);
  bool weighted;
  TieBreak tie;
};

const Variant kVariants[] = {
    {"mda lowest", minimum_degree, false, TieBreak::lowest_index},
    {"mda highest", minimum_degree, false, TieBreak::highest_index},
    {"mda-w lowest", minimum_degree, true, TieBreak::lowest_index},
    {"mda-w highest", minimum_degree, true, TieBreak::highest_index},
    {"meca degree", minimum_edge_creation, false, TieBreak::least_degree},
    {"meca lowest", minimum_edge_creation, false, TieBreak::lowest_index},
    {"meca highest", minimum_edge_creation, false, TieBreak::highest_index},
    {"meca-w degree", minimum_edge_creation, true, TieBreak::least_degree},
    {"meca-w lowest", minimum_edge_creation, true, TieBreak::lowest_index},
    {"meca-w highest", minimum_edge_creation, true, TieBreak::highest_index},
};
constexpr int kNumVariants = sizeof(kVariants) / sizeof(kVariants[0]);

}  // namespace

int main() {
  std::vector<std::pair<std::string, BlockPattern>> problems;
  for (std::string_view family : family_names()) {
    for (int size : {100, 1000, 5000}) {
      if (family == "heavy" && size > 100) continue;  // dense: every order costs the same
      problems.emplace_back(std::string(family) + "-" + std::to_string(size),
                            constraint_graph(make_family(family, size)));
    }
  }
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(LDLPGS_MATRICES)) {
    if (e.path().extension() == ".mtx" && e.path().filename() != "Pd.mtx") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  for (const std::string& f : files) {
    const SymmetricCsc a = read_matrix_market(f);
    problems.emplace_back(std::filesystem::path(f).filename().string(), BlockPattern::from_scalar(a, partition_auto(a)));
  }

  std::printf("| problem |");
  for (const Variant& v : kVariants) std::printf(" %s |", v.name);
  std::printf("\n|---|");
  for (int i = 0; i < kNumVariants; ++i) std::printf("---:|");
  std::printf("\n");
  // Geometric means of each variant's block flops relative to the pair's first variant.
  std::vector<double> log_ratio(kNumVariants, 0.0);
  for (const auto& [name, p] : problems) {
    std::printf("| %s |", name.c_str());
    double base = 0;
    for (int i = 0; i < kNumVariants; ++i) {
      const Variant& v = kVariants[i];
      const std::vector<int> pivots = v.fn(p, v.weighted, v.tie);
      const double flops = block_costs(p, pivots, eliminate(p, pivots)).flops;
      if (i == 0 || kVariants[i - 1].fn != v.fn || kVariants[i - 1].weighted != v.weighted) base = flops;
      log_ratio[i] += std::log(flops / base);
      std::printf(" %.4g |", flops);
    }
    std::printf("\n");
  }
  std::printf("| geometric mean vs. first of its group |");
  for (int i = 0; i < kNumVariants; ++i) std::printf(" %.3f |", std::exp(log_ratio[i] / problems.size()));
  std::printf("\n");
  return 0;
}
