#pragma once
// The problems the CLI orders, verifies and benchmarks: a symmetric matrix with its block
// partition, read from a Matrix Market file, generated as a mechanism family, or a scene's H_0.
#include <string>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs::cli {

struct Problem {
  std::string name;  // file name or family name with its size
  SymmetricCsc a;
  BlockPattern blocks;
  Graph scalar_graph;
};

// Reads a Matrix Market file and partitions it (spec as --blocks: auto, N or FILE).
Problem load_matrix(const std::string& path, const std::string& blocks_spec, int max_block);
// A generated mechanism: its constraint graph, values H = J W J^T + 1e-6 diag (mechanism_matrix.h).
Problem make_mechanism(const std::string& family, int num_constraints);
// A scene's H_0 = J W J^T + eps diag(H) over its equality constraints at the initial pose, one
// block per constraint (what `ldlpgs export --no-shatter` writes).
Problem scene_problem(const Mechanism& m);
// A Matrix Market file, or FAMILY:CONSTRAINTS (e.g. chain:100) for a generated mechanism.
// split_blocks: the matrix without its exact zeros (without_zeros) and its blocks refined by
// partition_refine, so orderings, CHOLMOD and the factor all see the nonzero values' pattern.
Problem load_problem(const std::string& spec, const std::string& blocks_spec, int max_block,
                     bool split_blocks = false);

}  // namespace ldlpgs::cli
