// ldlpgs order PROBLEM: every requested ordering on one matrix (a file or a generated mechanism), with nnz(L), flops, block
// fill and block flops, optionally beside CHOLMOD's own counts for the same permutations.
#include <filesystem>
#include <fstream>

#include "apps/commands.h"
#include "apps/compare.h"
#include "apps/options.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

Command add_order_command(CLI::App& app) {
  struct Options {
    ProblemArgs problem;
    std::string orderings = "all", perm_dir;
    bool json = false, cholmod = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("order", "Compare elimination orderings on a Matrix Market matrix or a generated mechanism");
  add_problem_options(cmd, &o->problem);
  add_ordering_option(cmd, &o->orderings, "Orderings to compare", true);
  add_json_flag(cmd, &o->json);
  cmd->add_option("--perm-dir", o->perm_dir, "Write DIR/ORDERING.perm: the 0-based scalar pivot order, one a line");
  add_alias(cmd, "--perm-out", &o->perm_dir);
  cmd->add_flag("--cholmod", o->cholmod, "Add CHOLMOD's nnz(L) and flops for each permutation");
  return [o] {
    const std::vector<std::string> names = parse_ordering_list(o->orderings);
    const Problem p = load_problem(o->problem.spec, o->problem.blocks, o->problem.max_block);
    // a large matrix takes seconds per ordering (METIS, the explicit elimination graph)
    auto before = [&](const std::string& name) {
      if (p.a.n >= kProgressDimension) progress("order", p.name + ": " + name);
    };
    const std::vector<Row> rows = compare(p, names, o->cholmod, before);
    if (!o->perm_dir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(o->perm_dir, ec);
      for (const Row& r : rows) {
        const std::string path = o->perm_dir + "/" + r.summary.name + ".perm";
        std::ofstream f(path);
        for (int i : r.ordering.perm) f << i << '\n';
        if (!f) throw InputError(path + ": cannot write file");
      }
    }
    if (o->json) {
      print_json(json_header("order", to_json(p, rows)));
    } else {
      print_table(stdout, p, rows);
    }
    return 0;
  };
}

}  // namespace ldlpgs::cli
