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
#include "ldlpgs/physics/mjcf.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs::cli {

namespace {

struct PeersArgs {
  std::string scene;
  double seconds = 1;
  std::vector<std::string> engines;  // empty: all
  bool json = false;
};

int run_peers(const PeersArgs& a) {
  const Mechanism m = load_mechanism(a.scene);
  if (!(a.seconds > 0) || !std::isfinite(a.seconds)) throw InputError("--seconds must be positive");
  // At least one step, and at most 10^6 (the references take 16 times as many, at timestep / 16):
  // 1e308 s was 0 steps once the count overflowed an int, and printed NaN.
  const double wanted = a.seconds / m.timestep;
  if (!(wanted >= 0.5) || wanted > 1e6) {
    char why[160];
    std::snprintf(why, sizeof why, "--seconds %g: %.3g steps of the scene's %g s; at least 1 and at most 10^6", a.seconds,
                  wanted, m.timestep);
    throw InputError(why);
  }
  const std::string mjcf_path = is_mjcf_path(a.scene) ? a.scene : "";
  std::vector<peers::PeerEngine> table = peers::peer_engines();
  if (!mjcf_path.empty()) table.push_back(peers::mjcf_peer(mjcf_path));
  std::vector<const peers::PeerEngine*> engines;
  for (const std::string& name : a.engines) {
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

  const peers::PeerResult reference = peers::reference_run(m, a.seconds);
  if (!reference.ran()) std::fprintf(stderr, "ldlpgs peers: no reference trajectory: %s\n", reference.skipped.c_str());
  const peers::PeerResult rk4 = peers::rk4_reference_run(m, a.seconds, mjcf_path);
  if (!rk4.ran()) std::fprintf(stderr, "ldlpgs peers: no RK4 reference: %s\n", rk4.skipped.c_str());
  auto against_rk4 = [&](const peers::PeerResult& r) {
    peers::PeerResult copy = r;
    peers::compare_to(rk4, &copy);
    return copy.trajectory_error;
  };
  // how far the two references are apart (each at timestep / 16): a bound on what they resolve
  double references_apart = std::numeric_limits<double>::quiet_NaN();
  if (reference.ran() && rk4.ran()) {
    peers::PeerResult copy = reference;
    peers::compare_to(rk4, &copy);
    references_apart = copy.trajectory_error;
  }
  // our direct solver at the scene's timestep, whether or not it is among the engines run
  const peers::PeerResult direct = peers::find_peer("ldlpgs-direct")->run(m, a.seconds);
  auto same_step = [&](const peers::PeerResult& r) {
    peers::PeerResult copy = r;
    peers::compare_to(direct, &copy);
    return copy.trajectory_error;
  };
  std::vector<peers::PeerResult> results;
  for (const peers::PeerEngine* e : engines) {
    if (!e->available) {
      std::fprintf(stderr, "ldlpgs peers: %s skipped: %s is not installed\n", e->name.c_str(), e->library.c_str());
      continue;
    }
    peers::PeerResult r = e->run(m, a.seconds);
    if (!r.ran()) std::fprintf(stderr, "ldlpgs peers: %s skipped: %s\n", e->name.c_str(), r.skipped.c_str());
    peers::compare_to(reference, &r);
    results.push_back(std::move(r));
  }

  const int steps = peers::peer_steps(m, a.seconds);
  if (a.json) {
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
        j["rk4_trajectory_error_m"] = number_or_null(against_rk4(r));
        j["direct_same_step_error_m"] = number_or_null(same_step(r));
        j["finite"] = r.finite;
      }
      rows.push_back(j);
    }
    nlohmann::json out = {{"scene", m.name},
                                {"bodies", m.bodies.size()},
                                {"constraints", m.constraints.size()},
                                {"rows", m.num_rows()},
                                {"timestep_s", m.timestep},
                                {"steps", steps},
                                {"simulated_s", a.seconds},
                                {"reference", reference.ran() ? nlohmann::json(reference.engine) : nlohmann::json(nullptr)},
                                {"rk4_reference", rk4.ran() ? nlohmann::json(rk4.engine) : nlohmann::json(nullptr)},
                                {"references_apart_m", number_or_null(references_apart)},
                                {"engines", rows}};
    print_json(json_header("peers", std::move(out)));
  } else {
    std::printf("%s: %zu bodies, %zu constraints, %d rows; %d steps of %g s; reference: %s; RK4 reference: %s",
                m.name.c_str(), m.bodies.size(), m.constraints.size(), m.num_rows(), steps, m.timestep,
                reference.ran() ? reference.engine.c_str() : "none", rk4.ran() ? rk4.engine.c_str() : "none");
    if (std::isfinite(references_apart)) std::printf(" (%.3e m apart)", references_apart);
    std::printf("\n%-18s %12s %14s %16s %14s %14s %14s\n", "engine", "step (us)", "separation (m)", "penetration (m)",
                "trajectory (m)", "vs RK4 (m)", "vs direct (m)");
    for (const peers::PeerResult& r : results) {
      if (!r.ran()) {
        std::printf("%-18s skipped: %s\n", r.engine.c_str(), r.skipped.c_str());
        continue;
      }
      std::printf("%-18s %12.1f %14.3e %16.3e %14.3e %14.3e %14.3e%s\n", r.engine.c_str(), r.step_us, r.separation,
                  r.penetration_max, r.trajectory_error, against_rk4(r), same_step(r), r.finite ? "" : "  (blew up)");
    }
  }
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
  return [a] { return run_peers(*a); };
}

}  // namespace ldlpgs::cli
