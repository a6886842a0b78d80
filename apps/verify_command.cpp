// ldlpgs verify MATRIX: our block LDL^T beside CHOLMOD's simplicial LDL^T under the same
// permutation (factor/verify.h); exit code 1 when they disagree beyond the printed tolerance.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "apps/commands.h"
#include "apps/compare.h"
#include "ldlpgs/factor/verify.h"

namespace ldlpgs::cli {

namespace {

nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json to_json(const Problem& p, const Verification& v) {
  return {{"matrix", p.name},
          {"n", p.a.n},
          {"blocks", p.blocks.num_blocks()},
          {"ordering", v.ordering},
          {"nnz_L", v.nnz_L},
          {"nnz_L_cholmod", v.nnz_L_cholmod},
          {"flops", v.flops},
          {"flops_cholmod", v.flops_cholmod},
          {"L_rel_diff", number(v.L_rel_diff)},
          {"D_rel_diff", number(v.D_rel_diff)},
          {"x_rel_diff", number(v.x_rel_diff)},
          {"backward_error", number(v.backward_error)},
          {"backward_error_cholmod", number(v.backward_error_cholmod)},
          {"status", to_string(v.info.status)},
          {"inertia", {v.info.inertia.positive, v.info.inertia.negative, v.info.inertia.zero}},
          {"min_pivot_ratio", v.info.min_pivot_ratio},
          {"cholmod_status", v.cholmod_status},
          {"condition_estimate", number(v.condition_estimate)},
          {"tolerance", {{"factor", number(v.factor_tolerance)}, {"backward", v.tolerance.backward}}},
          {"ok", v.ok}};
}

void print(const Problem& p, const Verification& v) {
  std::printf("%s: n = %d, %d blocks, ordering %s\n", p.name.c_str(), p.a.n, p.blocks.num_blocks(), v.ordering.c_str());
  std::printf("%-24s %14s %14s\n", "", "ldlpgs", "CHOLMOD");
  std::printf("%-24s %14lld %14lld\n", "nnz(L)", static_cast<long long>(v.nnz_L), static_cast<long long>(v.nnz_L_cholmod));
  std::printf("%-24s %14.0f %14.0f\n", "flops", v.flops, v.flops_cholmod);
  std::printf("%-24s %14.2e %14.2e   (tolerance %.0e)\n", "backward error", v.backward_error,
              v.backward_error_cholmod, v.tolerance.backward);
  std::printf("%-24s %14.2e\n", "condition estimate", v.condition_estimate);
  const double t = v.factor_tolerance;
  std::printf("%-24s %14.2e   (tolerance %.1e)\n", "L max rel. difference", v.L_rel_diff, t);
  std::printf("%-24s %14.2e   (tolerance %.1e)\n", "D max rel. difference", v.D_rel_diff, t);
  std::printf("%-24s %14.2e   (tolerance %.1e)\n", "x rel. difference", v.x_rel_diff, t);
  std::printf("factorization: %s\n", v.info.message().c_str());
  std::printf("%s\n", v.ok ? "agree" : "DISAGREE");
}

}  // namespace

void print_verification_table(std::FILE* out, const std::vector<std::pair<std::string, Verification>>& rows,
                              bool markdown) {
  const char* header[] = {"problem", "ordering", "cond_1", "L diff", "D diff", "x diff", "tolerance",
                          "backward err", "CHOLMOD b. err", "agree"};
  if (markdown) {
    std::fprintf(out, "|");
    for (const char* h : header) std::fprintf(out, " %s |", h);
    std::fprintf(out, "\n|");
    for (size_t i = 0; i < std::size(header); ++i) std::fprintf(out, "---|");
    std::fprintf(out, "\n");
  } else {
    std::fprintf(out, "%-16s %-8s %9s %9s %9s %9s %9s %12s %14s %6s\n", header[0], header[1], header[2], header[3],
                 header[4], header[5], header[6], header[7], header[8], header[9]);
  }
  for (const auto& [name, v] : rows) {
    const char* agree = v.ok ? "yes" : (markdown ? "**no**" : "NO");
    const char* format = markdown ? "| %s | %s | %.1e | %.1e | %.1e | %.1e | %.0e | %.1e | %.1e | %s |\n"
                                  : "%-16s %-8s %9.1e %9.1e %9.1e %9.1e %9.0e %12.1e %14.1e %6s\n";
    std::fprintf(out, format, name.c_str(), v.ordering.c_str(), v.condition_estimate, v.L_rel_diff, v.D_rel_diff,
                 v.x_rel_diff, v.factor_tolerance, v.backward_error, v.backward_error_cholmod, agree);
  }
}

Command add_verify_command(CLI::App& app) {
  struct Options {
    std::string matrix, blocks = "auto", ordering = "meca";
    int max_block = 6;
    VerifyTolerance tolerance;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("verify", "Compare the block LDL^T with CHOLMOD's on one matrix");
  cmd->add_option("matrix", o->matrix, "Matrix Market file (symmetric), or FAMILY:CONSTRAINTS for a generated "
                                       "mechanism with H = J W J^T values (e.g. grid:100)")->required();
  cmd->add_option("--blocks", o->blocks, "Block partition: auto, N (uniform) or a file of block sizes")->capture_default_str();
  cmd->add_option("--max-block", o->max_block, "Largest block --blocks auto forms")->capture_default_str();
  cmd->add_option("--ordering", o->ordering, "Ordering name")->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance.factor, "Largest relative difference of L, D and x on a "
                  "well-conditioned matrix; on others, --per-condition times the condition estimate")->capture_default_str();
  cmd->add_option("--per-condition", o->tolerance.per_condition, "Tolerance per unit of condition number")->capture_default_str();
  cmd->add_option("--backward-tolerance", o->tolerance.backward, "Largest backward error")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of a table");
  return [o] {
    const OrderingInfo& info = find_ordering(o->ordering);
    const Problem p = load_problem(o->matrix, o->blocks, o->max_block);
    const Ordering ordering = compute_ordering(info, p.blocks, p.a);
    const Verification v = verify_against_cholmod(p.a, p.blocks, ordering, o->tolerance);
    if (o->json) std::cout << to_json(p, v).dump(2) << '\n';
    else print(p, v);
    return v.ok ? 0 : 1;
  };
}

}  // namespace ldlpgs::cli
