#pragma once
// Stepping a mechanism (the talk's velocity step, semi-implicit Euler):
//   V1 = V0 + W F dt + W J^T lambda,  lambda such that J V1 = target,
// target = -beta c / dt on equality rows (Baumgarte: a fraction beta of the position error c is
// corrected per step), and on an inequality row (c >= 0 when respected) J V1 >= -c / dt while
// c >= 0 (it may close the gap, not cross it) and J V1 >= -beta c / dt once violated, with
// lambda >= 0. Then positions and orientation quaternions are integrated with V1 and the
// quaternions renormalized. F is gravity, the bodies' constant loads (RigidBody::applied_force)
// and the forces applied for this step (Simulation::apply_force).
//
// Post-stabilization (position projection; Cline and Pai, "Post-stabilization for rigid body
// simulation with contact and constraints", ICRA 2003) then removes the position error the
// velocity step leaves, which is semi-implicit Euler's drift along the constraint manifold's
// curvature, (1/2) dt^2 |w x (w x r)| per step: with q1 the integrated pose, each iteration
//   solves (H_0 + E D_0) dmu = -c(q)  with the step's own factor (J_0, W_0 at the step's start),
//   moves q by W_0 J_0^T dmu: positions by its linear part, orientations by its angular part as
//   a world-frame rotation vector, q <- exp(dtheta) q (then normalized).
// A correction must use the factor's own J_0 and W_0: with the factor of J_0 and the Jacobian at
// q1 the two disagree and the correction is no longer a projection (measured: the tracked vehicle
// flew apart). Inequality rows take part with dmu >= 0 (the step's own hybrid at position level).
// With `post_stabilize_refactor`, each iteration instead evaluates J and W at the corrected pose
// and refactors (Newton: quadratic, not linear, convergence; about a factorization per iteration).
//
// The symbolic phase (ordering, block LDL^T symbolic) runs in the constructor and is reused by
// every step as long as the topology is the same: writing the state, forces, gravity or the
// timestep between steps keeps it. After the first step, step() allocates no memory.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/physics/chain_fits.h"
#include "ldlpgs/physics/collision.h"
#include "ldlpgs/physics/contact.h"
#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/solver/solver.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

struct StepOptions {
  SolverOptions solver;
  // eps of the compliance eps diag(H) (the talk): makes H of redundant loops invertible. Chosen
  // by measurement (papers/physics.md, "Compliance").
  double compliance = 1e-8;
  double baumgarte = 0.2;  // beta: fraction of the position error corrected per step
  // Post-stabilization: at most this many iterations per step reusing the step's factor (0:
  // off), stopping once no row's error exceeds the tolerance (m on translational rows, rad on
  // angular ones; inequality rows count only when violated). kAutoPostStabilize: 30 on the
  // solvers that factor (ldl-pgs, direct), 0 on pgs and block-gs, which have no factor to reuse
  // (given a count, they get one of their own: a factorization per step). Defaults chosen by
  // measurement (papers/physics.md, "Post-stabilization").
  static constexpr int kAutoPostStabilize = -1;
  int post_stabilize = kAutoPostStabilize;
  double post_stabilize_tolerance = 1e-9;
  // Each post-stabilization iteration refactors at the corrected pose (Newton) instead.
  bool post_stabilize_refactor = false;
  // ... from the first correction with J_0 that lowers the error by less than half (or not at
  // all, even shortened), as on a fast swing, instead of going on or stopping there
  // (papers/physics.md, "The heavy ball on a chain").
  bool post_stabilize_refactor_on_stall = true;
  // Iterations of the hybrid at position level on a mechanism with inequality rows (limits,
  // ropes), as PGS sweeps over the inequality rows only, then the block step (schedule
  // inequality-pgs): ropes nearly redundant with rods need the position solve converged on their
  // rows, or the corrections feed a slow instability (the rope bridge: papers/physics.md).
  int post_stabilize_sweeps = 40;
  // Equality rows' velocity target gains the constraint's curvature along the current motion,
  // -(dt/2) V^T c'' V, measured as c(q0 + dt V) - c0 - dt J V (one more evaluation of every
  // constraint per step): the energy-consistent variant of papers/physics.md.
  bool curvature_target = false;
  // Fill StepReport's error, velocity residual, energy and deepest contact (costs one more
  // evaluation of every constraint and contact per step; the CLI asks, a library stepping for
  // speed need not).
  bool diagnostics = false;
  // Bodies' shapes that touch become contact rows (physics/contact.h).
  ContactOptions contacts;
};

// No inequality rows (limits, ropes) and no shapes (contacts): what the direct solver steps.
bool equality_only(const Mechanism& mechanism);

// The talk's projection: with the step's own factor (J_0) only, never refactoring (clears
// post_stabilize_refactor_on_stall and ContactOptions::refactor_projection).
void use_own_factor_projection(StepOptions* options);

// The iterations `options` asks for, kAutoPostStabilize resolved for its solver.
int post_stabilize_iterations(const StepOptions& options);

// Position errors over all constraint rows, at the current pose: equality rows |c|, inequality
// rows max(0, -c) (only violation counts).
struct ConstraintError {
  double position_max = 0, position_rms = 0;  // translational rows (m)
  double angular_max = 0, angular_rms = 0;    // angular rows (rad)
};
// `fits`: a Simulation's shared chain fits (chain_fits.h), or null.
ConstraintError constraint_error(const Mechanism& mechanism, ChainFits* fits = nullptr);

// Kinetic plus gravitational potential energy (J), potential zero at the origin.
double total_energy(const Mechanism& mechanism);

// The step's impulse problem at the current state (columns = dynamic bodies in order): J, W,
// bounds, R = target - J (V0 + W F dt), compliance. Exposed so tests and `export` see what
// the solvers see.
System build_system(const Mechanism& mechanism, const StepOptions& options);

struct StepReport {
  // Each stage's time (physics/step_stages.h), and the whole step's
  double contact_us = 0;          // collide: collision detection and the contacts' matching
  double prepare_us = 0;          // prepare: joint dynamics, loads, J, W, R (the contacts' rows too)
  double solve_us = 0;            // the velocity solve alone (numeric phase: H, LDL^T, sweeps)
  double integrate_us = 0;        // impulses stored, velocities and poses integrated
  double post_stabilize_us = 0;   // the position correction (evaluations, solves, moves)
  double step_us = 0;             // the whole step (StepOptions::diagnostics' errors and energy not included)
  int contacts = 0;               // contact points this step
  int post_stabilize_iterations = 0;  // done (0 when off, or skipped after a failed factorization)
  SolveResult result;             // a failed factorization is reported here (the PGS impulses are used)
  // With StepOptions::diagnostics (zero otherwise):
  ConstraintError error;          // after the step
  double velocity_residual = 0;   // max |J V1 - target| as solver.h defines it (m/s, rad/s)
  double energy = 0;              // after the step
  double penetration_max_m = 0;   // the deepest of this step's contact points after it (m)
};

// A run that has come apart: at a mass ratio of 1e12 a solver can end a 5 m heavy chain tens of
// metres off its constraints, which must not pass for a result (README, "Supported range"). The size
// is the diagonal of the box around the bodies' centres and the constraints' anchors at the
// start; a run has failed once a step's state is not finite or its largest translational
// constraint error exceeds kApartFraction of that size: the mechanism is then not the one
// simulated. A detector of collapse, not of accuracy: a sound solver stays below 1e-6 of it
// (README, "Supported range").
inline constexpr double kApartFraction = 0.1;
double mechanism_size(const Mechanism& mechanism);
// Empty while the step (its report filled with StepOptions::diagnostics) is sound; otherwise the
// reason, one line ("non-finite state", "position error 49.6 m, beyond 0.1 of the mechanism's
// size 5.02 m: it came apart").
std::string run_failure(const StepReport& report, double size);

class Simulation {
 public:
  Simulation(Mechanism mechanism, const StepOptions& options);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  StepReport step();

  const Mechanism& mechanism() const { return mechanism_; }
  const StepOptions& options() const { return options_; }
  double time() const { return time_; }
  const Solver& solver() const { return solver_; }
  std::span<const double> impulses() const { return lambda_; }  // last step's lambda (size rows)
  // Steps whose post-stabilization was skipped because its factorization failed.
  int post_stabilize_skipped() const { return post_stabilize_skipped_; }
  // Corrections undone because they did not lower the largest error (the iteration then stops).
  int64_t post_stabilize_rejected() const { return post_stabilize_rejected_; }

  // The state between steps. Bodies are indices into mechanism().bodies (find_body for names).
  // Every write is checked in every build and refused with an InputError naming the body: an
  // index out of range, a non-finite value, a quaternion whose norm is off 1 by more than 1e-6
  // (within that it is normalized), a velocity or force on a static body (it never moves;
  // moving its position or orientation is allowed and carries its anchors).
  void set_position(int body, const Eigen::Vector3d& position);
  void set_orientation(int body, const Eigen::Quaterniond& orientation);
  void set_linear_velocity(int body, const Eigen::Vector3d& velocity);
  void set_angular_velocity(int body, const Eigen::Vector3d& velocity);
  // Flat arrays over all bodies in order, as MuJoCo's mjData keeps them: positions 3 per body
  // (xpos), orientations 4 per body (w, x, y, z: xquat), velocities 6 per body (linear then
  // angular, world frame). A span of the wrong size is refused.
  void get_positions(std::span<double> out) const;
  void get_orientations(std::span<double> out) const;
  void get_velocities(std::span<double> out) const;
  void set_positions(std::span<const double> in);
  void set_orientations(std::span<const double> in);
  void set_velocities(std::span<const double> in);  // static bodies' entries must be zero
  // An external force (N) through the centre of mass and a torque (N m), world frame, for the
  // next step only (they add up until it; MuJoCo's xfrc_applied, but cleared by step()). A
  // constant load is RigidBody::applied_force.
  void apply_force(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& torque = Eigen::Vector3d::Zero());
  // The same force applied at a world point: adds the torque (point - centre) x force.
  void apply_force_at(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& point);
  void set_gravity(const Eigen::Vector3d& gravity);  // m/s^2, finite
  // A shape on a body (physics/shape.h; checked as scene files are), touching from the next step.
  void add_shape(int body, const Shape& shape);
  // The last step's contact points: where, the normal, the depth at detection, and the impulses
  // the step applied (Contact::impulse: normal, two friction).
  std::span<const Contact> contacts() const { return contacts_; }
  void set_timestep(double timestep);                // s, finite and > 0
  // The actuators' controls (MuJoCo's ctrl, in the order of mechanism().actuators), applied by
  // every step from the next on; zero at the start. Checked in every build (check_controls: the
  // count, finite, inside ctrlrange where limited) and refused with an InputError naming the
  // actuator.
  void set_controls(std::span<const double> controls);
  std::span<const double> controls() const { return controls_; }

 private:
  RigidBody& writable(int body, const char* what, bool dynamic_only);
  // The stages of step() (physics/step_stages.h lists their files)
  void prepare_velocity_step();             // joint dynamics, loads, then velocity_system()
  void integrate();                         // V1 into the bodies, then their poses
  void diagnose(StepReport* report);        // StepOptions::diagnostics' fields
  void velocity_system();                   // J, W, rhs at the current pose into system_
  double position_rhs(bool with_jacobian);  // rhs = -c at the current pose (and J, W with it); max error
  bool post_stabilize(StepReport* report);  // false: a factorization failed
  void apply_correction(double scale);       // the saved pose moved by scale W J^T dmu
  double shorten_correction(double previous, bool with_jacobian);  // backtracking; the error reached
  double continue_correction(Solver& solver, double previous, bool refactored, bool with_jacobian);  // more sweeps
  void undo_correction(StepReport* report);  // back to the saved pose, counted as rejected
  bool solve_correction(Solver& solver, double error);  // dmu and dv_ for the current rhs; false: no factor
  bool solve_contact_correction(Solver& solver, double error, int iterations);  // ... on a contact step
  void save_pose();
  void restore_pose();
  void make_projector();                    // projector_, when the solver has no factor to reuse
  void detect_contacts();                   // this step's contacts, their blocks and warm start
  void mark_factored_contacts();            // ... which of them ldl-pgs factors
  void order_factored_first();              // ... its contacts reordered
  double contact_rows(bool velocity, bool with_jacobian);  // their rows at the current pose (velocity or position level)
  void keep_contact_impulses();             // lambda into the contacts, for the next step
  void keep_dof_rates();                    // the driven dofs' rates after the solve (actuation.h)
  void forget_dof_rates();                  // ... none: the state was written
  double penetration_max() const;

  Mechanism mechanism_;
  StepOptions options_;
  std::vector<int> column_;     // velocity block of each body, -1 static (size bodies)
  System system_;               // structure fixed; values rewritten every step
  Solver solver_;
  std::unique_ptr<Solver> projector_;  // post-stabilization's LDL^T when solver_ has none (pgs, block-gs)
  std::vector<double> lambda_;  // warm start (size rows)
  std::vector<double> dv_;      // W J^T lambda (size 6 dynamic bodies)
  std::vector<double> v0_;      // V0 + W F dt (size 6 dynamic bodies)
  std::vector<double> mu_;      // post-stabilization's dmu (size rows)
  std::vector<double> predicted_;  // curvature_target: c at q0 + dt V (size rows)
  std::vector<ConstraintRows> evaluated_;  // the constraints at the last pose position_rhs saw (size constraints)
  bool evaluated_valid_ = false;           // ... and the bodies are still there
  std::vector<double> load_;    // forces and torques applied for the next step (size 6 bodies)
  std::vector<Eigen::Vector3d> saved_position_;       // the pose before a correction (size bodies)
  std::vector<Eigen::Quaterniond> saved_orientation_;  // (size bodies)
  double time_ = 0;
  int post_stabilize_skipped_ = 0;
  int64_t post_stabilize_rejected_ = 0;
  // Contacts: system_'s blocks past the constraints', two per contact (normal, friction).
  int joint_blocks_ = 0;
  std::vector<char> jointed_;                  // the body has an equality constraint (size bodies)
  std::vector<char> carrying_;                 // mark_factored_contacts' (size bodies)
  std::unique_ptr<CollisionWorld> collision_;  // null while no body has a shape
  std::vector<ContactPoint> points_;           // detected this step
  std::vector<Eigen::Matrix3d> rotations_;     // the bodies' orientations, per pass over the contacts
  std::vector<Contact> contacts_, previous_contacts_;  // (previous: also the reordering's buffer)
  std::vector<ContactKey> contact_keys_;       // make_contacts' and the reordering's scratch
  // Joint dynamics and actuators (physics/actuation.h)
  std::vector<double> controls_;    // (size actuators)
  std::vector<DofState> dof_states_;  // joint_dynamics' scratch (size dofs)
  std::vector<DofRow> dof_rows_;    // the dof_drive and dof_motor rows' targets (size constraints)
  std::vector<double> dof_rates_;   // each dof's rate after the last solve, NaN before (size dofs)
  ChainFits chain_fits_;            // each joint chain's fit, once per pose
};

}  // namespace ldlpgs
