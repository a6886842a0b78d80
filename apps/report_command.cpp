// ldlpgs report: the main job. For now, the orderings comparison on the generated mechanism
// families and on the test matrices (papers/orderings.md is its --markdown output), then the
// block LDL^T of each of them verified against CHOLMOD's (factor/verify.h).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "apps/commands.h"
#include "apps/compare.h"
#include "sparse/error.h"
#include "sparse/families.h"

namespace ldlpgs::cli {

Command add_report_command(CLI::App& app) {
  struct Options {
    std::string matrices = LDLPGS_SOURCE_DIR "/tests/data/matrices", orderings = "all";
    std::vector<int> sizes = {100, 1000, 5000};
    std::string verify = "meca";
    bool markdown = false, cholmod = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("report", "The orderings comparison on mechanism families and test matrices");
  cmd->add_option("--matrices", o->matrices, "Directory of Matrix Market files")->capture_default_str();
  cmd->add_option("--sizes", o->sizes, "Constraint counts of the generated mechanisms")->capture_default_str()
      ->delimiter(',');
  cmd->add_option("--orderings", o->orderings, "Comma-separated ordering names, or all")->capture_default_str();
  cmd->add_flag("--markdown", o->markdown, "Markdown tables (papers/orderings.md)");
  cmd->add_flag("--cholmod", o->cholmod, "Add CHOLMOD's counts for each permutation");
  cmd->add_option("--verify", o->verify, "Ordering of the factorizations verified against CHOLMOD")->capture_default_str();
  return [o] {
    const std::vector<std::string> names = parse_ordering_list(o->orderings);
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(o->matrices, ec)) {
      if (entry.path().extension() == ".mtx") files.push_back(entry.path().string());
    }
    if (ec) throw InputError(o->matrices + ": cannot read directory (" + ec.message() + ")");
    std::sort(files.begin(), files.end());
    // Text: one table per problem. Markdown: one table per metric, a row per problem, the
    // best of each row marked (papers/orderings.md).
    std::vector<std::pair<Problem, std::vector<Row>>> results;
    auto show = [&](Problem p) {
      std::vector<Row> rows = compare(p, names, o->cholmod);
      if (!o->markdown) {
        print_table(stdout, p, rows);
        std::fflush(stdout);
      }
      for (Row& r : rows) r.ordering = Ordering();  // keep the summaries, not the permutations
      results.emplace_back(std::move(p), std::move(rows));
    };
    for (std::string_view family : family_names()) {
      for (int size : o->sizes) {
        // The heavy body makes H dense: past a few hundred constraints that is a dense matrix
        // with nothing left to order, and the explicit elimination graph holds all its edges.
        if (family == "heavy" && size > 500) continue;
        std::fprintf(stderr, "report: %s, %d constraints\n", std::string(family).c_str(), size);
        show(make_mechanism(std::string(family), size));
      }
    }
    for (const std::string& file : files) {
      std::fprintf(stderr, "report: %s\n", file.c_str());
      try {
        show(load_matrix(file, "auto", 6));
      } catch (const InputError& e) {
        // An unsymmetric matrix has no LDL^T: the comparison skips it and says why.
        std::printf("%sskipped: %s\n", o->markdown ? "\n" : "", e.what());
      }
    }
    if (o->markdown) print_markdown_by_metric(stdout, results);
    // The factorization of every problem, in the ordering o->verify, against CHOLMOD's.
    const OrderingInfo& verify_ordering = find_ordering(o->verify);
    std::vector<std::pair<std::string, Verification>> checks;
    for (const auto& [p, rows] : results) {
      std::fprintf(stderr, "report: verifying %s\n", p.name.c_str());
      checks.emplace_back(p.name, verify_against_cholmod(p.a, p.blocks, compute_ordering(verify_ordering, p.blocks, p.a)));
    }
    std::printf(o->markdown ? "\n### The block LDL^T against CHOLMOD\n\n" : "\nThe block LDL^T against CHOLMOD's simplicial LDL^T, same permutation:\n");
    print_verification_table(stdout, checks, o->markdown);
    const bool all_agree = std::all_of(checks.begin(), checks.end(), [](const auto& c) { return c.second.ok; });
    if (!all_agree) std::printf("DISAGREEMENT: see the rows marked no (tolerances in factor/verify.h)\n");
    return all_agree ? 0 : 1;
  };
}

}  // namespace ldlpgs::cli
