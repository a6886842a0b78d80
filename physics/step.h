#pragma once
// Stepping a mechanism (the talk's velocity step, semi-implicit Euler):
//   V1 = V0 + W F dt + W J^T lambda,  lambda such that J V1 = target,
// target = -beta c / dt on equality rows (Baumgarte: a fraction beta of the position error c is
// corrected per step), and on an inequality row (c >= 0 when respected) J V1 >= -c / dt while
// c >= 0 (it may close the gap, not cross it) and J V1 >= -beta c / dt once violated, with
// lambda >= 0. Then positions and orientation quaternions are integrated with V1 and the
// quaternions renormalized. The symbolic phase (ordering, block LDL^T symbolic) runs once in the
// constructor and is reused by every step: the topology never changes during a run.
#include <chrono>
#include <span>
#include <vector>

#include "physics/mechanism.h"
#include "solver/solver.h"
#include "sparse/csc.h"

namespace ldlpgs {

struct StepOptions {
  SolverOptions solver;
  // eps of the compliance eps diag(H) (the talk): makes H of redundant loops invertible. Chosen
  // by measurement (papers/physics.md, "Compliance").
  double compliance = 1e-8;
  double baumgarte = 0.2;  // beta: fraction of the position error corrected per step
};

// Position errors over all constraint rows, at the current pose: equality rows |c|, inequality
// rows max(0, -c) (only violation counts).
struct ConstraintError {
  double position_max = 0, position_rms = 0;  // translational rows (m)
  double angular_max = 0, angular_rms = 0;    // angular rows (rad)
};
ConstraintError constraint_error(const Mechanism& mechanism);

// Kinetic plus gravitational potential energy (J), potential zero at the origin.
double total_energy(const Mechanism& mechanism);

// The step's impulse problem at the current state (columns = dynamic bodies in order): J, W,
// bounds, R = target - J (V0 + W F dt), compliance. Exposed so tests and `export` see what
// the solvers see.
System build_system(const Mechanism& mechanism, const StepOptions& options);

struct StepReport {
  double solve_us = 0;           // Solver::solve alone (numeric phase: H, LDL^T, sweeps)
  ConstraintError error;         // after the step
  double velocity_residual = 0;  // max |J V1 - target| as solver.h defines it (m/s, rad/s)
  double energy = 0;             // after the step
  SolveResult result;            // a failed factorization is reported here (the PGS impulses are used)
};

class Simulation {
 public:
  Simulation(Mechanism mechanism, const StepOptions& options);
  StepReport step();
  const Mechanism& mechanism() const { return mechanism_; }
  double time() const { return time_; }
  const Solver& solver() const { return solver_; }
  std::span<const double> impulses() const { return lambda_; }  // last step's lambda (size rows)

 private:
  Mechanism mechanism_;
  StepOptions options_;
  Solver solver_;
  System system_;
  std::vector<double> lambda_;  // warm start (size rows)
  std::vector<double> dv_;      // W J^T lambda (size 6 dynamic bodies)
  double time_ = 0;
};

}  // namespace ldlpgs
