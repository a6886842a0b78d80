#pragma once
// A user's MJCF models checked beside MuJoCo's own step (ldlpgs models, and the report's stage).
#include <nlohmann/json.hpp>

#include <string>

#include "ldlpgs/physics/step.h"

namespace ldlpgs::cli {

// One model's row: loaded or refused and why, what was dropped, step times (ours and MuJoCo's
// medians), our largest joint error, deepest contact, and the first step that came apart.
struct ModelRow {
  std::string path, refused, dropped;
  int bodies = 0, constraints = 0, rows = 0, steps = 0;
  double timestep_s = 0, step_us = 0, mujoco_step_us = 0;
  ConstraintError error;  // largest over the steps
  double penetration_max_m = 0;
  std::string failure, mujoco_skipped;
};

// The model loaded (physics/io/mjcf.h), stepped `steps` steps of its own timestep by our ldl-pgs
// with `schedule`, then by MuJoCo (peers/peer.h, mjcf_peer), both at zero controls.
ModelRow check_model(const std::string& path, int steps, HybridSchedule schedule, bool allow_dropped);
// Its --json object (docs/cli.md's vocabulary).
nlohmann::json row_json(const ModelRow& row);

}  // namespace ldlpgs::cli
