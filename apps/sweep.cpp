// Speed against error and the mass ratio at which each solver breaks (apps/sweep.h).
#include "apps/sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "apps/commands.h"
#include "apps/options.h"
#include "ldlpgs/physics/step.h"

namespace ldlpgs::cli {

std::vector<std::string> sweep_cases(bool full) {
  if (!full)
    return {"heavy-chain-10-10", "heavy-chain-10-1000", "heavy-chain-10-1e6", "chain-10", "chain-100",
            "four-bar", "driven-crank", "tracked-vehicle", "multi-wheeled-vehicle", "ragdoll",
            "box-stack-1000", "ball-chain-20-1000"};
  return {"heavy-chain-10-10", "heavy-chain-10-100", "heavy-chain-10-1000", "heavy-chain-10-1e4", "heavy-chain-10-1e5",
          "heavy-chain-10-1e6", "chain-10", "chain-100", "chain-1000", "four-bar", "driven-crank", "tracked-vehicle",
          "multi-wheeled-vehicle", "ragdoll", "box-stack-1000", "ball-chain-20-1000", "pyramid-10",
          "tracked-vehicle-on-ground", "multi-wheeled-vehicle-on-ground"};
}

std::vector<int> sweep_iterations(bool full) {
  if (!full) return {1, 4, 16, 64};
  return {1, 2, 4, 8, 16, 32, 64, 128};
}

std::vector<SweepPoint> speed_vs_error(const std::vector<std::string>& cases, const std::vector<int>& iterations,
                                       double seconds, bool progress) {
  std::vector<SweepPoint> points;
  for (const std::string& scene : cases) {
    if (progress) std::fprintf(stderr, "sweep: %s\n", scene.c_str());
    const Mechanism m = load_mechanism(scene);
    for (const char* solver : {"pgs", "block-gs", "ldl-pgs"})
      for (int it : iterations) points.push_back(run_case(m, scene, solver, it, seconds));
    if (equality_only(m)) points.push_back(run_case(m, scene, "direct", 1, seconds));
  }
  return points;
}

std::vector<Breakdown> stability(const std::vector<std::string>& cases, int iterations, double seconds, bool progress) {
  std::vector<Breakdown> rows;
  for (const std::string& scene : cases) {
    if (progress) std::fprintf(stderr, "stability: %s\n", scene.c_str());
    Mechanism base = load_mechanism(scene);
    base.timestep = std::min(base.timestep, 0.0025);  // below the integrator's own centimetre (papers/physics.md)
    std::vector<std::string> solvers = {"pgs", "block-gs", "ldl-pgs"};
    if (equality_only(base)) solvers.push_back("direct");
    for (const std::string& solver : solvers) {
      Breakdown b{scene, solver, solver == "direct" ? 1 : iterations, 0, 0, ""};
      // the load made 10^k times heavier, k = 0..9: the mass ratios the scene reaches from its own
      for (int k = 0; k <= 9; ++k) {
        const Mechanism m = with_heavier_load(base, std::pow(10.0, k));
        const SweepPoint p = run_case(m, scene, solver, iterations, seconds);
        if (!p.failed() && p.error_max <= 0.01) {
          b.survives = mass_ratio(m);
          continue;
        }
        b.breaks = mass_ratio(m);
        b.how = p.failed() ? p.failure : "error > 1 cm";
        break;
      }
      rows.push_back(b);
    }
  }
  return rows;
}

void print_sweep_markdown(std::FILE* out, const std::vector<SweepPoint>& points) {
  std::fprintf(out, "| case | solver | iterations | solve us (median) | position error after (m) | largest during (m) "
                    "| angular error after (rad) | largest during (rad) | deepest contact (m) |\n");
  std::fprintf(out, "|---|---|---|---|---|---|---|---|---|\n");
  for (const SweepPoint& p : points) {
    if (p.failure == "non-finite" || p.failure == "energy")
      std::fprintf(out, "| %s | %s | %d | %.1f | failed: %s | | | | |\n", p.scene.c_str(), p.solver.c_str(),
                   p.iterations, p.solve_us, p.failure.c_str());
    else
      std::fprintf(out, "| %s | %s | %d | %.1f | %.2e%s | %.2e | %.2e | %.2e | %.2e |\n", p.scene.c_str(),
                   p.solver.c_str(), p.iterations, p.solve_us, p.error, p.failed() ? " (singular steps)" : "",
                   p.error_max, p.angular_error, p.angular_error_max, p.penetration_max);
  }
}

void print_sweep_summary(std::FILE* out, const std::vector<SweepPoint>& points) {
  const char* solvers[] = {"pgs", "block-gs", "ldl-pgs", "direct"};
  std::fprintf(out, "| case |");
  for (const char* s : solvers) std::fprintf(out, " %s: best error (m) at us | %s: fastest to 1 mm |", s, s);
  std::fprintf(out, "\n|---|");
  for (size_t i = 0; i < std::size(solvers); ++i) std::fprintf(out, "---|---|");
  std::fprintf(out, "\n");
  std::vector<std::string> cases;
  for (const SweepPoint& p : points)
    if (std::find(cases.begin(), cases.end(), p.scene) == cases.end()) cases.push_back(p.scene);
  for (const std::string& c : cases) {
    std::fprintf(out, "| %s |", c.c_str());
    for (const char* s : solvers) {
      const SweepPoint *best = nullptr, *fastest = nullptr;
      bool ran = false;
      double lowest = std::numeric_limits<double>::infinity();
      for (const SweepPoint& p : points)
        if (p.scene == c && p.solver == s && !p.failed()) lowest = std::min(lowest, p.error_max);
      for (const SweepPoint& p : points) {
        if (p.scene != c || p.solver != s) continue;
        ran = true;
        if (p.failed()) continue;
        // the cheapest run within 1% of the lowest error: more sweeps that change nothing are not "best"
        if (p.error_max <= 1.01 * lowest && (!best || p.solve_us < best->solve_us)) best = &p;
        if (p.error_max <= 1e-3 && (!fastest || p.solve_us < fastest->solve_us)) fastest = &p;
      }
      if (!ran) {
        std::fprintf(out, " | |");
        continue;
      }
      if (best) std::fprintf(out, " %.1e at %.1f |", best->error_max, best->solve_us);
      else std::fprintf(out, " failed |");
      if (fastest) std::fprintf(out, " %.1f us (%d it.) |", fastest->solve_us, fastest->iterations);
      else std::fprintf(out, " - |");
    }
    std::fprintf(out, "\n");
  }
}

void print_stability_markdown(std::FILE* out, const std::vector<Breakdown>& rows) {
  std::fprintf(out, "| case | solver | iterations | holds up to mass ratio | breaks at mass ratio | how |\n"
                    "|---|---|---|---|---|---|\n");
  auto ratio = [](double r) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", r);
    return std::string(text);
  };
  for (const Breakdown& b : rows) {
    std::fprintf(out, "| %s | %s | %d | %s | %s | %s |\n", b.scene.c_str(), b.solver.c_str(), b.iterations,
                 b.survives > 0 ? ratio(b.survives).c_str() : "none",
                 b.breaks > 0 ? ratio(b.breaks).c_str() : "not up to 1e9 x the scene's",
                 b.how.empty() ? "-" : b.how.c_str());
  }
}

nlohmann::json to_json(const std::vector<SweepPoint>& points) {
  nlohmann::json j = nlohmann::json::array();
  for (const SweepPoint& p : points) j.push_back(to_json(p));
  return j;
}

nlohmann::json to_json(const std::vector<Breakdown>& rows) {
  nlohmann::json j = nlohmann::json::array();
  for (const Breakdown& b : rows)
    j.push_back({{"scene", b.scene},
                 {"solver", b.solver},
                 {"iterations", b.iterations},
                 {"holds_mass_ratio", b.survives > 0 ? nlohmann::json(b.survives) : nlohmann::json(nullptr)},
                 {"breaks_mass_ratio", b.breaks > 0 ? nlohmann::json(b.breaks) : nlohmann::json(nullptr)},
                 {"failure", b.how}});
  return j;
}

nlohmann::json sweep_json(const std::vector<SweepPoint>& points, double seconds) {
  return json_header("sweep", {{"simulated_s", seconds}, {"points", to_json(points)}});
}

}  // namespace ldlpgs::cli
