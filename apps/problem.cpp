// The CLI's problems (problem.h).
#include "apps/problem.h"

#include "apps/options.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/mechanism_matrix.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs::cli {

Problem load_matrix(const std::string& path, const std::string& blocks_spec, int max_block) {
  Problem p;
  p.name = std::filesystem::path(path).filename().string();
  p.a = read_matrix_market(path);
  // (CHOLMOD refuses n = 0, and there is nothing to order, factor or time.)
  if (p.a.n == 0) throw InputError(path + ": a 0 x 0 matrix: nothing to order or factor");
  p.blocks = BlockPattern::from_scalar(p.a, parse_partition(blocks_spec, p.a, max_block));
  p.scalar_graph = graph_of(p.a);
  return p;
}

Problem make_mechanism(const std::string& family, int num_constraints) {
  Problem p;
  p.blocks = constraint_graph(make_family(family, num_constraints));
  p.name = family + "-" + std::to_string(p.blocks.num_blocks());
  p.a = mechanism_matrix(make_family(family, num_constraints));
  p.scalar_graph = graph_of(p.a);
  return p;
}

Problem scene_problem(const Mechanism& m) {
  Problem p;
  p.name = m.name;
  std::vector<int> sizes;
  p.a = equality_matrix(build_system(m, StepOptions{}), &sizes);
  p.blocks = BlockPattern::from_scalar(p.a, sizes);
  p.scalar_graph = graph_of(p.a);
  return p;
}

namespace {

Problem split_blocks(Problem p) {
  p.a = without_zeros(p.a);
  p.blocks = BlockPattern::from_scalar(p.a, partition_refine(p.a, p.blocks.block_sizes()));
  p.scalar_graph = graph_of(p.a);
  return p;
}

Problem load_unsplit(const std::string& spec, const std::string& blocks_spec, int max_block) {
  const size_t colon = spec.rfind(':');
  if (colon == std::string::npos || std::filesystem::exists(spec)) return load_matrix(spec, blocks_spec, max_block);
  const std::string family = spec.substr(0, colon), count = spec.substr(colon + 1);
  // A generated mechanism has its blocks already, one per constraint: a partition asked for it
  // was ignored without a word.
  if (blocks_spec != ProblemArgs{}.blocks)
    throw InputError(spec + ": --blocks " + blocks_spec + " is for a Matrix Market file (a generated mechanism has "
                     "one block per constraint)");
  if (max_block != ProblemArgs{}.max_block)
    throw InputError(spec + ": --max-block is for --blocks auto on a Matrix Market file (a generated mechanism has "
                     "one block per constraint)");
  int m = 0;
  try {
    size_t used = 0;
    m = std::stoi(count, &used);
    if (used != count.size() || m < 1) throw std::invalid_argument(count);
  } catch (const std::logic_error&) {
    throw InputError(spec + ": expected FAMILY:CONSTRAINTS with a positive count, got '" + count + "'");
  }
  return make_mechanism(family, m);  // throws InputError naming an unknown family
}

}  // namespace

Problem load_problem(const std::string& spec, const std::string& blocks_spec, int max_block, bool split) {
  Problem p = load_unsplit(spec, blocks_spec, max_block);
  return split ? split_blocks(std::move(p)) : p;
}

}  // namespace ldlpgs::cli
