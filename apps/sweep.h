#pragma once
// Speed against error (papers/speed-vs-error.md, `ldlpgs sweep`, `ldlpgs report`): each hard
// case stepped for a fixed simulated time with pgs, block-gs and ldl-pgs at several iteration
// counts, and direct; and the mass ratio at which each solver breaks.
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/mechanism.h"

namespace ldlpgs::cli {

// The hard cases: heavy-load chains at mass ratios 1e1..1e6, chains of 10 to 1000 links, the
// four-bar, the vehicles, the ragdoll (quick: fewer of them).
std::vector<std::string> sweep_cases(bool full);
std::vector<int> sweep_iterations(bool full);

struct SweepPoint {
  std::string scene, solver;
  int iterations = 0;
  double solve_us = 0;      // median per step
  double error = 0;         // largest position error (m) over the constraints after the run
  double error_max = 0;     // largest over the whole run
  bool failed = false;      // non-finite state, a failed factorization, or energy blow-up
};

// One scene stepped for `seconds` with one solver (direct: iterations ignored).
SweepPoint run_case(const Mechanism& m, const std::string& scene, const std::string& solver, int iterations,
                    double seconds);
// Every case, every solver, every iteration count (direct once per case; not on scenes with
// inequality rows). `progress` prints a line per case on stderr.
std::vector<SweepPoint> speed_vs_error(const std::vector<std::string>& cases, const std::vector<int>& iterations,
                                       double seconds, bool progress);

// The heaviest dynamic body (the last among equals) scaled in mass and inertia by `ratio`.
Mechanism with_mass_ratio(const Mechanism& m, double ratio);
struct Breakdown {
  std::string scene, solver;
  int iterations = 0;
  double survives = 0;   // the largest ratio 10^k (k = 0, 1, ...) still held (error < 1 cm, finite, no blow-up)
  double breaks = 0;     // the first ratio that failed (0: none up to the last tried)
  std::string how;       // "error", "non-finite", "energy", "singular"
};
std::vector<Breakdown> stability(const std::vector<std::string>& cases, int iterations, double seconds, bool progress);

void print_sweep_markdown(std::FILE* out, const std::vector<SweepPoint>& points);
// A row per case, per solver: the lowest final error reached (and the time per step it took),
// and the fastest run whose final error is within 1 mm ("-": none).
void print_sweep_summary(std::FILE* out, const std::vector<SweepPoint>& points);
void print_stability_markdown(std::FILE* out, const std::vector<Breakdown>& rows);
nlohmann::json to_json(const std::vector<SweepPoint>& points);

}  // namespace ldlpgs::cli
