#pragma once
// The orderings comparison shared by `ldlpgs order` and `ldlpgs report`: one matrix with its
// block partition, every requested ordering run on it, and the output as a table or JSON.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "apps/problem.h"
#include "ldlpgs/ordering/certify.h"
#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/sparse/cholmod_adapter.h"

namespace ldlpgs::cli {

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
// The problem's matrix, n, blocks and a row per ordering (docs/cli.md, "Command-line vocabulary").
nlohmann::json to_json(const Problem& p, const std::vector<Row>& rows);
// order --certify: the certificate's fields, and in each block ordering's row whether it is
// optimal (its block flops equal the proved optimum or a lower bound).
void add_certificate(nlohmann::json* j, const std::vector<Row>& rows, const BlockFlopsCertificate& cert);
void print_certificate(std::FILE* out, const std::vector<Row>& rows, const BlockFlopsCertificate& cert);
}  // namespace ldlpgs::cli
