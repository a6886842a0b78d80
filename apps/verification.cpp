// Verdicts and tables of the block LDL^T against CHOLMOD (verification.h).
#include "apps/verification.h"

#include <algorithm>
#include <cctype>
#include <iterator>

#include "apps/options.h"

namespace ldlpgs::cli {

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

nlohmann::json to_json(const Problem& p, const Verification& v) {
  const Inertia& in = v.info.inertia;
  return {{"matrix", p.name},
          {"n", p.a.n},
          {"blocks", p.blocks.num_blocks()},
          {"ordering", v.ordering},
          {"chosen", v.chosen},
          {"nnz_L", v.nnz_L},
          {"cholmod_nnz_L", v.nnz_L_cholmod},
          {"flops", v.flops},
          {"cholmod_flops", v.flops_cholmod},
          {"L_rel_diff", number_or_null(v.L_rel_diff)},
          {"D_rel_diff", number_or_null(v.D_rel_diff)},
          {"x_rel_diff", number_or_null(v.x_rel_diff)},
          {"backward_error", number_or_null(v.backward_error)},
          {"cholmod_backward_error", number_or_null(v.backward_error_cholmod)},
          {"status", to_string(v.info.status)},
          {"inertia", {{"positive", in.positive}, {"negative", in.negative}, {"zero", in.zero}}},
          {"min_pivot_ratio", v.info.min_pivot_ratio},
          {"cholmod_status", v.cholmod_status},
          {"cholmod_row", v.cholmod_row >= 0 ? nlohmann::json(v.cholmod_row) : nlohmann::json(nullptr)},
          {"condition_estimate", number_or_null(v.condition_estimate)},
          {"tolerance", {{"factor", number_or_null(v.factor_tolerance)}, {"backward", v.tolerance.backward}}},
          {"verifiable", v.verifiable},
          {"ok", v.ok}};
}

}  // namespace ldlpgs::cli
