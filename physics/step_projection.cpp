// The step's project-positions stage: post-stabilization (step.h), with the step's own factor or
// refactoring at the corrected pose.
#include "ldlpgs/physics/step_stages.h"

#include <algorithm>
#include <cmath>
#include <new>
#include <type_traits>

#include "ldlpgs/physics/chain_fits.h"

namespace ldlpgs {

using namespace step_stages;

double Simulation::position_rhs(bool with_jacobian) {
  if (with_jacobian) write_inverse_mass(mechanism_, column_, &system_);
  const Mechanism& m = mechanism_;
  double worst = 0;
  for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
    const Constraint& con = m.constraints[k];
    if (acts_on_a_dof(con.type)) {
      // No position error (c = 0), and its J stays the step's even when the projection refactors:
      // a soft row is the projection's metric there, not a constraint to meet. Nothing evaluated
      // (nor kept in evaluated_): re-fitting the chains in every iteration of a contact step's
      // projection was most of MuJoCo's humanoid's step (papers/physics.md, "MJCF models").
      system_.rhs[system_.blocks[k].position] = 0;
      continue;
    }
    // Constructed in place (the prvalue initializes the element: no 640-byte copy); the type is
    // trivially destructible, so the old value needs no destructor.
    static_assert(std::is_trivially_destructible_v<ConstraintRows>);
    const ConstraintRows& rows =
        *::new (static_cast<void*>(&evaluated_[k]))
            ConstraintRows(evaluate(con, m.bodies[con.body_a], m.bodies[con.body_b], chain_fits_.constraint(m, k)));
    if (with_jacobian) write_jacobian(rows, k, &system_);
    // (H_0 + E D_0) dmu = -c; an inequality row (c >= 0 respected, dmu >= 0) then asks only
    // J dq >= -c: a respected gap stays open, a violated one is closed.
    const bool equality = is_equality(con.type);
    for (int r = 0; r < rows.rows; ++r) {
      system_.rhs[system_.blocks[k].position + r] = -rows.c[r];
      worst = std::max(worst, equality ? std::abs(rows.c[r]) : -rows.c[r]);
    }
  }
  evaluated_valid_ = true;
  if (!contacts_.empty()) worst = std::max(worst, contact_rows(/*velocity=*/false, with_jacobian));
  return worst;
}

bool Simulation::post_stabilize(StepReport* report) {
  Solver& solver = projector_ ? *projector_ : solver_;
  // A dof_motor bounds a velocity impulse (friction loss, a servo's force): no position correction
  // meets it. (A dof_drive stays, as the step factored it: with c = 0 it turns the projection's
  // metric M into M + (a + dt b) z z^T, the joints still met exactly.)
  for (int k = 0; k < static_cast<int>(mechanism_.constraints.size()); ++k)
    if (mechanism_.constraints[k].type == ConstraintType::dof_motor) {
      const int i = system_.blocks[k].position;
      system_.lower[i] = system_.upper[i] = 0;
    }
  const int cap = options_.post_stabilize;
  bool refactor = options_.post_stabilize_refactor || (options_.contacts.refactor_projection && collision_);
  double previous = kUnbounded;
  for (int it = 0;; ++it) {
    const bool with_jacobian = refactor && it < cap;  // (the last evaluation only measures)
    // The first measure writes J only if it is needed: most steps end within the tolerance.
    double error = position_rhs(with_jacobian && it > 0);
    if (it == 0 && with_jacobian && error > options_.post_stabilize_tolerance) error = position_rhs(true);
    if (it > 0 && !(error < previous)) error = shorten_correction(previous, with_jacobian);
    if (it > 0 && !(error < previous) && !contacts_.empty()) error = continue_correction(solver, previous, refactor, with_jacobian);
    // A correction that did not lower the largest error even shortened is undone. J_0's
    // projection then turns to Newton's from the last pose; Newton's stops: on a mechanism whose
    // position-level hybrid has not converged (limits that the velocity step left far from their
    // active set) the corrections otherwise feed an instability.
    if (!(error < previous)) {
      if (it == 0) break;
      undo_correction(report);
      if (refactor || !options_.post_stabilize_refactor_on_stall || it == cap) break;
      refactor = true;
      error = position_rhs(/*with_jacobian=*/true);
    } else if (!refactor && it > 0 && error > 0.5 * previous && options_.post_stabilize_refactor_on_stall && it < cap) {
      refactor = true;  // J_0's corrections converge too slowly here (a fast swing)
      error = position_rhs(/*with_jacobian=*/true);
    }
    if (error <= options_.post_stabilize_tolerance || it == cap) break;
    previous = error;
    save_pose();
    std::fill(mu_.begin(), mu_.end(), 0.0);
    // Without a factor of its own (pgs, block-gs) the projector factors once per step, at J_0.
    SolveResult r;
    if (refactor || (projector_ && it == 0)) r = solver.factorize(system_);
    if (!r.ok()) return false;
    if (!solve_correction(solver, error)) return false;
    apply_correction(1);
    ++report->post_stabilize_iterations;
  }
  return true;
}

// dmu for the current position error (rhs, largest entry `error`), and dv_ = W J^T dmu.
bool Simulation::solve_correction(Solver& solver, double error) {
  if (contacts_.empty())
    return solver.resolve(system_, mu_, dv_, options_.post_stabilize_sweeps, HybridSchedule::inequality_pgs).ok();
  return solve_contact_correction(solver, error, options_.contacts.position_iterations);
}

// On a contact step, from mu_ on, at most `iterations` iterations. Contacts take their own
// schedule, block Gauss-Seidel run until the correction stops changing: the single block
// iteration of inequality-pgs leaves joints and contacts coupled, which turns Newton's quadratic
// convergence into a linear one (papers/physics.md, "The heavy ball on a chain"). "Stops
// changing": by less than kInexact times the error it corrects (an inexact Newton step; a fixed
// threshold let slow iterations stop with the error just above the tolerance). Where block
// Gauss-Seidel has not converged after ContactOptions::position_schur_after iterations, the
// contact rows' Schur complement takes over from its impulses, if they are few enough that its
// solve per row costs no more than the iterations' cap (papers/physics.md, "Vehicles on the ground").
bool Simulation::solve_contact_correction(Solver& solver, double error, int iterations) {
  constexpr double kInexact = 1e-3;
  const ContactOptions& o = options_.contacts;
  const double converged = kInexact * error;
  const bool then_schur = o.schedule == HybridSchedule::block_gs && o.position_schur_after > 0 &&
                          static_cast<int>(contacts_.size()) <= o.position_iterations;
  const int first = then_schur ? std::min(o.position_schur_after, iterations) : iterations;
  SolveResult r = solver.resolve(system_, mu_, dv_, first, o.schedule, converged);
  if (then_schur && r.ok() && !r.converged) r = solver.resolve(system_, mu_, dv_, iterations, HybridSchedule::schur, converged);
  return r.ok();
}

// A contact step's correction that raised the error even shortened: its iterations stopped at
// their cap unconverged (contacts pressing on jointed bodies converge slowly: a contact row's
// sweep moves one body that the joints then pull back). They are continued from their impulses
// with 2, 4, ... times as many, kMoreAccurate times: a Newton step made more exact only where the
// cheap one failed. Returns the error at the last pose tried.
double Simulation::continue_correction(Solver& solver, double previous, bool refactored, bool with_jacobian) {
  constexpr int kMoreAccurate = 4;
  double error = kUnbounded;
  for (int k = 1; k <= kMoreAccurate && !(error < previous); ++k) {
    restore_pose();
    position_rhs(refactored);  // the saved pose's rows, those the factor was computed from
    if (!solve_contact_correction(solver, previous, options_.contacts.position_iterations << k)) break;
    apply_correction(1);
    error = position_rhs(with_jacobian);
    if (!(error < previous)) error = shorten_correction(previous, with_jacobian);
  }
  return error;
}

void Simulation::undo_correction(StepReport* report) {
  restore_pose();
  evaluated_valid_ = false;
  --report->post_stabilize_iterations;
  ++post_stabilize_rejected_;
}

// The saved pose moved by `scale` times the last correction W J^T dmu (dv_): positions by its
// linear part, orientations by its angular part as a world-frame rotation vector.
void Simulation::apply_correction(double scale) {
  evaluated_valid_ = false;
  int c = 0;
  for (RigidBody& b : mechanism_.bodies) {
    if (b.is_static) continue;
    const double* dq = dv_.data() + 6 * c++;
    b.position += scale * Eigen::Vector3d(dq[0], dq[1], dq[2]);
    rotate(b, scale * Eigen::Vector3d(dq[3], dq[4], dq[5]));
  }
}

// A correction that raised the largest error is retried at half, a quarter, ... (a backtracking
// line search, kBacktracks times): near a straight chain's configuration a full Newton or J_0
// step overshoots where a shorter one still lowers the error (papers/physics.md, "The heavy ball
// on a chain"). Returns the error at the last pose tried.
double Simulation::shorten_correction(double previous, bool with_jacobian) {
  constexpr int kBacktracks = 4;
  double error = kUnbounded;
  for (int h = 1; h <= kBacktracks && !(error < previous); ++h) {
    restore_pose();
    apply_correction(std::ldexp(1.0, -h));
    error = position_rhs(with_jacobian);
  }
  return error;
}

void Simulation::save_pose() {
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) {
    saved_position_[b] = mechanism_.bodies[b].position;
    saved_orientation_[b] = mechanism_.bodies[b].orientation;
  }
}

void Simulation::restore_pose() {
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) {
    mechanism_.bodies[b].position = saved_position_[b];
    mechanism_.bodies[b].orientation = saved_orientation_[b];
  }
}
}  // namespace ldlpgs
