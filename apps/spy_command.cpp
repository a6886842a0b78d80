// ldlpgs spy SCENE --json-file FILE.json (--json: to standard output): the block structure of H_0 (the equality constraints' matrix
// at the initial pose) and of its block L, fill blocks marked, in pivot order, after body
// shattering (physics/shatter.h) unless --no-shatter: the data of the talk's pictures of H and L
// (papers/scripts/plot_spy.py draws them, papers/scripts/talk_figures.py tabulates them). --scene-file writes the
// mechanism it spied, shattered or not, for `ldlpgs export` and `ldlpgs bench`.
//
// The file, one JSON object: scene, shattered (a body was split), shatter_threshold (null with
// --no-shatter), shattered_bodies, welds, bodies, constraints and blocks (both H_0's blocks, one
// per equality constraint), n (H_0's dimension), density (stored entries of the full symmetric H_0 / n^2), ordering, flops and nnz_L (Symbolic, as
// ordering/metrics.h counts them), fill_blocks, and per pivot position k: pivots[k] (the block,
// i.e. the equality constraint, eliminated k-th; rows for a scalar ordering), block_sizes[k];
// H_blocks: [i, k] for every block of H_0's lower triangle, diagonal included, in pivot
// positions (i >= k); L_blocks: [i, k, fill] for every block of L, diagonal included, fill true
// for a block elimination created. Both lists go column by column, rows ascending.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <span>
#include <vector>

#include "apps/commands.h"
#include "apps/options.h"
#include "apps/shatter_args.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

namespace {

struct SpyArgs {
  std::string scene, out, ordering = "best", scene_out;
  bool json = false;
  ShatterArgs shatter;
};

int run_spy(const SpyArgs& a) {
  const OrderingInfo& info = find_ordering(a.ordering);  // throws on an unknown name
  const Mechanism original = load_mechanism(a.scene);
  const ShatterResult shattered = shatter_as_told(original, a.shatter, a.ordering);
  const Mechanism& m = shattered.mechanism;
  if (!a.scene_out.empty()) save_scene(m, a.scene_out);

  std::vector<int> sizes;
  const SymmetricCsc h = equality_matrix(build_system(m, StepOptions{}), &sizes);
  if (h.n == 0) throw InputError(a.scene + ": no equality constraints, H_0 is empty");
  const BlockPattern blocks = BlockPattern::from_scalar(h, sizes);
  const Ordering ordering = compute_ordering(info, blocks, h);
  const Symbolic symbolic = Symbolic::analyze(h, blocks, ordering);
  // The blocks the Symbolic pivots on: H_0's, or single rows for a scalar ordering.
  const BlockPattern pivoted = ordering.level == Level::scalar ? BlockPattern::unit(h) : blocks;

  const int np = symbolic.num_pivots();
  std::vector<int> position(np);  // pivot position of each block (size np)
  nlohmann::json pivots = nlohmann::json::array(), block_sizes = nlohmann::json::array(),
                 h_blocks = nlohmann::json::array(), l_blocks = nlohmann::json::array();
  for (int k = 0; k < np; ++k) {
    position[symbolic.block(k)] = k;
    pivots.push_back(symbolic.block(k));
    block_sizes.push_back(symbolic.size(k));
  }
  // Only when they are written: on the 1000-arm star these lists are 1M small JSON arrays, built
  // and freed for a summary line that does not show them (papers/factor.md, "Supernodes: before
  // and after").
  const bool write_lists = a.json || !a.out.empty();
  for (int k = 0; write_lists && k < np; ++k) {  // column by column, rows ascending
    std::vector<int> rows = {k};
    for (int b : pivoted.neighbors(symbolic.block(k)))
      if (position[b] > k) rows.push_back(position[b]);
    std::sort(rows.begin(), rows.end());
    for (int i : rows) h_blocks.push_back({i, k});
    l_blocks.push_back({k, k, false});
    const std::span<const int> edges = symbolic.edges(k);
    for (size_t e = 0; e < edges.size(); ++e)
      l_blocks.push_back({edges[e], k, symbolic.is_fill(symbolic.first_edge(k) + static_cast<int64_t>(e))});
  }
  const double density = static_cast<double>(full_nnz(h)) / (static_cast<double>(h.n) * h.n);

  nlohmann::json j = {{"scene", original.name},
                      {"shattered", shattered.shattered_bodies > 0},
                      {"shatter_threshold", a.shatter.none ? nlohmann::json(nullptr) : nlohmann::json(a.shatter.threshold)},
                      {"shattered_bodies", shattered.shattered_bodies},
                      {"welds", shattered.welds},
                      {"bodies", m.bodies.size()},
                      {"constraints", blocks.num_blocks()},
                      {"blocks", blocks.num_blocks()},
                      {"n", h.n},
                      {"density", density},
                      {"ordering", ordering.name},
                      {"chosen", ordering.chosen},
                      {"flops", symbolic.flops()},
                      {"nnz_L", symbolic.nnz_l()},
                      {"fill_blocks", symbolic.num_fill_edges()},
                      {"pivots", pivots},
                      {"block_sizes", block_sizes},
                      {"H_blocks", h_blocks},
                      {"L_blocks", l_blocks}};
  j = json_header("spy", std::move(j));
  if (!a.out.empty()) {
    std::ofstream out(a.out);
    out << j.dump() << '\n';
    finish_writing(out, a.out, "the spy file");
  }
  if (a.json) {
    print_json(j);
    return 0;
  }
  std::printf("%s%s: %d constraints, dim(H) %d, density %.1f%%, %s: %lld fill blocks, nnz(L) %lld, %.0f flops -> %s\n",
              original.name.c_str(), j["shattered"].get<bool>() ? " (shattered)" : "", blocks.num_blocks(), h.n,
              100 * density, shown_name(ordering).c_str(), static_cast<long long>(symbolic.num_fill_edges()),
              static_cast<long long>(symbolic.nnz_l()), symbolic.flops(),
              a.out.empty() ? "--json-file FILE writes the data" : a.out.c_str());
  return 0;
}

}  // namespace

Command add_spy_command(CLI::App& app) {
  auto a = std::make_shared<SpyArgs>();
  CLI::App* cmd = app.add_subcommand("spy", "Write the block structure of a scene's H and of its L (fill marked) as JSON");
  cmd->add_option("scene", a->scene, "Scene file (JSON) or built-in scene name")->required();
  cmd->add_option("--json-file", a->out, "JSON file to write (papers/scripts/plot_spy.py draws it)");
  add_alias(cmd, "--out", &a->out);
  add_json_flag(cmd, &a->json);
  add_ordering_option(cmd, &a->ordering, "Ordering of H's blocks");
  add_shatter_options(cmd, &a->shatter);
  cmd->add_option("--scene-file", a->scene_out, "Also write the mechanism spied (shattered or not) as a scene file");
  add_alias(cmd, "--scene-out", &a->scene_out);
  return [a] { return run_spy(*a); };
}

}  // namespace ldlpgs::cli
