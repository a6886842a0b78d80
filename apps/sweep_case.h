#pragma once
// One run of speed against error (apps/sweep.h): a scene stepped for a fixed simulated time with
// one solver, and what made it fail. The program's `sweep` and `report` and the Python module's
// sweep_run (python/physics.cpp, behind ldlpgs.study) run this same code, so a study's rows are
// the program's points.
#include <string>

#include <nlohmann/json.hpp>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::cli {

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
// The heaviest dynamic body (the last among equals) scaled in mass and inertia by `factor`.
Mechanism with_heavier_load(const Mechanism& m, double factor);
// Heaviest over lightest dynamic mass.
double mass_ratio(const Mechanism& m);
// One point's object (docs/cli.md, "Command-line vocabulary"); a blown-up run's errors are null.
nlohmann::json to_json(const SweepPoint& p);

}  // namespace ldlpgs::cli
