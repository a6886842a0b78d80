// ldlpgs order PROBLEM: every requested ordering on one matrix (a file or a generated mechanism), with nnz(L), flops, block
// fill and block flops, optionally beside CHOLMOD's own counts for the same permutations. With --certify, the proof of
// ordering/certify.h; when it proves an optimum that no ordering compared reaches, its order is the last row, "optimal"
// (chosen "certify"; --perm-dir writes optimal.perm).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>

#include "apps/commands.h"
#include "apps/compare.h"
#include "apps/options.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

Command add_order_command(CLI::App& app) {
  struct Options {
    ProblemArgs problem;
    std::string orderings = "all", perm_dir;
    bool json = false, cholmod = false, certify = false;
    double certify_time_limit_s = 10;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("order", "Compare elimination orderings on a Matrix Market matrix or a generated mechanism");
  add_problem_options(cmd, &o->problem);
  add_ordering_option(cmd, &o->orderings, "Orderings to compare", true);
  add_json_flag(cmd, &o->json);
  cmd->add_option("--perm-dir", o->perm_dir, "Write DIR/ORDERING.perm: the 0-based scalar pivot order, one a line");
  add_alias(cmd, "--perm-out", &o->perm_dir);
  cmd->add_flag("--cholmod", o->cholmod, "Add CHOLMOD's nnz(L) and flops for each permutation");
  cmd->add_flag("--certify", o->certify,
                "Prove which block orderings have the fewest block flops of any order, or give a lower bound; "
                "an optimum below them all becomes a row of its own, optimal");
  cmd->add_option("--certify-time-limit-s", o->certify_time_limit_s, "Time limit of the exact search of --certify")
      ->capture_default_str()
      ->check(finite_in(0));
  return [o] {
    const std::vector<std::string> names = parse_ordering_list(o->orderings);
    if (!(o->certify_time_limit_s >= 0) || !std::isfinite(o->certify_time_limit_s))
      throw InputError("--certify-time-limit-s must be finite and >= 0");
    const Problem p = load_problem(o->problem.spec, o->problem.blocks, o->problem.max_block, o->problem.split_blocks);
    // a large matrix takes seconds per ordering (METIS, the explicit elimination graph)
    auto before = [&](const std::string& name) {
      if (p.a.n >= kProgressDimension) progress("order", p.name + ": " + name);
    };
    std::vector<Row> rows = compare(p, names, o->cholmod, before);
    std::optional<BlockFlopsCertificate> cert;
    if (o->certify) {
      if (p.a.n >= kProgressDimension) progress("order", p.name + ": certify");
      // The block ordering with the fewest block flops prunes the search (or none: no pruning).
      const Row* known = nullptr;
      for (const Row& r : rows)
        if (r.summary.block && (!known || r.summary.block->flops < known->summary.block->flops)) known = &r;
      cert = certify_block_flops(p.blocks, o->certify_time_limit_s,
                                 known ? std::span<const int>(known->ordering.pivots) : std::span<const int>());
      // An optimum below every ordering compared: its order becomes a row, "optimal".
      const double fewest = known ? known->summary.block->flops : std::numeric_limits<double>::infinity();
      if (std::optional<Ordering> optimal = certificate_ordering(p.blocks, *cert, fewest)) {
        Row r;
        r.ordering = std::move(*optimal);
        r.summary = summarize(r.ordering, p.blocks, p.scalar_graph);
        if (o->cholmod) {
          Cholmod cm;
          r.cholmod = cholmod_counts(p.a, r.ordering.perm, cm);
        }
        rows.push_back(std::move(r));
      }
    }
    if (!o->perm_dir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(o->perm_dir, ec);
      for (const Row& r : rows) {
        const std::string path = o->perm_dir + "/" + r.summary.name + ".perm";
        std::ofstream f(path);
        for (int i : r.ordering.perm) f << i << '\n';
        finish_writing(f, path, "the permutation");
      }
    }
    if (o->json) {
      nlohmann::json j = to_json(p, rows);
      if (cert) add_certificate(&j, rows, *cert);
      print_json(json_header("order", std::move(j)));
    } else {
      print_table(stdout, p, rows);
      if (cert) print_certificate(stdout, rows, *cert);
    }
    return 0;
  };
}

}  // namespace ldlpgs::cli
