#pragma once
// The block LDL^T against CHOLMOD (factor/verify.h) as the CLI reports it: a verdict per problem,
// the table of `verify` and `report`, and the JSON record.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "apps/problem.h"
#include "ldlpgs/factor/verify.h"

namespace ldlpgs::cli {

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
