// ldlpgs peers SCENE: one scene (a JSON file or a built-in name) stepped by every peer engine
// and every one of our solvers in the same run (bench/peers/peer.h): median wall time per whole
// step, the largest joint separation after the run, and the largest distance of any body from
// the reference trajectory (our direct solver at a 16x smaller timestep) and from our direct
// solver at the scene's own timestep (the same discretization: what is left is the solver's).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "bench/peers/peer.h"
#include "sparse/error.h"

namespace ldlpgs::cli {

namespace {

struct PeersArgs {
  std::string scene;
  double seconds = 1;
  std::vector<std::string> engines;  // empty: all
  bool json = false;
};

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

int run_peers(const PeersArgs& a) {
  const Mechanism m = load_mechanism(a.scene);
  if (!(a.seconds > 0) || !std::isfinite(a.seconds)) throw InputError("--seconds must be positive");
  std::vector<const peers::PeerEngine*> engines;
  for (const std::string& name : a.engines) {
    const peers::PeerEngine* e = peers::find_peer(name);
    if (!e) {
      std::string known;
      for (const peers::PeerEngine& p : peers::peer_engines()) known += " " + p.name;
      throw InputError("--engines " + name + ": unknown engine (known:" + known + ")");
    }
    engines.push_back(e);
  }
  if (engines.empty())
    for (const peers::PeerEngine& e : peers::peer_engines()) engines.push_back(&e);

  const peers::PeerResult reference = peers::reference_run(m, a.seconds);
  if (!reference.ran()) std::fprintf(stderr, "ldlpgs peers: no reference trajectory: %s\n", reference.skipped.c_str());
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
        j["separation"] = number_or_null(r.separation);
        j["trajectory_error"] = number_or_null(r.trajectory_error);
        j["direct_same_step_error"] = number_or_null(same_step(r));
        j["finite"] = r.finite;
      }
      rows.push_back(j);
    }
    const nlohmann::json out = {{"scene", m.name},
                                {"bodies", m.bodies.size()},
                                {"constraints", m.constraints.size()},
                                {"rows", m.num_rows()},
                                {"timestep", m.timestep},
                                {"steps", steps},
                                {"seconds", a.seconds},
                                {"reference", reference.ran() ? nlohmann::json(reference.engine) : nlohmann::json(nullptr)},
                                {"engines", rows}};
    std::cout << out.dump(2) << '\n';
  } else {
    std::printf("%s: %zu bodies, %zu constraints, %d rows; %d steps of %g s; reference: %s\n", m.name.c_str(),
                m.bodies.size(), m.constraints.size(), m.num_rows(), steps, m.timestep,
                reference.ran() ? reference.engine.c_str() : "none");
    std::printf("%-18s %12s %14s %14s %14s\n", "engine", "step (us)", "separation (m)", "trajectory (m)",
                "vs direct (m)");
    for (const peers::PeerResult& r : results) {
      if (!r.ran()) {
        std::printf("%-18s skipped: %s\n", r.engine.c_str(), r.skipped.c_str());
        continue;
      }
      std::printf("%-18s %12.1f %14.3e %14.3e %14.3e%s\n", r.engine.c_str(), r.step_us, r.separation,
                  r.trajectory_error, same_step(r), r.finite ? "" : "  (blew up)");
    }
  }
  return 0;
}

}  // namespace

Command add_peers_command(CLI::App& app) {
  auto a = std::make_shared<PeersArgs>();
  CLI::App* cmd = app.add_subcommand("peers", "Step a scene in ODE, Bullet, MuJoCo and with our solvers, side by side");
  cmd->add_option("scene", a->scene, "Scene file (JSON) or built-in scene name (e.g. heavy-chain-100-1000)")->required();
  cmd->add_option("--seconds", a->seconds, "Simulated time of each run")->capture_default_str();
  cmd->add_option("--engines", a->engines, "Engines to run (default: all)")->delimiter(',');
  cmd->add_flag("--json", a->json, "Print one JSON object");
  return [a] { return run_peers(*a); };
}

}  // namespace ldlpgs::cli
