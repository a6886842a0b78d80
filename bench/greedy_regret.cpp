// Not a timing: how often an ordering passes over a block that would create fewer new edges than
// the one it takes, replayed on the explicit elimination graph. At each step of the ordering's
// pivot sequence it compares the fill of the block taken (pairs of its neighbours not yet
// adjacent, each weighted w_u w_v by block size for a weighted ordering, as meca-w counts them)
// with the least fill of any block left: the regret of that step against the exact greedy choice
// (what meca-exact and meca-w-exact take). papers/orderings.md uses it on bcsstk13:
//   build/bin/greedy_regret tests/data/matrices/bcsstk13.mtx meca-w
// Cost: each step counts every live block, O(blocks x sum of neighbour degrees); 30 s there.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

using namespace ldlpgs;

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: greedy_regret MATRIX.mtx|FAMILY:CONSTRAINTS ORDERING [STEPS_SHOWN]\n");
    return 2;
  }
  try {
    const std::string problem = argv[1];
    const OrderingInfo& info = find_ordering(argv[2]);
    if (info.level != Level::block) throw InputError(std::string(argv[2]) + ": a block ordering is needed");
    const int shown = argc == 4 ? std::atoi(argv[3]) : 10;
    BlockPattern pattern;
    const size_t colon = problem.rfind(':');
    if (problem.size() > 4 && problem.substr(problem.size() - 4) == ".mtx") {
      const SymmetricCsc a = read_matrix_market(problem);
      pattern = BlockPattern::from_scalar(a, partition_auto(a));
    } else if (colon != std::string::npos) {
      pattern = constraint_graph(make_family(problem.substr(0, colon), std::stoi(problem.substr(colon + 1))));
    } else {
      throw InputError(problem + ": neither a .mtx file nor FAMILY:CONSTRAINTS");
    }
    const int nb = pattern.num_blocks();
    // The weights the ordering's own score uses: block sizes for the weighted forms.
    const std::string name(info.name);
    const bool weighted = name.find("-w") != std::string::npos;
    std::vector<int> weight(nb, 1);  // (size nb)
    if (weighted) weight = pattern.block_sizes();

    const std::vector<int> pivots = info.fn(pattern);
    EliminationGraph g(pattern.graph());
    int64_t total = 0, regret = 0;
    int steps = 0, first = -1;
    for (int k = 0; k < nb; ++k) {
      const int taken = pivots[k];
      const int64_t fill = g.fill_if_eliminated(taken, weight);
      int64_t least = fill;
      int argmin = taken;
      for (int v = 0; v < nb; ++v) {
        if (g.eliminated(v) || v == taken) continue;
        const int64_t f = g.fill_if_eliminated(v, weight);
        if (f < least) {
          least = f;
          argmin = v;
        }
      }
      if (least < fill) {
        if (first < 0) first = k;
        if (steps++ < shown)
          std::printf("step %d: took block %d (fill %lld, degree %d); block %d had fill %lld (degree %d)\n", k, taken,
                      static_cast<long long>(fill), g.degree(taken), argmin, static_cast<long long>(least),
                      g.degree(argmin));
        regret += fill - least;
      }
      total += fill;
      g.eliminate(taken);
    }
    const std::string at = first < 0 ? "" : " (the first at step " + std::to_string(first) + ")";
    std::printf("%s on %s: %d blocks; %d steps took a block with more %s than the least%s; %s fill %lld, sum of "
                "the steps' excess %lld\n",
                name.c_str(), problem.c_str(), nb, steps, weighted ? "weighted fill" : "fill", at.c_str(),
                weighted ? "weighted" : "block", static_cast<long long>(total), static_cast<long long>(regret));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "greedy_regret: %s\n", e.what());
    return 2;
  }
  return 0;
}
