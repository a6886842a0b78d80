#pragma once
// The orderings comparison shared by `ldlpgs order` and `ldlpgs report`: one matrix with its
// block partition, every requested ordering run on it, and the output as a table or JSON.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ldlpgs/factor/verify.h"
#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/ordering/certify.h"
#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/sparse/cholmod_adapter.h"

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

struct Row {
  OrderingSummary summary;
  Ordering ordering;
  std::optional<CholmodCounts> cholmod;  // CHOLMOD's counts for the same permutation
};

// `before` (if given) is called with each ordering's name before it runs: order's progress line.
std::vector<Row> compare(const Problem& p, const std::vector<std::string>& names, bool with_cholmod,
                         const std::function<void(const std::string&)>& before = {});

// One table: a row per ordering, the best of each column marked '*'.
void print_table(std::FILE* out, const Problem& p, const std::vector<Row>& rows);
// Three tables (nnz(L), flops, block flops): a row per problem, a column per ordering, the
// best of each row in bold.
void print_markdown_by_metric(std::FILE* out, const std::vector<std::pair<Problem, std::vector<Row>>>& results);
// The problem's matrix, n, blocks and a row per ordering (README.md, "Command-line vocabulary").
nlohmann::json to_json(const Problem& p, const std::vector<Row>& rows);
// order --certify: the certificate's fields, and in each block ordering's row whether it is
// optimal (its block flops equal the proved optimum or a lower bound).
void add_certificate(nlohmann::json* j, const std::vector<Row>& rows, const BlockFlopsCertificate& cert);
void print_certificate(std::FILE* out, const std::vector<Row>& rows, const BlockFlopsCertificate& cert);
// One verification (verify --json, report/data/verification.*).
nlohmann::json to_json(const Problem& p, const Verification& v);

// What a verification concluded: every difference within the tolerance, one beyond it, nothing to
// compare (ours or CHOLMOD refused the matrix), or a tolerance that checks no digit (factor/verify.h).
enum class Verdict { agree, disagree, not_verified, cannot_verify };
Verdict verdict(const Verification& v);
// As the tables print it: "yes", "no", "not verified", "cannot verify".
const char* to_string(Verdict v);
// The rows that do not agree, counted by kind: "1 disagree, 2 not verified (a solver refused the
// matrix)"; "" when all agree.
std::string not_agreeing(const std::vector<std::pair<std::string, Verification>>& rows);

// The block LDL^T against CHOLMOD (factor/verify.h), one row per problem, as text or Markdown
// (verify_command.cpp); the last column is to_string(verdict()).
void print_verification_table(std::FILE* out, const std::vector<std::pair<std::string, Verification>>& rows,
                              bool markdown);

}  // namespace ldlpgs::cli
