// ldlpgs report: the main job. For now, the orderings comparison on the generated mechanism
// families and on the test matrices (papers/orderings.md is its --markdown output).
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
    return 0;
  };
}

}  // namespace ldlpgs::cli
