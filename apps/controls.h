#pragma once
// The actuators' controls over a run of step and view (an MJCF model's actuators, in its order):
// --controls v1,v2,... held for the whole run, or --controls-file, a CSV of time and controls
// whose rows each hold from their time on (zero before the first).
#include <CLI/CLI.hpp>

#include <span>
#include <string>
#include <vector>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::cli {

struct ControlArgs {
  std::vector<double> values;  // --controls
  std::string file;            // --controls-file
};
void add_control_options(CLI::App* cmd, ControlArgs* a);

// --allow-dropped: step an MJCF model whose conversion leaves out something that changes its
// dynamics (listed on standard error) instead of refusing it.
void add_allow_dropped_flag(CLI::App* cmd, bool* allow_dropped);

class ControlSchedule {
 public:
  // Reads and checks the controls for `m`'s actuators (physics/actuation.h, check_controls): an
  // InputError naming the flag or the file and line, and the actuator.
  ControlSchedule(const ControlArgs& a, const Mechanism& m);
  bool empty() const { return rows_.empty(); }
  // The controls at time t (s): the last row whose time is <= t (zero before the first).
  std::span<const double> at(double time) const;

 private:
  std::vector<double> times_;
  std::vector<std::vector<double>> rows_;  // (size times_)
  std::vector<double> zero_;
};

}  // namespace ldlpgs::cli
