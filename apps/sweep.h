#pragma once
// Speed against error (papers/speed-vs-error.md, `ldlpgs sweep`, `ldlpgs report`): each hard
// case stepped for a fixed simulated time with pgs, block-gs and ldl-pgs at several iteration
// counts, and direct; and the mass ratio at which each solver breaks.
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/sweep_case.h"
#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::cli {

// The hard cases: heavy-load chains at mass ratios 1e1..1e6, chains of 10 to 1000 links, the
// four-bar, the torque-driven crank, the vehicles, the ragdoll, and with contacts the 1:1000
// stack, the heavy ball on a chain, the pyramid, the vehicles on the ground (quick: fewer).
std::vector<std::string> sweep_cases(bool full);
std::vector<int> sweep_iterations(bool full);

// Every case, every solver, every iteration count (direct once per case; not on scenes with
// inequality rows). `progress` prints a line per case on stderr.
std::vector<SweepPoint> speed_vs_error(const std::vector<std::string>& cases, const std::vector<int>& iterations,
                                       double seconds, bool progress);

struct Breakdown {
  std::string scene, solver;
  int iterations = 0;
  double survives = 0;   // the largest mass ratio still held (error < 1 cm, no failure); 0: none
  double breaks = 0;     // the first mass ratio that failed (0: none up to the last tried)
  std::string how;       // "error > 1 cm", or SweepPoint::failure
};
std::vector<Breakdown> stability(const std::vector<std::string>& cases, int iterations, double seconds, bool progress);

void print_sweep_markdown(std::FILE* out, const std::vector<SweepPoint>& points);
// A row per case, per solver: the lowest error reached over a run (the cheapest run within 1% of
// it, and its time per step), and the fastest run whose error stays within 1 mm ("-": none).
void print_sweep_summary(std::FILE* out, const std::vector<SweepPoint>& points);
void print_stability_markdown(std::FILE* out, const std::vector<Breakdown>& rows);
nlohmann::json to_json(const std::vector<Breakdown>& rows);
// The points, one object each (docs/cli.md, "Command-line vocabulary").
nlohmann::json to_json(const std::vector<SweepPoint>& points);
// What `sweep --json` prints and `--json-file` writes: the points and the simulated time of each run.
nlohmann::json sweep_json(const std::vector<SweepPoint>& points, double seconds);

}  // namespace ldlpgs::cli
