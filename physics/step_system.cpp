// The step's prepare stage: the joint dynamics and loads, then W, J, R and the compliance of the
// velocity step (and build_system, the same for tests and export).
#include "ldlpgs/physics/step_stages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <type_traits>

#include "ldlpgs/physics/chain_fits.h"

namespace ldlpgs {
namespace step_stages {

// column[b] = the velocity block of body b, -1 for a static body (size num_bodies)
std::vector<int> body_columns(const Mechanism& m) {
  std::vector<int> column(m.bodies.size(), -1);
  int next = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b)
    if (!m.bodies[b].is_static) column[b] = next++;
  return column;
}

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

}  // namespace step_stages

using namespace step_stages;

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

// Joint dynamics and actuators (their rows' targets and the explicit forces), the medium's
// loads, then the velocity system at the current pose, the contacts' rows with it.
void Simulation::prepare_velocity_step() {
  Mechanism& m = mechanism_;
  if (!m.dofs.empty() || !m.actuators.empty())
    joint_dynamics(m, controls_, m.timestep, dof_rates_, dof_states_, load_, dof_rows_, &chain_fits_);
  if (m.fluid.active()) add_fluid_loads(m, load_);
  velocity_system();
}

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

// A state written through the API: the armature measures from the pose's own rates again.
void Simulation::forget_dof_rates() { std::fill(dof_rates_.begin(), dof_rates_.end(), std::numeric_limits<double>::quiet_NaN()); }
}  // namespace ldlpgs
