#pragma once
// Speed against error (papers/speed-vs-error.md, `ldlpgs sweep`, `ldlpgs report`): each hard
// case stepped for a fixed simulated time with pgs, block-gs and ldl-pgs at several iteration
// counts, and direct; and the mass ratio at which each solver breaks.
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::cli {

// The hard cases: heavy-load chains at mass ratios 1e1..1e6, chains of 10 to 1000 links, the
// four-bar, the torque-driven crank, the vehicles, the ragdoll, and with contacts the 1:1000
// stack, the heavy ball on a chain, the pyramid, the vehicles on the ground (quick: fewer).
std::vector<std::string> sweep_cases(bool full);
std::vector<int> sweep_iterations(bool full);

struct SweepPoint {
  std::string scene, solver;
  int iterations = 0;
  double solve_us = 0;          // median per step
  double error = 0;             // largest position error (m) over the constraints after the run
  double error_max = 0;         // largest over the whole run
  double angular_error = 0;     // the same for angular rows (rad)
  double angular_error_max = 0;
  double penetration_max = 0;   // the deepest contact at the end of any step (m; 0 without shapes)
  // Why the run failed, "" if it did not: "non-finite" (a NaN or infinity in the state),
  // "energy" (a blow-up: see blew_up), "singular" (a step's factorization failed; the step
  // went on with the PGS impulses, as Simulation does).
  std::string failure;
  bool failed() const { return !failure.empty(); }
};

// An energy blow-up: the mechanism gained more than it takes to lift all of it by its own size
// against gravity, plus its initial kinetic energy (at least 1 J), beyond the work its constant
// loads (RigidBody::applied_force, applied_torque) did. Gravity is conservative and
// Baumgarte's correction moves positions by a fraction of the error, so a sound step cannot
// gain that; the test does not depend on where potential energy is zero.
double blow_up_energy(const Mechanism& m);

// One scene stepped for `seconds` with one solver (direct: iterations ignored).
SweepPoint run_case(const Mechanism& m, const std::string& scene, const std::string& solver, int iterations,
                    double seconds);
// Every case, every solver, every iteration count (direct once per case; not on scenes with
// inequality rows). `progress` prints a line per case on stderr.
std::vector<SweepPoint> speed_vs_error(const std::vector<std::string>& cases, const std::vector<int>& iterations,
                                       double seconds, bool progress);

// The heaviest dynamic body (the last among equals) scaled in mass and inertia by `factor`.
Mechanism with_heavier_load(const Mechanism& m, double factor);
// Heaviest over lightest dynamic mass.
double mass_ratio(const Mechanism& m);
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
