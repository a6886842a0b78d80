// ldlpgs verify MATRIX: our block LDL^T beside CHOLMOD's simplicial LDL^T under the same
// permutation (factor/verify.h); exit code 1 when they disagree beyond the printed tolerance,
// when no tolerance could be computed (cond_1 inf) or it checks no digit (>= 1), or when either
// side refuses the matrix.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "apps/commands.h"
#include "apps/compare.h"
#include "apps/options.h"
#include "ldlpgs/factor/verify.h"

namespace ldlpgs::cli {

namespace {

void print(const Problem& p, const Verification& v) {
  std::printf("%s: n = %d, %d blocks, ordering %s\n", p.name.c_str(), p.a.n, p.blocks.num_blocks(),
              shown_name(v.ordering, v.chosen).c_str());
  std::printf("%-24s %14s %14s\n", "", "ldlpgs", "CHOLMOD");
  std::printf("%-24s %14lld %14lld\n", "nnz(L)", static_cast<long long>(v.nnz_L), static_cast<long long>(v.nnz_L_cholmod));
  std::printf("%-24s %14.0f %14.0f\n", "flops", v.flops, v.flops_cholmod);
  const double t = v.factor_tolerance;
  // Either side refusing the matrix leaves nothing to compare: said as such, not as a
  // disagreement, and without the NaN differences and zero tolerance left in its fields.
  // CHOLMOD stops only at an exactly zero pivot, ours at its threshold
  // (FactorOptions::zero_pivot), so a nearly singular matrix may stop one and not the other.
  const Verdict said = verdict(v);
  if (said != Verdict::not_verified) {
    std::printf("%-24s %14.2e %14.2e   (tolerance %.0e)\n", "backward error", v.backward_error,
                v.backward_error_cholmod, v.tolerance.backward);
    std::printf("%-24s %14.2e\n", "condition estimate", v.condition_estimate);
    std::printf("%-24s %14.2e   (tolerance %.1e)\n", "L max rel. difference", v.L_rel_diff, t);
    std::printf("%-24s %14.2e   (tolerance %.1e)\n", "D max rel. difference", v.D_rel_diff, t);
    std::printf("%-24s %14.2e   (tolerance %.1e)\n", "x rel. difference", v.x_rel_diff, t);
  }
  std::printf("factorization: %s\n", v.info.message().c_str());
  if (said == Verdict::not_verified) {
    const std::string cholmod = v.cholmod_row >= 0 ? "stopped at a zero pivot in row " + std::to_string(v.cholmod_row)
                                                   : "status " + std::to_string(v.cholmod_status);
    std::printf("NOT VERIFIED: %s; CHOLMOD %s\n", v.info.usable() ? "ours factored" : "ours failed (above)",
                v.cholmod_factored() ? "factored" : cholmod.c_str());
  } else if (said == Verdict::cannot_verify) {
    std::printf("CANNOT VERIFY: the tolerance for L, D and x is %.1e (condition estimate %.2e), so no digit is "
                "checked\n", t, v.condition_estimate);
  } else {
    std::printf("%s\n", v.ok ? "agree" : "DISAGREE");
  }
}

}  // namespace

Verdict verdict(const Verification& v) {
  if (!v.info.usable() || !v.cholmod_factored()) return Verdict::not_verified;
  if (!v.verifiable) return Verdict::cannot_verify;
  return v.ok ? Verdict::agree : Verdict::disagree;
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::agree: return "yes";
    case Verdict::disagree: return "no";
    case Verdict::not_verified: return "not verified";
    case Verdict::cannot_verify: return "cannot verify";
  }
  return "";
}

std::string not_agreeing(const std::vector<std::pair<std::string, Verification>>& rows) {
  std::string said;
  for (auto [kind, words] : {std::pair{Verdict::disagree, "disagree"},
                             {Verdict::not_verified, "not verified (a solver refused the matrix)"},
                             {Verdict::cannot_verify, "cannot verify (the tolerance checks no digit)"}}) {
    const auto count = std::count_if(rows.begin(), rows.end(), [&](const auto& r) { return verdict(r.second) == kind; });
    if (count > 0) said += (said.empty() ? "" : ", ") + std::to_string(count) + " " + words;
  }
  return said;
}

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
    // anything but yes stands out: bold in Markdown, capitals in text
    const Verdict said = verdict(v);
    std::string agree = to_string(said);
    if (said != Verdict::agree) {
      if (markdown) agree = "**" + agree + "**";
      else std::transform(agree.begin(), agree.end(), agree.begin(), [](unsigned char c) { return std::toupper(c); });
    }
    // a refused matrix has nothing measured: "-", not the NaNs left in its fields
    const bool measured = said != Verdict::not_verified;
    auto number = [&](double x, const char* format) {
      char text[32] = "-";
      if (measured) std::snprintf(text, sizeof text, format, x);
      return std::string(text);
    };
    const std::string cells[] = {number(v.condition_estimate, "%.1e"), number(v.L_rel_diff, "%.1e"),
                                 number(v.D_rel_diff, "%.1e"),         number(v.x_rel_diff, "%.1e"),
                                 number(v.factor_tolerance, "%.0e"),   number(v.backward_error, "%.1e"),
                                 number(v.backward_error_cholmod, "%.1e")};
    const char* format = markdown ? "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n"
                                  : "%-16s %-8s %9s %9s %9s %9s %9s %12s %14s %6s\n";
    std::fprintf(out, format, name.c_str(), v.ordering.c_str(), cells[0].c_str(), cells[1].c_str(), cells[2].c_str(),
                 cells[3].c_str(), cells[4].c_str(), cells[5].c_str(), cells[6].c_str(), agree.c_str());
  }
}

Command add_verify_command(CLI::App& app) {
  struct Options {
    ProblemArgs problem;
    std::string ordering = "best";
    VerifyTolerance tolerance;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("verify", "Compare the block LDL^T with CHOLMOD's on one matrix");
  add_problem_options(cmd, &o->problem);
  add_ordering_option(cmd, &o->ordering, "Ordering name");
  cmd->add_option("--tolerance", o->tolerance.factor, "Largest relative difference of L, D and x on a "
                  "well-conditioned matrix; on others, --per-condition times the condition estimate")
      ->capture_default_str()
      ->check(finite_in(0));
  cmd->add_option("--per-condition", o->tolerance.per_condition, "Tolerance per unit of condition number")
      ->capture_default_str()
      ->check(finite_in(0));
  cmd->add_option("--backward-tolerance", o->tolerance.backward, "Largest backward error")
      ->capture_default_str()
      ->check(finite_in(0));
  add_json_flag(cmd, &o->json);
  return [o] {
    const OrderingInfo& info = find_ordering(o->ordering);
    const Problem p = load_problem(o->problem.spec, o->problem.blocks, o->problem.max_block, o->problem.split_blocks);
    const Ordering ordering = compute_ordering(info, p.blocks, p.a);
    const Verification v = verify_against_cholmod(p.a, p.blocks, ordering, o->tolerance);
    if (o->json) print_json(json_header("verify", to_json(p, v)));
    else print(p, v);
    return v.ok ? 0 : 1;
  };
}

}  // namespace ldlpgs::cli
