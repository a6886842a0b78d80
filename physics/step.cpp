// The velocity step of the talk (semi-implicit Euler) around the constraint solver.
#include "ldlpgs/physics/step.h"

#include <cassert>
#include <algorithm>
#include <chrono>
#include <climits>
#include <limits>
#include <cmath>
#include <cstdio>
#include <new>
#include <string>
#include <type_traits>

#include <Eigen/Geometry>

#include "ldlpgs/physics/chain_fits.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {

// column[b] = the velocity block of body b, -1 for a static body (size num_bodies)
std::vector<int> body_columns(const Mechanism& m) {
  std::vector<int> column(m.bodies.size(), -1);
  int next = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b)
    if (!m.bodies[b].is_static) column[b] = next++;
  return column;
}

}  // namespace

ConstraintError constraint_error(const Mechanism& m, ChainFits* fits) {
  ConstraintError e;
  double sum_p = 0, sum_a = 0;
  int n_p = 0, n_a = 0;
  for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
    const Constraint& c = m.constraints[k];
    const ConstraintRows rows = evaluate(c, m.bodies[c.body_a], m.bodies[c.body_b], fits ? fits->constraint(m, k) : nullptr);
    for (int r = 0; r < rows.rows; ++r) {
      const double v = is_equality(c.type) ? std::abs(rows.c[r]) : std::max(0.0, -rows.c[r]);
      if (rows.angular[r]) {
        e.angular_max = std::max(e.angular_max, v);
        sum_a += v * v;
        ++n_a;
      } else {
        e.position_max = std::max(e.position_max, v);
        sum_p += v * v;
        ++n_p;
      }
    }
  }
  e.position_rms = n_p ? std::sqrt(sum_p / n_p) : 0;
  e.angular_rms = n_a ? std::sqrt(sum_a / n_a) : 0;
  return e;
}

double total_energy(const Mechanism& m) {
  double e = 0;
  for (const RigidBody& b : m.bodies)
    if (!b.is_static) e += b.kinetic_energy() - b.mass * m.gravity.dot(b.position);
  return e;
}

double mechanism_size(const Mechanism& m) {
  Eigen::AlignedBox3d box;
  for (const RigidBody& b : m.bodies) box.extend(b.position);
  for (const Constraint& c : m.constraints) {
    box.extend(m.bodies[c.body_a].to_world(c.anchor_a));
    box.extend(m.bodies[c.body_b].to_world(c.anchor_b));
  }
  return box.isEmpty() ? 0 : box.diagonal().norm();
}

std::string run_failure(const StepReport& r, double size) {
  if (!std::isfinite(r.energy) || !std::isfinite(r.error.position_max) || !std::isfinite(r.error.angular_max))
    return "non-finite state";
  if (size > 0 && r.error.position_max > kApartFraction * size) {
    char line[200];
    std::snprintf(line, sizeof line, "position error %.3g m, beyond %g of the mechanism's size %.3g m: it came apart",
                  r.error.position_max, kApartFraction, size);
    return line;
  }
  return "";
}

namespace {

// The structure of the step's System: one block per constraint in order, inequality blocks
// bounded below by 0. Values are written by write_velocity_system.
System system_structure(const Mechanism& m, const std::vector<int>& column) {
  System s;
  s.num_columns = m.num_dynamic_bodies();
  s.inverse_mass.assign(36 * static_cast<size_t>(s.num_columns), 0.0);
  for (const Constraint& con : m.constraints) {
    const int k = s.add_block(num_rows(con), column[con.body_a], column[con.body_b]);
    if (!is_equality(con.type)) s.set_bounds(k, 0, kUnbounded);
  }
  s.set_compliance(0);
  return s;
}

// W_b = blockdiag(I3 / m, R diag(1/I) R^T) per column, at the current orientations.
void write_inverse_mass(const Mechanism& m, const std::vector<int>& column, System* s) {
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const int c = column[b];
    if (c < 0) continue;
    const RigidBody& body = m.bodies[b];
    double* w = s->inverse_mass.data() + 36 * c;
    const Eigen::Matrix3d inv_i = body.inverse_inertia_world();
    for (int i = 0; i < 3; ++i) {
      w[6 * i + i] = 1 / body.mass;
      for (int j = 0; j < 3; ++j) w[6 * (3 + i) + 3 + j] = inv_i(i, j);
    }
  }
}

// Constraint k's rows (c and J, evaluated at the current pose) into the System's cells.
void write_jacobian(const ConstraintRows& rows, int k, System* s) {
  for (int r = 0; r < rows.rows; ++r) {
    const double* j = rows.jacobian.data() + 12 * r;
    std::copy(j, j + 6, s->cell_a(k) + 6 * r);
    std::copy(j + 6, j + 12, s->cell_b(k) + 6 * r);
  }
}

// ContactOptions::implicit_gyroscopic applies: it is on and the mechanism has shapes.
bool implicit_gyroscopic(const Mechanism& m, const StepOptions& options) {
  return options.contacts.implicit_gyroscopic && has_shapes(m);
}

// w' with I (w' - w) + dt w' x I w' = 0 in the body frame (the gyroscopic term implicit), by one
// Newton step from w, whose Jacobian is I + dt ([w]x I - [I w]x).
Eigen::Vector3d gyroscopic_velocity(const RigidBody& b, double dt) {
  const Eigen::Vector3d w = b.orientation.conjugate() * b.angular_velocity;
  const Eigen::Vector3d iw = b.inertia.cwiseProduct(w);
  const auto cross_matrix = [](const Eigen::Vector3d& a) {
    Eigen::Matrix3d m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
  };
  const Eigen::Matrix3d jacobian = Eigen::Matrix3d(b.inertia.asDiagonal()) +
                                   dt * (cross_matrix(w) * b.inertia.asDiagonal() - cross_matrix(iw));
  return b.orientation * (w - jacobian.partialPivLu().solve(dt * w.cross(iw)));
}

// The velocity step's values, each constraint evaluated once: W, J, R = target - J (V0 + W F dt)
// and the compliance. v0 (size 6 columns) receives V0 + W F dt; load (size 6 bodies, or empty)
// holds the forces and torques applied for this step on top of gravity and the constant loads.
// predicted (size rows, or empty): c at q0 + dt V, the pose the current velocities V reach,
// for the curvature target (StepOptions::curvature_target). known (size constraints, or empty):
// the constraints already evaluated at this pose.
void write_velocity_system(const Mechanism& m, const StepOptions& options, const std::vector<int>& column,
                           std::span<const double> load, std::span<const double> predicted,
                           std::span<const ConstraintRows> known, ChainFits* fits, std::span<double> v0,
                           System* s) {
  const double dt = m.timestep;
  const bool gyroscopic = implicit_gyroscopic(m, options);
  write_inverse_mass(m, column, s);
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const int c = column[b];
    if (c < 0) continue;
    const RigidBody& body = m.bodies[b];
    Eigen::Vector3d force = body.applied_force, torque = body.applied_torque;
    if (!load.empty()) {
      force += Eigen::Vector3d(load[6 * b], load[6 * b + 1], load[6 * b + 2]);
      torque += Eigen::Vector3d(load[6 * b + 3], load[6 * b + 4], load[6 * b + 5]);
    }
    const Eigen::Vector3d v = body.linear_velocity + (m.gravity + force / body.mass) * dt;
    Eigen::Vector3d w = gyroscopic ? gyroscopic_velocity(body, dt) : body.angular_velocity;
    if (!torque.isZero(0)) w += body.inverse_inertia_world() * torque * dt;
    for (int i = 0; i < 3; ++i) {
      v0[6 * c + i] = v[i];
      v0[6 * c + 3 + i] = w[i];
    }
  }
  // Constraint k's J into the cells and its target into R. The rows are taken by reference
  // (ConstraintRows is 640 bytes: copying it twice per constraint was a few percent of a 10-link
  // chain's step).
  const auto write_rows = [&](int k, const ConstraintRows& rows) {
    const Constraint& con = m.constraints[k];
    write_jacobian(rows, k, s);
    const int ca = column[con.body_a], cb = column[con.body_b];
    for (int r = 0; r < rows.rows; ++r) {
      const double* j = rows.jacobian.data() + 12 * r;
      double jv = 0;  // J (V0 + W F dt)
      for (int x = 0; x < 6; ++x) {
        if (ca >= 0) jv += j[x] * v0[6 * ca + x];
        if (cb >= 0) jv += j[6 + x] * v0[6 * cb + x];
      }
      const double cv = rows.c[r];
      const int i = s->blocks[k].position + r;
      double target = -options.baumgarte * cv / dt;
      if (!is_equality(con.type) && cv >= 0) target = -cv / dt;  // speculative: close the gap, not cross
      if (!predicted.empty() && is_equality(con.type) && con.type != ConstraintType::dof_drive) {
        // c(q0 + dt V) = c0 + dt J V + (dt^2 / 2) V^T c'' V + O(dt^3): the curvature term, from
        // the current velocities, asks J V1 = -(dt / 2) V^T c'' V, so that the chord q0 -> q1 is
        // tangent at its midpoint (a particle on a circle then keeps |x| and |v| exactly).
        const RigidBody &a = m.bodies[con.body_a], &b = m.bodies[con.body_b];
        double jv_now = 0;
        for (int x = 0; x < 3; ++x)
          jv_now += j[x] * a.linear_velocity[x] + j[3 + x] * a.angular_velocity[x] + j[6 + x] * b.linear_velocity[x] +
                    j[9 + x] * b.angular_velocity[x];
        target -= (predicted[i] - cv - dt * jv_now) / dt;
      }
      s->rhs[i] = target - jv;
    }
  };
  for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
    const Constraint& con = m.constraints[k];
    // (a dof row's evaluation is not kept by the projection, which skips it: acts_on_a_dof)
    if (known.empty() || acts_on_a_dof(con.type))
      write_rows(k, evaluate(con, m.bodies[con.body_a], m.bodies[con.body_b], fits ? fits->constraint(m, k) : nullptr));
    else write_rows(k, known[k]);
  }
  std::fill(s->compliance.begin(), s->compliance.end(), options.compliance);
}

// The dof_drive and dof_motor rows' targets, softness and bounds (joint_dynamics) over what
// write_velocity_system wrote (their c is 0, so R = -J (V0 + W F dt)). A compliance C is absolute:
// eps_i = C / H_ii, at most kInertCompliance (an inert row: its impulse ~1e-12 of a rigid one's).
void write_dof_rows(const Mechanism& m, std::span<const DofRow> rows, System* s) {
  constexpr double kInertCompliance = 1e12;
  for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
    const ConstraintType type = m.constraints[k].type;
    if (!acts_on_a_dof(type)) continue;
    const int i = s->blocks[k].position;
    const DofRow& row = rows[k];
    s->rhs[i] += row.target;
    if (row.compliance > 0) s->compliance[i] = std::min(row.compliance / row_diagonal(*s, k, 0), kInertCompliance);
    if (type == ConstraintType::dof_motor) {
      s->lower[i] = row.lower;
      s->upper[i] = row.upper;
    }
  }
}

// The medium's wrench on every moving body (fluid.h), onto `load` (6 per body).
void add_fluid_loads(const Mechanism& m, std::span<double> load) {
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    Eigen::Vector3d force, torque;
    fluid_wrench(m.bodies[b], m.fluid, &force, &torque);
    for (int x = 0; x < 3; ++x) {
      load[6 * b + x] += force[x];
      load[6 * b + 3 + x] += torque[x];
    }
  }
}

// q <- exp(dtheta) q, dtheta a world-frame rotation vector (left product: world frame; the right
// product would rotate about the body-frame axis, the same only where the two coincide, as on
// planar scenes), then normalized.
void rotate(RigidBody& b, const Eigen::Vector3d& dtheta) {
  const double angle = dtheta.norm();
  if (angle > 0) b.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, dtheta / angle)) * b.orientation).normalized();
}

}  // namespace

bool equality_only(const Mechanism& m) { return m.first_inequality() < 0 && !has_shapes(m); }

void use_own_factor_projection(StepOptions* options) {
  options->post_stabilize_refactor_on_stall = false;
  options->contacts.refactor_projection = false;
}

int post_stabilize_iterations(const StepOptions& options) {
  if (options.post_stabilize != StepOptions::kAutoPostStabilize) return options.post_stabilize;
  const bool factors = options.solver.kind == SolverKind::ldl_pgs || options.solver.kind == SolverKind::direct;
  return factors ? 30 : 0;
}

System build_system(const Mechanism& m, const StepOptions& options) {
  const std::vector<int> column = body_columns(m);
  System s = system_structure(m, column);
  std::vector<double> v0(6 * static_cast<size_t>(s.num_columns));
  // the joint dynamics at zero controls
  std::vector<double> load(6 * m.bodies.size(), 0.0), controls(m.actuators.size(), 0.0);
  std::vector<DofState> states(m.dofs.size());
  std::vector<DofRow> rows(m.constraints.size());
  joint_dynamics(m, controls, m.timestep, {}, states, load, rows);
  if (m.fluid.active()) add_fluid_loads(m, load);
  write_velocity_system(m, options, column, load, {}, {}, nullptr, v0, &s);
  write_dof_rows(m, rows, &s);
  return s;
}

Simulation::Simulation(Mechanism mechanism, const StepOptions& options)
    : mechanism_(std::move(mechanism)),
      options_(options),
      column_(body_columns(mechanism_)),
      system_(system_structure(mechanism_, column_)),
      solver_(system_, options.solver),
      lambda_(mechanism_.num_rows(), 0.0),
      dv_(6 * static_cast<size_t>(mechanism_.num_dynamic_bodies()), 0.0),
      v0_(dv_.size(), 0.0),
      mu_(lambda_.size(), 0.0),
      predicted_(lambda_.size(), 0.0),
      evaluated_(mechanism_.constraints.size()),
      load_(6 * mechanism_.bodies.size(), 0.0),
      saved_position_(mechanism_.bodies.size()),
      saved_orientation_(mechanism_.bodies.size()),
      joint_blocks_(static_cast<int>(mechanism_.constraints.size())),
      jointed_(mechanism_.bodies.size(), 0),
      carrying_(mechanism_.bodies.size(), 0),
      controls_(mechanism_.actuators.size(), 0.0),
      dof_states_(mechanism_.dofs.size()),
      dof_rows_(mechanism_.constraints.size()),
      dof_rates_(mechanism_.dofs.size(), std::numeric_limits<double>::quiet_NaN()),
      chain_fits_(mechanism_) {
  for (const Constraint& c : mechanism_.constraints)
    if (is_equality(c.type)) jointed_[c.body_a] = jointed_[c.body_b] = 1;
  if (has_shapes(mechanism_)) {
    if (options.solver.kind == SolverKind::direct) {
      const auto shaped = std::find_if(mechanism_.bodies.begin(), mechanism_.bodies.end(),
                                       [](const RigidBody& b) { return !b.shapes.empty(); });
      throw InputError("the direct solver takes no contacts: " +
                       body_label(mechanism_, static_cast<int>(shaped - mechanism_.bodies.begin())) +
                       " has shapes (use ldl-pgs)");
    }
    collision_ = std::make_unique<CollisionWorld>(mechanism_);
  }
  options_.post_stabilize = post_stabilize_iterations(options);
  if (options_.post_stabilize < 0 || options.post_stabilize_sweeps < 1 || !(options.post_stabilize_tolerance >= 0))
    throw InputError("post-stabilization: iterations >= 0, sweeps >= 1 and a tolerance >= 0 are required");
  if (!(options.contacts.margin >= 0 && options.contacts.margin <= 1))
    throw InputError("contacts: the margin must be in [0, 1] m, not " + std::to_string(options.contacts.margin));
  make_projector();
}

void Simulation::make_projector() {
  if (options_.post_stabilize > 0 && !solver_.symbolic()) {
    // pgs and block-gs have no factor: the projection gets one of its own, the hybrid on
    // inequality rows (contacts among them), exact otherwise.
    SolverOptions o = options_.solver;
    o.kind = equality_only(mechanism_) ? SolverKind::direct : SolverKind::ldl_pgs;
    projector_ = std::make_unique<Solver>(system_, o);
  }
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::velocity_system() {
  if (options_.curvature_target) {
    // c at the pose the current velocities reach in dt (positions only; restored after)
    save_pose();
    const double dt = mechanism_.timestep;
    for (RigidBody& b : mechanism_.bodies) {
      if (b.is_static) continue;
      b.position += b.linear_velocity * dt;
      rotate(b, b.angular_velocity * dt);
    }
    for (int k = 0; k < static_cast<int>(mechanism_.constraints.size()); ++k) {
      const Constraint& con = mechanism_.constraints[k];
      const ConstraintRows rows =
          evaluate(con, mechanism_.bodies[con.body_a], mechanism_.bodies[con.body_b], chain_fits_.constraint(mechanism_, k));
      for (int r = 0; r < rows.rows; ++r) predicted_[system_.blocks[k].position + r] = rows.c[r];
    }
    restore_pose();
  }
  // The last post-stabilization evaluated every constraint at this very pose (nothing moved it
  // since): its rows are this step's, one evaluation saved per step.
  write_velocity_system(mechanism_, options_, column_, load_,
                        options_.curvature_target ? predicted_ : std::span<const double>(),
                        evaluated_valid_ ? evaluated_ : std::span<const ConstraintRows>(), &chain_fits_, v0_, &system_);
  write_dof_rows(mechanism_, dof_rows_, &system_);
  contact_rows(/*velocity=*/true, /*with_jacobian=*/true);
}

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

// This step's contact points, matched with the last step's, as two blocks each past the
// constraints' (normal: impulse >= 0; friction: bounded by the normal impulse), warm-started with
// the matched impulses. A contact pushing for ContactOptions::factor_after steps in a row joins
// ldl-pgs's LDL block with its normal row; those come first, so that a repeated set of factored
// contacts is the same blocks and its symbolic phase is reused (solver.h).
void Simulation::detect_contacts() {
  const ContactOptions& o = options_.contacts;
  collision_->detect(mechanism_, o.margin, mechanism_.timestep, &points_);
  std::swap(contacts_, previous_contacts_);
  body_rotations(mechanism_, &rotations_);
  make_contacts(mechanism_, rotations_, points_, previous_contacts_, o.match_distance, &contact_keys_, &contacts_);
  mark_factored_contacts();
  order_factored_first();
  system_.truncate(joint_blocks_);
  for (const Contact& c : contacts_) {
    const int normal = system_.add_block(1, column_[c.body_a], column_[c.body_b]);
    system_.set_bounds(normal, 0, kUnbounded);
    system_.blocks[normal].factored = c.factored;
    const int friction = system_.add_block(2, column_[c.body_a], column_[c.body_b]);
    system_.set_friction(friction, system_.blocks[normal].position, c.friction, o.friction_pyramid);
  }
  const size_t rows = system_.num_rows;
  lambda_.resize(rows);
  mu_.resize(rows);
  predicted_.resize(rows);
  for (size_t i = 0; i < contacts_.size(); ++i) {
    const int first = system_.blocks[joint_blocks_ + 2 * i].position;
    for (int r = 0; r < 3; ++r) lambda_[first + r] = contacts_[i].impulse[r];
  }
}

// Which contacts ldl-pgs factors this step (ContactOptions: factor_after, factor_jointed,
// factor_mass_ratio). carrying_[b]: body b touches a dynamic body factor_mass_ratio times its mass.
void Simulation::mark_factored_contacts() {
  const ContactOptions& o = options_.contacts;
  const bool factoring = options_.solver.kind == SolverKind::ldl_pgs && o.factor_after > 0;
  std::fill(carrying_.begin(), carrying_.end(), char{o.factor_mass_ratio <= 0});
  if (factoring && o.factor_mass_ratio > 0)
    for (const Contact& c : contacts_) {
      const RigidBody &a = mechanism_.bodies[c.body_a], &b = mechanism_.bodies[c.body_b];
      if (a.is_static || b.is_static) continue;
      if (b.mass >= o.factor_mass_ratio * a.mass) carrying_[c.body_a] = 1;
      if (a.mass >= o.factor_mass_ratio * b.mass) carrying_[c.body_b] = 1;
    }
  for (Contact& c : contacts_)
    c.factored = factoring && c.pushing_steps >= o.factor_after &&
                 (o.factor_jointed || !(jointed_[c.body_a] || jointed_[c.body_b])) &&
                 (carrying_[c.body_a] || carrying_[c.body_b]);
}

// Factored contacts first, in the order of their bodies, so that the same set of touching pairs
// is the same blocks whatever order the detector found them in; the rest in the detector's order.
// The permutation is sorted as small keys and applied through previous_contacts_, no longer
// needed once matched (std::sort on a total order: stable_sort would allocate every step).
void Simulation::order_factored_first() {
  const int n = static_cast<int>(contacts_.size());
  bool any_factored = false;
  for (int i = 0; i < n; ++i) {
    contacts_[i].point_index = i;
    any_factored = any_factored || contacts_[i].factored;
  }
  if (!any_factored) return;  // (the detector's order already: no sort, no copy)
  contact_keys_.resize(n);
  for (int i = 0; i < n; ++i) {
    const Contact& c = contacts_[i];
    // (unfactored: after every body, in the detector's order)
    contact_keys_[i] = c.factored ? ContactKey{c.body_a, c.body_b, c.shape_a, c.shape_b, i} : ContactKey{INT_MAX, 0, 0, 0, i};
  }
  std::sort(contact_keys_.begin(), contact_keys_.end());
  previous_contacts_.resize(n);
  for (int i = 0; i < n; ++i) previous_contacts_[i] = contacts_[contact_keys_[i].index];
  std::swap(contacts_, previous_contacts_);
}

// The contacts' rows at the current pose into system_: J (with_jacobian: the velocity level, or
// a refactoring position level; otherwise the step's J_0 stays, as post_stabilize needs), and
// the right-hand side. Velocity level: the normal row
// asks J V1 >= target, target = the gap closed in one step when apart (speculative), else
// baumgarte (depth - slop) / dt within max_correction_speed, and at least -e v_n when approaching
// faster than the restitution threshold; friction rows ask J V1 = 0 within their bound.
// Position level: (n . d + slop) >= 0 for the normal row; friction rows take no part (mu = 0).
// Returns the largest violation n . d + slop < 0 (m).
double Simulation::contact_rows(bool velocity, bool with_jacobian) {
  const ContactOptions& o = options_.contacts;
  const double dt = mechanism_.timestep;
  // The position level's rows of contact kn: its separation c and a slop, no friction.
  const auto position_row = [&](int kn, double c) {
    system_.blocks[kn + 1].friction = 0;
    const int in = system_.blocks[kn].position, if0 = system_.blocks[kn + 1].position;
    system_.rhs[in] = -(c + o.slop);
    system_.rhs[if0] = system_.rhs[if0 + 1] = 0;
    return -(c + o.slop);
  };
  double worst = 0;
  body_rotations(mechanism_, &rotations_);
  for (size_t i = 0; i < contacts_.size(); ++i) {
    const Contact& con = contacts_[i];
    const RigidBody &a = mechanism_.bodies[con.body_a], &b = mechanism_.bodies[con.body_b];
    const Eigen::Matrix3d &ra = rotations_[con.body_a], &rb = rotations_[con.body_b];
    const int kn = joint_blocks_ + 2 * static_cast<int>(i), kf = kn + 1;
    const int in = system_.blocks[kn].position, if0 = system_.blocks[kf].position;
    system_.blocks[kn].regularization = con.factored ? o.regularization : 0;
    if (con.factored) system_.compliance[in] = o.compliance;
    if (!velocity && !with_jacobian) {  // (the normal row's c is all it needs)
      worst = std::max(worst, position_row(kn, separation(con, a, ra, b, rb)));
      continue;
    }
    ContactRows rows;
    evaluate(con, a, ra, b, rb, &rows);
    const int ca = column_[con.body_a], cb = column_[con.body_b];
    for (int r = 0; r < 3 && with_jacobian; ++r) {
      const double* j = rows.jacobian.data() + 12 * r;
      const int k = r == 0 ? kn : kf, row = r == 0 ? 0 : r - 1;
      std::copy(j, j + 6, system_.cell_a(k) + 6 * row);
      std::copy(j + 6, j + 12, system_.cell_b(k) + 6 * row);
    }
    if (!velocity) {
      worst = std::max(worst, position_row(kn, rows.c[0]));
      continue;
    }
    system_.blocks[kf].friction = con.friction;
    // J V for the velocities before (now: a's and b's v and w) and after the free motion (v0_)
    const auto jv = [&](int r, const double* va, const double* vb) {
      const double* j = rows.jacobian.data() + 12 * r;
      double s = 0;
      for (int x = 0; x < 6; ++x) {
        if (va) s += j[x] * va[x];
        if (vb) s += j[6 + x] * vb[x];
      }
      return s;
    };
    const double* free_a = ca >= 0 ? v0_.data() + 6 * ca : nullptr;
    const double* free_b = cb >= 0 ? v0_.data() + 6 * cb : nullptr;
    const double gap = rows.c[0];
    double target = 0;
    if (con.factored) {
      // J V1 = 0: in the LDL block the targets must be consistent (in J's range), since the part
      // of them outside it (a clamp, a threshold, a slop) is divided by the compliance alone;
      // the post-stabilization corrects the depth (papers/physics.md, "Contacts in the factor").
      target = 0;
    } else {
      target = gap > 0 ? -gap / dt : std::min(o.baumgarte * std::max(0.0, -gap - o.slop) / dt, o.max_correction_speed);
      const double now_a[6] = {a.linear_velocity.x(),  a.linear_velocity.y(),  a.linear_velocity.z(),
                               a.angular_velocity.x(), a.angular_velocity.y(), a.angular_velocity.z()};
      const double now_b[6] = {b.linear_velocity.x(),  b.linear_velocity.y(),  b.linear_velocity.z(),
                               b.angular_velocity.x(), b.angular_velocity.y(), b.angular_velocity.z()};
      const double approach = jv(0, ca >= 0 ? now_a : nullptr, cb >= 0 ? now_b : nullptr);
      if (approach < -o.restitution_threshold) target = std::max(target, -con.restitution * approach);
    }
    system_.rhs[in] = target - jv(0, free_a, free_b);
    system_.rhs[if0] = -jv(1, free_a, free_b);
    system_.rhs[if0 + 1] = -jv(2, free_a, free_b);
  }
  return worst;
}

void Simulation::keep_contact_impulses() {
  for (size_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    const int first = system_.blocks[joint_blocks_ + 2 * i].position;
    for (int r = 0; r < 3; ++r) c.impulse[r] = lambda_[first + r];
    c.pushing_steps = c.impulse[0] > 0 ? c.pushing_steps + 1 : 0;
  }
}

double Simulation::penetration_max() const {
  double worst = 0;
  for (const Contact& c : contacts_)
    worst = std::max(worst, -separation(c, mechanism_.bodies[c.body_a], mechanism_.bodies[c.body_b]));
  return worst;
}

void Simulation::add_shape(int body, const Shape& shape) {
  RigidBody& b = writable(body, "add_shape", false);
  const std::string problem = shape_problem(shape, b.is_static);
  if (!problem.empty()) throw InputError("add_shape: body " + std::to_string(body) + " (" + b.name + "): " + problem);
  if (options_.solver.kind == SolverKind::direct)
    throw InputError("add_shape: the direct solver takes no contacts (use ldl-pgs)");
  b.shapes.push_back(shape);
  if (shape.type == ShapeType::plane) b.shapes.back().normal.normalize();
  collision_ = std::make_unique<CollisionWorld>(mechanism_);
  make_projector();  // (an exact projector takes no contacts)
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

StepReport Simulation::step() {
  using Clock = std::chrono::steady_clock;
  const auto us = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  Mechanism& m = mechanism_;
  const double dt = m.timestep;
  StepReport report;
  const auto start = Clock::now();
  if (collision_) {
    detect_contacts();
    report.contacts = static_cast<int>(contacts_.size());
    report.contact_us = us(start, Clock::now());
  }
  if (!m.dofs.empty() || !m.actuators.empty())
    joint_dynamics(m, controls_, dt, dof_rates_, dof_states_, load_, dof_rows_, &chain_fits_);
  if (m.fluid.active()) add_fluid_loads(m, load_);
  velocity_system();
  const auto solve_start = Clock::now();
  report.result = solver_.solve(system_, lambda_, dv_,
                                contacts_.empty() ? std::nullopt : std::optional(options_.contacts.schedule));
  const auto solve_end = Clock::now();
  report.solve_us = us(solve_start, solve_end);
  keep_contact_impulses();
  keep_dof_rates();
  if (options_.diagnostics) report.velocity_residual = velocity_residual(system_, lambda_, dv_);
  const bool gyroscopic = implicit_gyroscopic(m, options_);
  int c = 0;
  for (RigidBody& b : m.bodies) {
    if (b.is_static) continue;
    // V1 = V0 + W F dt + W J^T lambda
    const double* v0 = v0_.data() + 6 * c;
    const double* dv = dv_.data() + 6 * c;
    ++c;
    b.linear_velocity = Eigen::Vector3d(v0[0] + dv[0], v0[1] + dv[1], v0[2] + dv[2]);
    b.angular_velocity = Eigen::Vector3d(v0[3] + dv[3], v0[4] + dv[4], v0[5] + dv[5]);
    b.position += b.linear_velocity * dt;
    // q <- exp(w dt) q (world-frame w), renormalized. Unless the free motion took the gyroscopic
    // term implicitly, the body's angular momentum I w is kept through the rotation
    // (w <- I_new^-1 I_old w): without it a free asymmetric body's angular momentum would drift,
    // since semi-implicit Euler drops the gyroscopic term w x I w. (I_world w = R (I .* (R^T w))
    // by quaternion rotations: no rotation matrix is built)
    if (gyroscopic) {
      rotate(b, b.angular_velocity * dt);
      continue;
    }
    const Eigen::Vector3d momentum = b.orientation * b.inertia.cwiseProduct(b.orientation.conjugate() * b.angular_velocity);
    rotate(b, b.angular_velocity * dt);
    b.angular_velocity = b.orientation * (b.orientation.conjugate() * momentum).cwiseQuotient(b.inertia);
  }
  evaluated_valid_ = false;  // the pose moved
  std::fill(load_.begin(), load_.end(), 0.0);
  if (options_.post_stabilize > 0) {
    // A failed factorization (report.result) leaves nothing to project with: skipped, counted.
    if (!report.result.ok() || !post_stabilize(&report)) ++post_stabilize_skipped_;
    report.post_stabilize_us = us(solve_end, Clock::now());
  }
  time_ += dt;
  report.step_us = us(start, Clock::now());
  if (options_.diagnostics) {
    report.error = constraint_error(m, &chain_fits_);
    report.energy = total_energy(m);
    report.penetration_max_m = penetration_max();
  }
  return report;
}

// --- the state and force API -----------------------------------------------------------------

RigidBody& Simulation::writable(int body, const char* what, bool dynamic_only) {
  if (body < 0 || body >= static_cast<int>(mechanism_.bodies.size()))
    throw InputError(std::string(what) + ": body " + std::to_string(body) + " out of range 0.." +
                     std::to_string(static_cast<int>(mechanism_.bodies.size()) - 1));
  RigidBody& b = mechanism_.bodies[body];
  if (dynamic_only && b.is_static)
    throw InputError(std::string(what) + ": body " + std::to_string(body) + " (" + b.name + ") is static");
  return b;
}

namespace {
// Within MechanismRanges (physics/mechanism.h), as a scene file's values: what a caller sets is
// what a scene may hold, so that nothing computed from it overflows.
void require_within(const Eigen::Vector3d& v, double max, const char* what, int body, const char* quantity,
                    const char* unit) {
  // (the label is built only to name a fault: the setters run between steps, allocation-free)
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(v[k]) <= max)) check_range(what, "body " + std::to_string(body), quantity, v[k], 0, max, unit);
}

// A unit quaternion within 1e-6 (the caller normalizes it).
void require_unit(const Eigen::Quaterniond& q, const char* what, int body) {
  const double norm = q.norm();
  if (!std::isfinite(norm) || std::abs(norm - 1) > 1e-6)
    throw InputError(std::string(what) + ": body " + std::to_string(body) + ": quaternion norm " +
                     std::to_string(norm) + " is not 1 (within 1e-6)");
}
}  // namespace

void Simulation::set_position(int body, const Eigen::Vector3d& position) {
  forget_dof_rates();
  evaluated_valid_ = false;  // (even if refused below: nothing is lost but one evaluation)
  RigidBody& b = writable(body, "set_position", false);
  require_within(position, MechanismRanges::coordinate_max, "set_position", body, "position", "m");
  b.position = position;
}

void Simulation::set_orientation(int body, const Eigen::Quaterniond& orientation) {
  forget_dof_rates();
  evaluated_valid_ = false;  // (even if refused below: nothing is lost but one evaluation)
  RigidBody& b = writable(body, "set_orientation", false);
  require_unit(orientation, "set_orientation", body);
  b.orientation = orientation.normalized();
}

void Simulation::set_linear_velocity(int body, const Eigen::Vector3d& velocity) {
  forget_dof_rates();
  RigidBody& b = writable(body, "set_linear_velocity", true);
  require_within(velocity, MechanismRanges::velocity_max, "set_linear_velocity", body, "velocity", "m/s");
  b.linear_velocity = velocity;
}

void Simulation::set_angular_velocity(int body, const Eigen::Vector3d& velocity) {
  forget_dof_rates();
  RigidBody& b = writable(body, "set_angular_velocity", true);
  require_within(velocity, MechanismRanges::velocity_max, "set_angular_velocity", body, "velocity", "rad/s");
  b.angular_velocity = velocity;
}

namespace {
void require_size(size_t got, size_t per_body, size_t bodies, const char* what) {
  if (got != per_body * bodies)
    throw InputError(std::string(what) + ": " + std::to_string(got) + " values for " + std::to_string(bodies) +
                     " bodies (" + std::to_string(per_body) + " per body)");
}
}  // namespace

void Simulation::get_positions(std::span<double> out) const {
  require_size(out.size(), 3, mechanism_.bodies.size(), "get_positions");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b)
    for (int i = 0; i < 3; ++i) out[3 * b + i] = mechanism_.bodies[b].position[i];
}

void Simulation::get_orientations(std::span<double> out) const {
  require_size(out.size(), 4, mechanism_.bodies.size(), "get_orientations");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) {
    const Eigen::Quaterniond& q = mechanism_.bodies[b].orientation;
    out[4 * b] = q.w();
    out[4 * b + 1] = q.x();
    out[4 * b + 2] = q.y();
    out[4 * b + 3] = q.z();
  }
}

void Simulation::get_velocities(std::span<double> out) const {
  require_size(out.size(), 6, mechanism_.bodies.size(), "get_velocities");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b)
    for (int i = 0; i < 3; ++i) {
      out[6 * b + i] = mechanism_.bodies[b].linear_velocity[i];
      out[6 * b + 3 + i] = mechanism_.bodies[b].angular_velocity[i];
    }
}

// The array setters check everything before writing anything: a refused call changes nothing.
void Simulation::set_positions(std::span<const double> in) {
  forget_dof_rates();
  evaluated_valid_ = false;  // (even if refused below: nothing is lost but one evaluation)
  require_size(in.size(), 3, mechanism_.bodies.size(), "set_positions");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b)
    require_within(Eigen::Vector3d(in[3 * b], in[3 * b + 1], in[3 * b + 2]), MechanismRanges::coordinate_max, "set_positions",
                   static_cast<int>(b), "position", "m");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b)
    mechanism_.bodies[b].position = Eigen::Vector3d(in[3 * b], in[3 * b + 1], in[3 * b + 2]);
}

void Simulation::set_orientations(std::span<const double> in) {
  forget_dof_rates();
  evaluated_valid_ = false;  // (even if refused below: nothing is lost but one evaluation)
  require_size(in.size(), 4, mechanism_.bodies.size(), "set_orientations");
  const auto at = [&](size_t b) { return Eigen::Quaterniond(in[4 * b], in[4 * b + 1], in[4 * b + 2], in[4 * b + 3]); };
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) require_unit(at(b), "set_orientations", static_cast<int>(b));
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) mechanism_.bodies[b].orientation = at(b).normalized();
}

void Simulation::set_velocities(std::span<const double> in) {
  forget_dof_rates();
  require_size(in.size(), 6, mechanism_.bodies.size(), "set_velocities");
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) {
    const Eigen::Vector3d v(in[6 * b], in[6 * b + 1], in[6 * b + 2]), w(in[6 * b + 3], in[6 * b + 4], in[6 * b + 5]);
    require_within(v, MechanismRanges::velocity_max, "set_velocities", static_cast<int>(b), "linear velocity", "m/s");
    require_within(w, MechanismRanges::velocity_max, "set_velocities", static_cast<int>(b), "angular velocity", "rad/s");
    if (mechanism_.bodies[b].is_static && !(v.isZero(0) && w.isZero(0)))
      throw InputError("set_velocities: body " + std::to_string(b) + " (" + mechanism_.bodies[b].name +
                       ") is static: its velocity must be zero");
  }
  for (size_t b = 0; b < mechanism_.bodies.size(); ++b) {
    if (mechanism_.bodies[b].is_static) continue;
    mechanism_.bodies[b].linear_velocity = Eigen::Vector3d(in[6 * b], in[6 * b + 1], in[6 * b + 2]);
    mechanism_.bodies[b].angular_velocity = Eigen::Vector3d(in[6 * b + 3], in[6 * b + 4], in[6 * b + 5]);
  }
}

void Simulation::apply_force(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  writable(body, "apply_force", true);
  require_within(force, MechanismRanges::load_max, "apply_force", body, "force", "N");
  require_within(torque, MechanismRanges::load_max, "apply_force", body, "torque", "N m");
  for (int i = 0; i < 3; ++i) {
    load_[6 * body + i] += force[i];
    load_[6 * body + 3 + i] += torque[i];
  }
}

void Simulation::apply_force_at(int body, const Eigen::Vector3d& force, const Eigen::Vector3d& point) {
  const RigidBody& b = writable(body, "apply_force_at", true);
  require_within(point, MechanismRanges::coordinate_max, "apply_force_at", body, "point", "m");
  require_within(force, MechanismRanges::load_max, "apply_force_at", body, "force", "N");
  apply_force(body, force, (point - b.position).cross(force));
}

void Simulation::set_gravity(const Eigen::Vector3d& gravity) {
  for (int k = 0; k < 3; ++k) check_range("set_gravity", "", "component", gravity[k], 0, MechanismRanges::velocity_max, "m/s^2");
  mechanism_.gravity = gravity;
}

void Simulation::set_timestep(double timestep) {
  check_range("set_timestep", "", "timestep", timestep, MechanismRanges::timestep_min, MechanismRanges::timestep_max, "s");
  mechanism_.timestep = timestep;
}

// A state written through the API: the armature measures from the pose's own rates again.
void Simulation::forget_dof_rates() { std::fill(dof_rates_.begin(), dof_rates_.end(), std::numeric_limits<double>::quiet_NaN()); }

// Each driven dof's rate after the solve, J_drive V1 along its row of this step (joint_dynamics:
// the armature's q_dot0 of the next).
void Simulation::keep_dof_rates() {
  for (size_t d = 0; d < mechanism_.dofs.size(); ++d) {
    const int k = mechanism_.dofs[d].drive;
    if (k < 0) continue;
    const RowBlock& b = system_.blocks[k];
    double rate = 0;
    for (int x = 0; x < 6; ++x) {
      if (b.column_a >= 0) rate += system_.cell_a(k)[x] * (v0_[6 * b.column_a + x] + dv_[6 * b.column_a + x]);
      if (b.column_b >= 0) rate += system_.cell_b(k)[x] * (v0_[6 * b.column_b + x] + dv_[6 * b.column_b + x]);
    }
    dof_rates_[d] = rate;
  }
}

void Simulation::set_controls(std::span<const double> controls) {
  check_controls(mechanism_.actuators, controls);
  std::copy(controls.begin(), controls.end(), controls_.begin());
}

}  // namespace ldlpgs
