// ldlpgs models PATH...: a user's own MJCF models checked in one run. Every *.xml file named, or
// found under a named folder, is loaded (physics/io/mjcf.h) and stepped --steps steps of its own
// timestep by our ldl-pgs beside MuJoCo stepping the same file (peers/peer.h, mjcf_peer: its
// own reduced coordinates), both at zero controls; one row per
// model: loaded or refused and why, what was dropped, step times (ours and MuJoCo's medians),
// our largest joint error, deepest contact, and the first step that came apart.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "apps/commands.h"
#include "apps/controls.h"
#include "apps/models.h"
#include "apps/options.h"
#include "peers/median.h"
#include "peers/peer.h"
#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs::cli {

namespace {

struct ModelsArgs {
  std::vector<std::string> paths;
  int steps = 1000;
  std::string schedule = "talk";
  bool json = false, allow_dropped = false;
};

// The MJCF files of the paths, in order (a folder's sorted, found recursively). A path that is
// neither a file nor a folder, or a folder with no *.xml below it, is bad input.
std::vector<std::string> model_files(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& path : paths) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      std::vector<std::string> found;
      for (const auto& entry : std::filesystem::recursive_directory_iterator(path, ec))
        if (entry.is_regular_file(ec) && is_mjcf_path(entry.path().string())) found.push_back(entry.path().string());
      if (found.empty()) throw InputError(printable(path) + ": no MJCF (*.xml) files in this folder");
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (std::filesystem::is_regular_file(path, ec)) {
      files.push_back(path);
    } else {
      throw InputError(printable(path) + ": no such file or folder");
    }
  }
  return files;
}

}  // namespace

ModelRow check_model(const std::string& path, int steps, HybridSchedule schedule, bool allow_dropped) {
  ModelRow row;
  row.path = path;
  Mechanism m;
  MjcfDropped dropped;
  try {
    m = load_mjcf(path, &dropped, allow_dropped);
  } catch (const InputError& e) {
    row.refused = e.what();
    return row;
  }
  row.dropped = describe(dropped);
  constexpr std::string_view kPrefix = "dropped: ";  // describe's; the field and the column say it
  if (row.dropped.rfind(kPrefix, 0) == 0) row.dropped.erase(0, kPrefix.size());
  row.bodies = static_cast<int>(m.bodies.size());
  row.constraints = static_cast<int>(m.constraints.size());
  row.rows = m.num_rows();
  row.timestep_s = m.timestep;
  StepOptions options;
  options.diagnostics = true;
  options.solver.schedule = schedule;
  const double size = mechanism_size(m);
  Simulation sim(m, options);
  std::vector<double> step_us;
  for (int s = 1; s <= steps; ++s) {
    const StepReport r = sim.step();
    step_us.push_back(r.step_us);
    row.steps = s;
    row.error.position_max = std::max(row.error.position_max, r.error.position_max);
    row.error.angular_max = std::max(row.error.angular_max, r.error.angular_max);
    row.penetration_max_m = std::max(row.penetration_max_m, r.penetration_max_m);
    if (std::string why = run_failure(r, size); !why.empty()) {
      row.failure = "step " + std::to_string(s) + ": " + why;
      break;
    }
  }
  row.step_us = median(step_us);
  const peers::PeerEngine mujoco = peers::mjcf_peer(path);
  if (!mujoco.available) {
    row.mujoco_skipped = mujoco.library + " is not installed";
  } else {
    const peers::PeerResult r = mujoco.run(m, steps * m.timestep);
    if (r.ran()) row.mujoco_step_us = r.step_us;
    else row.mujoco_skipped = r.skipped;
  }
  return row;
}

nlohmann::json row_json(const ModelRow& r) {
  nlohmann::json j = {{"path", r.path}, {"loaded", r.refused.empty()}};
  if (!r.refused.empty()) {
    j["refused"] = r.refused;
    return j;
  }
  j["scene"] = std::filesystem::path(r.path).stem().string();
  j["dropped"] = r.dropped;
  j["bodies"] = r.bodies;
  j["constraints"] = r.constraints;
  j["rows"] = r.rows;
  j["steps"] = r.steps;
  j["timestep_s"] = r.timestep_s;
  j["step_us"] = r.step_us;
  j["mujoco_step_us"] = r.mujoco_skipped.empty() ? number_or_null(r.mujoco_step_us) : nlohmann::json(nullptr);
  j["position_error_max_m"] = number_or_null(r.error.position_max);
  j["angular_error_max_rad"] = number_or_null(r.error.angular_max);
  j["penetration_max_m"] = number_or_null(r.penetration_max_m);
  j["failure"] = r.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.failure);
  return j;
}

namespace {

void print_table(const std::vector<ModelRow>& rows) {
  std::printf("%-28s %9s %9s %10s %10s %10s  %s\n", "model", "step_us", "mujoco_us", "joints_m", "joints_rad",
              "contact_m", "dropped / refused / failure");
  for (const ModelRow& r : rows) {
    const std::string name = std::filesystem::path(r.path).filename().string();
    if (!r.refused.empty()) {
      std::printf("%-28s %9s %9s %10s %10s %10s  refused: %s\n", name.c_str(), "-", "-", "-", "-", "-", r.refused.c_str());
      continue;
    }
    std::string note = !r.failure.empty() ? "failed: " + r.failure : r.dropped.empty() ? "" : "dropped: " + r.dropped;
    if (!r.mujoco_skipped.empty()) note += (note.empty() ? "" : "; ") + ("MuJoCo: " + r.mujoco_skipped);
    std::printf("%-28s %9.1f %9.1f %10.2g %10.2g %10.2g  %s\n", name.c_str(), r.step_us, r.mujoco_step_us,
                r.error.position_max, r.error.angular_max, r.penetration_max_m, note.c_str());
  }
}

}  // namespace

Command add_models_command(CLI::App& app) {
  auto a = std::make_shared<ModelsArgs>();
  CLI::App* cmd = app.add_subcommand("models", "Load and step MJCF models (files or folders) beside MuJoCo's own step");
  cmd->add_option("paths", a->paths, "MJCF files (.xml) and folders holding them")->required();
  cmd->add_option("--steps", a->steps, "Steps of each model's own timestep")->check(integer_in(1, 1000000));
  cmd->add_option("--schedule", a->schedule, "ldl-pgs with inequality rows, on steps without contacts: talk, "
                                              "inequality-pgs, block-gs or schur");
  add_json_flag(cmd, &a->json);
  add_allow_dropped_flag(cmd, &a->allow_dropped);
  return [a]() {
    if (!mjcf_supported()) throw InputError("ldlpgs models: built without MuJoCo, which reads MJCF models");
    const HybridSchedule schedule = schedule_option("--schedule", a->schedule);
    std::vector<ModelRow> rows;
    for (const std::string& path : model_files(a->paths)) {
      if (!a->json) progress("models", path);
      rows.push_back(check_model(path, a->steps, schedule, a->allow_dropped));
    }
    if (a->json) {
      nlohmann::json models = nlohmann::json::array();
      for (const ModelRow& r : rows) models.push_back(row_json(r));
      print_json(json_header("models", {{"solver", "ldl-pgs"}, {"schedule", a->schedule}, {"models", models}}));
    } else {
      print_table(rows);
    }
    return 0;
  };
}

}  // namespace ldlpgs::cli
