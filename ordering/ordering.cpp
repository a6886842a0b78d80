#include "ldlpgs/ordering/ordering.h"

#include <array>
#include <cassert>
#include <chrono>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {
constexpr std::array<OrderingInfo, 14> kOrderings = {{
    {"best", order_best, Level::block, "the fewest block flops of meca, meca-w, amd, metis, mda-w, mda", choose_best},
    {"natural", order_natural, Level::block, "blocks in their given order"},
    {"mda", order_mda, Level::block, "minimum degree, in blocks (quotient graph, approximate degrees)"},
    {"mda-w", order_mda_w, Level::block, "minimum degree, in rows (quotient graph, approximate degrees)"},
    {"meca", order_meca, Level::block, "minimum edge creation: fewest new block edges (quotient graph, approximate)"},
    {"meca-w", order_meca_w, Level::block, "minimum edge creation: fewest new scalar entries (quotient graph, approximate)"},
    {"mda-exact", order_mda_exact, Level::block, "minimum degree, in blocks, on the explicit graph"},
    {"mda-w-exact", order_mda_w_exact, Level::block, "minimum degree, in rows, on the explicit graph"},
    {"meca-exact", order_meca_exact, Level::block, "minimum edge creation, block edges, on the explicit graph"},
    {"meca-w-exact", order_meca_w_exact, Level::block, "minimum edge creation, scalar entries, on the explicit graph"},
    {"amd", order_amd, Level::block, "SuiteSparse AMD on the block graph"},
    {"amd-scalar", order_amd, Level::scalar, "SuiteSparse AMD on the scalar graph (may split blocks)"},
    {"metis", order_metis, Level::block, "METIS_NodeND on the block graph, sizes as weights"},
    {"metis-scalar", order_metis, Level::scalar, "METIS_NodeND on the scalar graph (may split blocks)"},
}};

std::string known_names() {
  std::string s;
  for (const OrderingInfo& o : kOrderings) s += (s.empty() ? "" : ", ") + std::string(o.name);
  return s;
}
}  // namespace

std::span<const OrderingInfo> orderings() { return kOrderings; }

const OrderingInfo& find_ordering(std::string_view name) {
  for (const OrderingInfo& o : kOrderings) {
    if (o.name == name) return o;
  }
  throw InputError("unknown ordering '" + std::string(name) + "' (known: " + known_names() + ")");
}

std::vector<std::string> parse_ordering_list(std::string_view list) {
  std::vector<std::string> names;
  if (list == "all") {
    for (const OrderingInfo& o : kOrderings) names.emplace_back(o.name);
    return names;
  }
  if (list.empty()) throw InputError("empty ordering list (known: " + known_names() + ")");
  // every item, the empty ones too: "natural," had been read as "natural" and ",natural" refused
  for (size_t start = 0;;) {
    const size_t comma = list.find(',', start);
    const std::string_view name = list.substr(start, comma - start);
    if (name.empty()) throw InputError("an empty name in the ordering list '" + std::string(list) + "'");
    names.emplace_back(find_ordering(name).name);
    if (comma == std::string_view::npos) return names;
    start = comma + 1;
  }
}

std::string shown_name(std::string_view name, std::string_view chosen) {
  std::string s(name);
  if (!chosen.empty() && chosen != name) s += " (" + std::string(chosen) + ")";
  return s;
}
std::string shown_name(const Ordering& o) { return shown_name(o.name, o.chosen); }

std::vector<int> expand_pivots(const BlockPattern& pattern, std::span<const int> pivots) {
  std::vector<int> perm;
  perm.reserve(pattern.num_rows());
  for (int b : pivots) {
    const Block& blk = pattern.block(b);
    for (int k = 0; k < blk.size; ++k) perm.push_back(blk.position + k);
  }
  return perm;
}

Ordering compute_ordering(const OrderingInfo& info, const BlockPattern& blocks, const SymmetricCsc& a) {
  if (blocks.num_rows() != a.n)
    throw ArgumentError("compute_ordering: the block partition covers " + std::to_string(blocks.num_rows()) +
                        " rows of a matrix with " + std::to_string(a.n));
  Ordering o;
  o.name = info.name;
  o.level = info.level;
  const BlockPattern unit = info.level == Level::scalar ? BlockPattern::unit(a) : BlockPattern();
  const BlockPattern& pattern = info.level == Level::scalar ? unit : blocks;
  const auto start = std::chrono::steady_clock::now();
  if (info.choose) {
    Choice c = info.choose(pattern);
    o.pivots = std::move(c.pivots);
    o.chosen = std::move(c.chosen);
  } else {
    o.pivots = info.fn(pattern);
    o.chosen = info.name;
  }
  o.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  o.perm = expand_pivots(pattern, o.pivots);
  o.elimination = eliminate(pattern, o.pivots);
  return o;
}

}  // namespace ldlpgs
