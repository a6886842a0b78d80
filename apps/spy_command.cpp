// ldlpgs spy SCENE --out FILE.json: the block structure of H_0 (the equality constraints' matrix
// at the initial pose) and of its block L, fill blocks marked, in pivot order, after body
// shattering (physics/shatter.h) unless --no-shatter: the data of the talk's pictures of H and L
// (papers/plot_spy.py draws them, papers/talk_figures.py tabulates them). --scene-out writes the
// mechanism it spied, shattered or not, for `ldlpgs export` and `ldlpgs bench`.
//
// The file, one JSON object: scene, shattered (a body was split), shatter_threshold (null with
// --no-shatter), shattered_bodies, welds, bodies, constraints (H_0's blocks), dim, density
// (stored entries of the full symmetric H_0 / dim^2), ordering, flops and nnz_L (Symbolic, as
// ordering/metrics.h counts them), fill_blocks, and per pivot position k: pivots[k] (the block,
// i.e. the equality constraint, eliminated k-th; rows for a scalar ordering), block_sizes[k];
// H_blocks: [i, k] for every block of H_0's lower triangle, diagonal included, in pivot
// positions (i >= k); L_blocks: [i, k, fill] for every block of L, diagonal included, fill true
// for a block elimination created. Both lists go column by column, rows ascending.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>
#include <span>
#include <vector>

#include "apps/commands.h"
#include "factor/symbolic.h"
#include "physics/scene.h"
#include "physics/shatter.h"
#include "physics/step.h"
#include "sparse/error.h"

namespace ldlpgs::cli {

namespace {

struct SpyArgs {
  std::string scene, out, ordering = "meca", scene_out;
  int shatter_threshold = ShatterOptions{}.threshold;
  int shards = 0;  // 0: shatter() chooses by flops
  bool no_shatter = false;
};

struct Shattered {
  Mechanism mechanism;
  int bodies = 0, welds = 0;  // bodies split, welds added
};

// Every dynamic body of more constraint rows than the threshold split into `shards` shards,
// as shatter() splits the bodies it chooses to (physics/shatter.h).
Shattered shatter_into(const Mechanism& original, int threshold, int shards) {
  std::vector<int> degree(original.bodies.size(), 0);  // constraint rows per body (size bodies)
  for (const Constraint& c : original.constraints) {
    degree[c.body_a] += num_rows(c.type);
    degree[c.body_b] += num_rows(c.type);
  }
  Shattered s{original};
  // shatter_body keeps a body's index for its first shard and appends the others
  for (size_t b = 0; b < original.bodies.size(); ++b) {
    if (original.bodies[b].is_static || degree[b] <= threshold) continue;
    s.mechanism = shatter_body(s.mechanism, static_cast<int>(b), shards, nullptr);
    ++s.bodies;
    s.welds += shards - 1;
  }
  return s;
}

// Stored entries of the full symmetric matrix whose lower triangle `a` holds.
int64_t full_nnz(const SymmetricCsc& a) {
  int64_t diagonal = 0;
  for (int j = 0; j < a.n; ++j)
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) diagonal += a.row_idx[p] == j;
  return 2 * a.nnz() - diagonal;
}

int run_spy(const SpyArgs& a) {
  const OrderingInfo& info = find_ordering(a.ordering);  // throws on an unknown name
  if (!a.no_shatter && a.shatter_threshold < 1) throw InputError("--shatter must be at least 1 (rows)");
  if (a.shards != 0 && (a.shards < 2 || a.shards > 64)) throw InputError("--shards must be in 2..64");
  const Mechanism original = load_mechanism(a.scene);
  std::optional<Shattered> shattered;
  if (a.shards) {
    shattered = shatter_into(original, a.shatter_threshold, a.shards);
  } else if (!a.no_shatter) {
    ShatterResult r = shatter(original, {.threshold = a.shatter_threshold, .ordering = a.ordering});
    shattered = Shattered{std::move(r.mechanism), r.shattered_bodies, r.welds};
  }
  const Mechanism& m = shattered ? shattered->mechanism : original;
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
  for (int k = 0; k < np; ++k) {  // column by column, rows ascending
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
                      {"shattered", shattered && shattered->bodies > 0},
                      {"shatter_threshold", shattered ? nlohmann::json(a.shatter_threshold) : nlohmann::json(nullptr)},
                      {"shattered_bodies", shattered ? shattered->bodies : 0},
                      {"welds", shattered ? shattered->welds : 0},
                      {"bodies", m.bodies.size()},
                      {"constraints", blocks.num_blocks()},
                      {"dim", h.n},
                      {"density", density},
                      {"ordering", ordering.name},
                      {"flops", symbolic.flops()},
                      {"nnz_L", symbolic.nnz_l()},
                      {"fill_blocks", symbolic.num_fill_edges()},
                      {"pivots", pivots},
                      {"block_sizes", block_sizes},
                      {"H_blocks", h_blocks},
                      {"L_blocks", l_blocks}};
  std::ofstream out(a.out);
  out << j.dump() << '\n';
  if (!out) throw InputError(a.out + ": cannot write the spy file");
  std::printf("%s%s: %d constraints, dim(H) %d, density %.1f%%, %s: %lld fill blocks, nnz(L) %lld, %.0f flops -> %s\n",
              original.name.c_str(), j["shattered"].get<bool>() ? " (shattered)" : "", blocks.num_blocks(), h.n,
              100 * density, ordering.name.c_str(), static_cast<long long>(symbolic.num_fill_edges()),
              static_cast<long long>(symbolic.nnz_l()), symbolic.flops(), a.out.c_str());
  return 0;
}

}  // namespace

Command add_spy_command(CLI::App& app) {
  auto a = std::make_shared<SpyArgs>();
  CLI::App* cmd = app.add_subcommand("spy", "Write the block structure of a scene's H and of its L (fill marked) as JSON");
  cmd->add_option("scene", a->scene, "Scene file (JSON) or built-in scene name")->required();
  cmd->add_option("--out", a->out, "JSON file to write (papers/plot_spy.py draws it)")->required();
  cmd->add_option("--ordering", a->ordering, "Ordering of H's blocks")->capture_default_str();
  CLI::Option* threshold = cmd->add_option("--shatter", a->shatter_threshold,
                                           "Shatter bodies of more constraint rows than this (physics/shatter.h); "
                                           "the number of shards is chosen by flops")->capture_default_str();
  CLI::Option* shards = cmd->add_option("--shards", a->shards, "Split each of those bodies into this many shards "
                                        "instead (2..64)");
  cmd->add_flag("--no-shatter", a->no_shatter, "Keep the mechanism whole")->excludes(threshold)->excludes(shards);
  cmd->add_option("--scene-out", a->scene_out, "Also write the mechanism spied (shattered or not) as a scene file");
  return [a] { return run_spy(*a); };
}

}  // namespace ldlpgs::cli
