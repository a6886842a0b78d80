// --controls and --controls-file (apps/controls.h).
#include "apps/controls.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "apps/options.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs::cli {

namespace {

// One CSV line's numbers, or false if a field is not a number (a header).
bool parse_numbers(const std::string& line, std::vector<double>* out) {
  out->clear();
  size_t at = 0;
  while (at <= line.size()) {
    const size_t comma = std::min(line.find(',', at), line.size());
    std::string field = line.substr(at, comma - at);
    while (!field.empty() && (field.back() == ' ' || field.back() == '\r')) field.pop_back();
    while (!field.empty() && field.front() == ' ') field.erase(0, 1);
    size_t used = 0;
    try {
      out->push_back(std::stod(field, &used));
    } catch (const std::exception&) {
      return false;
    }
    if (used != field.size()) return false;
    at = comma + 1;
  }
  return true;
}

// check_controls' message with `where` in front ("f.csv:3: ..." or "--controls: ...").
void check(const Mechanism& m, std::span<const double> controls, const std::string& where) {
  try {
    check_controls(m.actuators, controls);
  } catch (const InputError& e) {
    std::string what = e.what();
    if (what.rfind("controls: ", 0) == 0) what.erase(0, 10);
    throw InputError(where + ": " + what);
  }
}

}  // namespace

void add_control_options(CLI::App* cmd, ControlArgs* a) {
  auto* values = add_list_option(cmd, "--controls", &a->values,
                                 "The actuators' controls for the whole run, in the model's actuator order");
  auto* file = cmd->add_option("--controls-file", a->file,
                               "CSV of time,control_1,...: each row's controls from its time (s) on, zero before the "
                               "first (a first line that is not numbers is a header)");
  values->excludes(file);
}

void add_allow_dropped_flag(CLI::App* cmd, bool* allow_dropped) {
  cmd->add_flag("--allow-dropped", *allow_dropped,
                "Step an MJCF model whose conversion leaves out something that changes its dynamics (listed on "
                "standard error) instead of refusing it");
}

ControlSchedule::ControlSchedule(const ControlArgs& a, const Mechanism& m) : zero_(m.actuators.size(), 0.0) {
  if (!a.values.empty()) {
    check(m, a.values, "--controls");
    times_.push_back(-HUGE_VAL);
    rows_.push_back(a.values);
    return;
  }
  if (a.file.empty()) return;
  std::ifstream in(a.file);
  if (!in) throw InputError(printable(a.file) + ": cannot read the controls file");
  std::string line;
  std::vector<double> numbers;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = printable(a.file) + ":" + std::to_string(number);
    if (line.empty() || line == "\r") continue;
    if (!parse_numbers(line, &numbers)) {
      if (number == 1) continue;  // the header
      throw InputError(where + ": not a row of numbers (time,control_1,...)");
    }
    if (numbers.size() != m.actuators.size() + 1)
      throw InputError(where + ": " + std::to_string(numbers.size()) + " fields, the model has " +
                       std::to_string(m.actuators.size()) + " actuators (time and one control each)");
    const double time = numbers[0];
    if (!std::isfinite(time) || (!times_.empty() && time < times_.back()))
      throw InputError(where + ": time " + format_number(time) + " is not finite or goes back");
    const std::span<const double> controls(numbers.data() + 1, numbers.size() - 1);
    check(m, controls, where);
    times_.push_back(time);
    rows_.emplace_back(controls.begin(), controls.end());
  }
  if (rows_.empty()) throw InputError(printable(a.file) + ": no rows of controls");
}

std::span<const double> ControlSchedule::at(double time) const {
  const auto after = std::upper_bound(times_.begin(), times_.end(), time);
  if (after == times_.begin()) return zero_;
  return rows_[after - times_.begin() - 1];
}

}  // namespace ldlpgs::cli
