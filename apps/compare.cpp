// The orderings comparison (compare.h).
#include "apps/compare.h"

#include "apps/options.h"

#include <algorithm>

namespace ldlpgs::cli {

std::vector<Row> compare(const Problem& p, const std::vector<std::string>& names, bool with_cholmod,
                         const std::function<void(const std::string&)>& before) {
  std::vector<Row> rows;
  std::optional<Cholmod> cm;
  if (with_cholmod) cm.emplace();
  for (const std::string& name : names) {
    if (before) before(name);
    Row r;
    r.ordering = compute_ordering(find_ordering(name), p.blocks, p.a);
    r.summary = summarize(r.ordering, p.blocks, p.scalar_graph);
    if (cm) r.cholmod = cholmod_counts(p.a, r.ordering.perm, *cm);
    rows.push_back(std::move(r));
  }
  return rows;
}

namespace {

std::string si(double x) {
  char buf[32];
  if (x >= 1e9) std::snprintf(buf, sizeof buf, "%.3gG", x / 1e9);
  else if (x >= 1e6) std::snprintf(buf, sizeof buf, "%.3gM", x / 1e6);
  else if (x >= 1e4) std::snprintf(buf, sizeof buf, "%.3gk", x / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f", x);
  return buf;
}

// The compared quantities; the block ones exist for block orderings only.
using Metric = std::optional<double> (*)(const OrderingSummary&);
std::optional<double> nnz(const OrderingSummary& s) { return s.nnz_L; }
std::optional<double> flops(const OrderingSummary& s) { return s.flops; }
std::optional<double> block_fill(const OrderingSummary& s) {
  return s.block ? std::optional<double>(s.block->fill_edges) : std::nullopt;
}
std::optional<double> block_flops(const OrderingSummary& s) {
  return s.block ? std::optional<double>(s.block->flops) : std::nullopt;
}

// The least value of a metric over the rows (fewest entries, flops, fill is best).
double best_of(const std::vector<Row>& rows, Metric get) {
  double b = 1e300;
  for (const Row& r : rows) {
    if (auto v = get(r.summary)) b = std::min(b, *v);
  }
  return b;
}

}  // namespace

void print_table(std::FILE* out, const Problem& p, const std::vector<Row>& rows) {
  const bool with_cholmod = !rows.empty() && rows.front().cholmod.has_value();
  // The best of each column gets a '*' (ties included).
  auto cell = [&](Metric get, const Row& r, bool exact) {
    const std::optional<double> v = get(r.summary);
    if (!v) return std::string("-");
    return (exact ? std::to_string(static_cast<long long>(*v)) : si(*v)) + (*v == best_of(rows, get) ? "*" : "");
  };
  std::fprintf(out, "%s: n = %d, %d blocks, %lld block edges, nnz(A) = %lld\n", p.name.c_str(), p.a.n,
               p.blocks.num_blocks(), static_cast<long long>(p.blocks.num_edges()),
               static_cast<long long>(full_nnz(p.a)));
  std::fprintf(out, "%-13s  %10s  %9s  %11s  %11s  %9s", "ordering", "nnz(L)", "flops", "block fill", "block flops",
               "ordering ms");
  if (with_cholmod) std::fprintf(out, "  %14s  %14s", "CHOLMOD nnz(L)", "CHOLMOD flops");
  std::fprintf(out, "\n");
  for (const Row& r : rows) {
    std::fprintf(out, "%-13s  %10s  %9s  %11s  %11s  %9.2f", shown_name(r.ordering).c_str(), cell(nnz, r, true).c_str(),
                 cell(flops, r, false).c_str(), cell(block_fill, r, true).c_str(), cell(block_flops, r, false).c_str(),
                 r.summary.time_ms);
    if (r.cholmod) std::fprintf(out, "  %14.0f  %14s", r.cholmod->lnz, si(r.cholmod->fl).c_str());
    std::fprintf(out, "\n");
  }
}

void print_markdown_by_metric(std::FILE* out, const std::vector<std::pair<Problem, std::vector<Row>>>& results) {
  if (results.empty()) return;
  const std::pair<const char*, Metric> metrics[] = {
      {"nnz(L), scalar, as CHOLMOD counts", nnz},
      {"flops, scalar, as CHOLMOD counts (Common->fl)", flops},
      {"block flops of the dense-block LDL^T (block orderings only)", block_flops},
  };
  for (const auto& [title, get] : metrics) {
    std::fprintf(out, "\n#### %s\n\n| problem | n | blocks |", title);
    for (const Row& r : results.front().second) std::fprintf(out, " %s |", r.summary.name.c_str());
    std::fprintf(out, "\n|---|---:|---:|");
    for (size_t i = 0; i < results.front().second.size(); ++i) std::fprintf(out, "---:|");
    std::fprintf(out, "\n");
    for (const auto& [p, rows] : results) {
      const double best = best_of(rows, get);
      std::fprintf(out, "| %s | %d | %d |", p.name.c_str(), p.a.n, p.blocks.num_blocks());
      for (const Row& r : rows) {
        const auto v = get(r.summary);
        if (!v) {
          std::fprintf(out, " - |");
        } else {
          const std::string s = si(*v);
          std::fprintf(out, *v == best ? " **%s** |" : " %s |", s.c_str());
        }
      }
      std::fprintf(out, "\n");
    }
  }
}

nlohmann::json to_json(const Problem& p, const std::vector<Row>& rows) {
  nlohmann::json j = {{"matrix", p.name}, {"n", p.a.n}, {"blocks", p.blocks.num_blocks()}};
  nlohmann::json results = nlohmann::json::array();
  for (const Row& r : rows) {
    nlohmann::json x = {{"ordering", r.summary.name},
                        {"chosen", r.ordering.chosen},
                        {"nnz_L", r.summary.nnz_L},
                        {"flops", r.summary.flops},
                        {"block_fill_edges", nullptr},
                        {"block_flops", nullptr},
                        {"ordering_ms", r.summary.time_ms}};
    if (r.summary.block) {
      x["block_fill_edges"] = r.summary.block->fill_edges;
      x["block_flops"] = r.summary.block->flops;
    }
    if (r.cholmod) {
      // CHOLMOD counts in a double; the count is exact, and an integer as ours is
      x["cholmod_nnz_L"] = static_cast<int64_t>(r.cholmod->lnz);
      x["cholmod_flops"] = r.cholmod->fl;
    }
    results.push_back(std::move(x));
  }
  j["results"] = std::move(results);
  return j;
}

namespace {
bool reaches(const OrderingSummary& s, const BlockFlopsCertificate& cert) {
  return s.block && certified_optimal(cert, s.block->flops);
}
}  // namespace

void add_certificate(nlohmann::json* j, const std::vector<Row>& rows, const BlockFlopsCertificate& cert) {
  (*j)["lower_bound_block_flops"] = cert.lower_bound;
  (*j)["optimum_proved"] = cert.optimal_proved;
  (*j)["peeled_blocks"] = cert.peeled;
  (*j)["chordal"] = cert.chordal;
  (*j)["atoms"] = cert.atoms;
  (*j)["certify_states"] = cert.states;
  (*j)["certify_ms"] = cert.time_ms;
  nlohmann::json& results = (*j)["results"];
  for (size_t i = 0; i < rows.size(); ++i) {
    results[i]["certified_optimal"] = reaches(rows[i].summary, cert);
    results[i]["lower_bound_block_flops"] = cert.lower_bound;
  }
}

void print_certificate(std::FILE* out, const std::vector<Row>& rows, const BlockFlopsCertificate& cert) {
  std::string optimal;
  for (const Row& r : rows)
    if (reaches(r.summary, cert)) optimal += (optimal.empty() ? "" : ", ") + shown_name(r.ordering);
  std::fprintf(out, "certificate: %s %.0f block flops (%d blocks peeled%s, %d atoms, %lld connected sets searched, %.1f ms); %s\n",
               cert.optimal_proved ? "optimum" : "lower bound", cert.lower_bound, cert.peeled,
               cert.chordal ? ", chordal" : "", cert.atoms, static_cast<long long>(cert.states), cert.time_ms,
               optimal.empty() ? "no ordering proved optimal" : ("optimal: " + optimal).c_str());
}

}  // namespace ldlpgs::cli
