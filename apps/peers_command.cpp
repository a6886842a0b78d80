// ldlpgs peers SCENE: one scene (a JSON file or a built-in name) stepped by every peer engine
// and every one of our solvers in the same run (peers/peer.h): median wall time per whole
// step, the largest joint separation after the run, the deepest penetration of two shapes over
// the run (the same measure for every engine: our collision detector on the engine's poses; the
// name step --json gives its own), and the largest distance of any body from
// the reference trajectory (our direct solver at a 16x smaller timestep), from the second
// reference for trees (MuJoCo's RK4 in reduced coordinates at that timestep) and from our direct
// solver at the scene's own timestep (the same discretization: what is left is the solver's);
// no trajectory error for scenes with shapes (no reference).
// An MJCF scene adds mujoco-mjcf, MuJoCo stepping the file itself.
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/options.h"
#include "peers/peer.h"
#include "ldlpgs/physics/io/mjcf.h"
#include "apps/controls.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

namespace {

struct PeersArgs {
  std::string scene;
  double seconds = 1;
  std::vector<std::string> engines;  // empty: all
  bool json = false, allow_dropped = false;
};

// The scene's step count for --seconds: at least one step, and at most 10^6 (the references take
// 16 times as many, at timestep / 16): 1e308 s was 0 steps once the count overflowed an int.
void check_seconds(const Mechanism& m, double seconds) {
  if (!(seconds > 0) || !std::isfinite(seconds)) throw InputError("--seconds must be positive");
  const double wanted = seconds / m.timestep;
  if (!(wanted >= 0.5) || wanted > 1e6) {
    char why[160];
    std::snprintf(why, sizeof why, "--seconds %g: %.3g steps of the scene's %g s; at least 1 and at most 10^6", seconds,
                  wanted, m.timestep);
    throw InputError(why);
  }
}

// The engines --engines names, in its order (all of `table` when it names none).
std::vector<const peers::PeerEngine*> chosen_engines(const std::vector<peers::PeerEngine>& table,
                                                     const std::vector<std::string>& names) {
  std::vector<const peers::PeerEngine*> engines;
  for (const std::string& name : names) {
    const peers::PeerEngine* e = nullptr;
    for (const peers::PeerEngine& p : table)
      if (p.name == name) e = &p;
    if (!e) {
      std::string known;
      for (const peers::PeerEngine& p : table) known += " " + p.name;
      throw InputError("--engines " + name + ": unknown engine (known:" + known + ")");
    }
    engines.push_back(e);
  }
  if (engines.empty())
    for (const peers::PeerEngine& e : table) engines.push_back(&e);
  return engines;
}

// What every engine's trajectory is measured against: the reference (our direct solver at
// timestep / 16), the second reference (MuJoCo's RK4 in reduced coordinates, trees only) and our
// direct solver at the scene's own timestep (the same discretization: what is left is the
// solver's).
struct References {
  peers::PeerResult reference, rk4, direct;
  double apart = std::numeric_limits<double>::quiet_NaN();  // the first two (what they resolve)

  References(const Mechanism& m, double seconds, const std::string& mjcf_path)
      : reference(peers::reference_run(m, seconds)),
        rk4(peers::rk4_reference_run(m, seconds, mjcf_path)),
        direct(peers::find_peer("ldlpgs-direct")->run(m, seconds)) {
    if (!reference.ran()) std::fprintf(stderr, "ldlpgs peers: no reference trajectory: %s\n", reference.skipped.c_str());
    if (!rk4.ran()) std::fprintf(stderr, "ldlpgs peers: no RK4 reference: %s\n", rk4.skipped.c_str());
    if (reference.ran() && rk4.ran()) apart = error_from(rk4, reference);
  }
  static double error_from(const peers::PeerResult& from, const peers::PeerResult& r) {
    peers::PeerResult copy = r;
    peers::compare_to(from, &copy);
    return copy.trajectory_error;
  }
  double against_rk4(const peers::PeerResult& r) const { return error_from(rk4, r); }
  double same_step(const peers::PeerResult& r) const { return error_from(direct, r); }
};

std::vector<peers::PeerResult> run_engines(const Mechanism& m, double seconds,
                                           const std::vector<const peers::PeerEngine*>& engines,
                                           const References& refs) {
  std::vector<peers::PeerResult> results;
  for (const peers::PeerEngine* e : engines) {
    if (!e->available) {
      std::fprintf(stderr, "ldlpgs peers: %s skipped: %s is not installed\n", e->name.c_str(), e->library.c_str());
      continue;
    }
    peers::PeerResult r = e->run(m, seconds);
    if (!r.ran()) std::fprintf(stderr, "ldlpgs peers: %s skipped: %s\n", e->name.c_str(), r.skipped.c_str());
    peers::compare_to(refs.reference, &r);
    results.push_back(std::move(r));
  }
  return results;
}

void print_json_results(const Mechanism& m, double seconds, const References& refs,
                        const std::vector<peers::PeerResult>& results) {
  nlohmann::json rows = nlohmann::json::array();
  for (const peers::PeerResult& r : results) {
    nlohmann::json j = {{"engine", r.engine}};
    if (!r.ran()) {
      j["skipped"] = r.skipped;
    } else {
      j["step_us"] = r.step_us;
      j["position_error_m"] = number_or_null(r.separation);
      j["penetration_max_m"] = number_or_null(r.penetration_max);
      j["trajectory_error_m"] = number_or_null(r.trajectory_error);
      j["rk4_trajectory_error_m"] = number_or_null(refs.against_rk4(r));
      j["direct_same_step_error_m"] = number_or_null(refs.same_step(r));
      j["finite"] = r.finite;
    }
    rows.push_back(j);
  }
  const auto engine_or_null = [](const peers::PeerResult& r) {
    return r.ran() ? nlohmann::json(r.engine) : nlohmann::json(nullptr);
  };
  nlohmann::json out = {{"scene", m.name},
                        {"bodies", m.bodies.size()},
                        {"constraints", m.constraints.size()},
                        {"rows", m.num_rows()},
                        {"timestep_s", m.timestep},
                        {"steps", peers::peer_steps(m, seconds)},
                        {"simulated_s", seconds},
                        {"reference", engine_or_null(refs.reference)},
                        {"rk4_reference", engine_or_null(refs.rk4)},
                        {"references_apart_m", number_or_null(refs.apart)},
                        {"engines", rows}};
  print_json(json_header("peers", std::move(out)));
}

void print_table(const Mechanism& m, double seconds, const References& refs,
                 const std::vector<peers::PeerResult>& results) {
  const auto name_or_none = [](const peers::PeerResult& r) { return r.ran() ? r.engine.c_str() : "none"; };
  std::printf("%s: %zu bodies, %zu constraints, %d rows; %d steps of %g s; reference: %s; RK4 reference: %s",
              m.name.c_str(), m.bodies.size(), m.constraints.size(), m.num_rows(), peers::peer_steps(m, seconds),
              m.timestep, name_or_none(refs.reference), name_or_none(refs.rk4));
  if (std::isfinite(refs.apart)) std::printf(" (%.3e m apart)", refs.apart);
  std::printf("\n%-18s %12s %14s %16s %14s %14s %14s\n", "engine", "step (us)", "separation (m)", "penetration (m)",
              "trajectory (m)", "vs RK4 (m)", "vs direct (m)");
  for (const peers::PeerResult& r : results) {
    if (!r.ran()) {
      std::printf("%-18s skipped: %s\n", r.engine.c_str(), r.skipped.c_str());
      continue;
    }
    std::printf("%-18s %12.1f %14.3e %16.3e %14.3e %14.3e %14.3e%s\n", r.engine.c_str(), r.step_us, r.separation,
                r.penetration_max, r.trajectory_error, refs.against_rk4(r), refs.same_step(r), r.finite ? "" : "  (blew up)");
  }
}

int run_peers(const PeersArgs& a) {
  const Mechanism m = load_mechanism(a.scene, a.allow_dropped);
  check_seconds(m, a.seconds);
  const std::string mjcf_path = is_mjcf_path(a.scene) ? a.scene : "";
  std::vector<peers::PeerEngine> table = peers::peer_engines();
  if (!mjcf_path.empty()) table.push_back(peers::mjcf_peer(mjcf_path));
  const std::vector<const peers::PeerEngine*> engines = chosen_engines(table, a.engines);
  const References refs(m, a.seconds, mjcf_path);
  const std::vector<peers::PeerResult> results = run_engines(m, a.seconds, engines, refs);
  if (a.json) print_json_results(m, a.seconds, refs, results);
  else print_table(m, a.seconds, refs, results);
  return 0;
}

}  // namespace

Command add_peers_command(CLI::App& app) {
  auto a = std::make_shared<PeersArgs>();
  CLI::App* cmd = app.add_subcommand("peers", "Step a scene in ODE, Bullet, MuJoCo and with our solvers, side by side");
  cmd->add_option("scene", a->scene, "Scene file (JSON or MJCF .xml) or built-in scene name (e.g. heavy-chain-100-1000)")->required();
  cmd->add_option("--seconds", a->seconds, "Simulated time of each run")->capture_default_str();
  add_list_option(cmd, "--engines", &a->engines, "Engines to run (default: all)");
  add_json_flag(cmd, &a->json);
  add_allow_dropped_flag(cmd, &a->allow_dropped);
  return [a] { return run_peers(*a); };
}

}  // namespace ldlpgs::cli
