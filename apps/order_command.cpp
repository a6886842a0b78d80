// ldlpgs order MATRIX.mtx: every requested ordering on one matrix, with nnz(L), flops, block
// fill and block flops, optionally beside CHOLMOD's own counts for the same permutations.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "apps/commands.h"
#include "apps/compare.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

Command add_order_command(CLI::App& app) {
  struct Options {
    std::string matrix, blocks = "auto", orderings = "all", perm_out;
    int max_block = 6;
    bool json = false, cholmod = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("order", "Compare elimination orderings on a Matrix Market matrix");
  cmd->add_option("matrix", o->matrix, "Matrix Market file (symmetric)")->required();
  cmd->add_option("--blocks", o->blocks, "Block partition: auto (identical consecutive rows), N (uniform), or a file "
                                         "with one block size per line")->capture_default_str();
  cmd->add_option("--max-block", o->max_block, "Largest block --blocks auto forms")->capture_default_str();
  cmd->add_option("--orderings", o->orderings, "Comma-separated ordering names, or all")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of a table");
  cmd->add_option("--perm-out", o->perm_out, "Write DIR/ORDERING.perm: the 0-based scalar pivot order, one a line");
  cmd->add_flag("--cholmod", o->cholmod, "Add CHOLMOD's nnz(L) and flops for each permutation");
  return [o] {
    const std::vector<std::string> names = parse_ordering_list(o->orderings);
    const Problem p = load_matrix(o->matrix, o->blocks, o->max_block);
    const std::vector<Row> rows = compare(p, names, o->cholmod);
    if (!o->perm_out.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(o->perm_out, ec);
      for (const Row& r : rows) {
        const std::string path = o->perm_out + "/" + r.summary.name + ".perm";
        std::ofstream f(path);
        for (int i : r.ordering.perm) f << i << '\n';
        if (!f) throw InputError(path + ": cannot write file");
      }
    }
    if (o->json) {
      std::cout << to_json(p, rows).dump(2) << '\n';
    } else {
      print_table(stdout, p, rows);
    }
    return 0;
  };
}

}  // namespace ldlpgs::cli
