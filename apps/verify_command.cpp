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
#include "apps/problem.h"
#include "apps/verification.h"
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
