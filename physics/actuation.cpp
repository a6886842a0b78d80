// MuJoCo's joint dynamics and actuators as loads and soft rows (the model: actuation.h).
#include "ldlpgs/physics/actuation.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ldlpgs/physics/chain_fits.h"
#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

namespace {

// The generalized force tau on a dof as loads on its two bodies: z^T tau, z its rate covector.
void add_generalized_force(const Constraint& coordinate, const DofState& state, double tau, std::span<double> load) {
  if (tau == 0) return;
  for (int x = 0; x < 6; ++x) {
    load[6 * static_cast<size_t>(coordinate.body_a) + x] += state.row[x] * tau;
    load[6 * static_cast<size_t>(coordinate.body_b) + x] += state.row[6 + x] * tau;
  }
}

// A soft term of a drive row, accumulated as (sum of 1/C, sum of target / C); resolved by
// finish_drive.
void add_to_drive(DofRow* row, double inverse_compliance, double target) {
  row->compliance += inverse_compliance;
  row->target += inverse_compliance * target;
}
// (nothing softened it, as with actuation off: the row is inert, C = infinity)
void finish_drive(DofRow* row) {
  if (row->compliance > 0) row->target /= row->compliance;
  row->compliance = row->compliance > 0 ? 1 / row->compliance : kUnbounded;
}

std::string actuator_label(std::span<const Actuator> actuators, size_t i) {
  return cat("actuator \"", printable(actuators[i].name, 80), "\" (", std::to_string(i), ")");
}

}  // namespace

DofState dof_state(const DofDynamics& dof, const std::vector<RigidBody>& bodies, const ChainFit* fit_given) {
  const Constraint& c = dof.coordinate;
  const RigidBody &a = bodies[c.body_a], &b = bodies[c.body_b];
  ChainFit own;
  const ChainFit& fit = chain_fit(c, a, b, fit_given, &own);
  Twist z;
  DofState s;
  s.q = chain_dof(*c.chain, fit, c.joint, &z) + dof.offset;
  chain_jacobian_row(*c.chain, z, a, b, s.row.data());
  const std::array<const Eigen::Vector3d*, 4> v = {&a.linear_velocity, &a.angular_velocity, &b.linear_velocity,
                                                   &b.angular_velocity};
  for (int k = 0; k < 4; ++k)
    for (int x = 0; x < 3; ++x) s.rate += s.row[3 * k + x] * (*v[k])[x];
  return s;
}

void check_controls(std::span<const Actuator> actuators, std::span<const double> controls) {
  if (controls.size() != actuators.size())
    throw InputError(cat("controls: ", std::to_string(controls.size()), " given, the model has ",
                         std::to_string(actuators.size()), " actuators"));
  for (size_t i = 0; i < actuators.size(); ++i) {
    const Actuator& a = actuators[i];
    const double u = controls[i];
    if (!std::isfinite(u)) throw InputError(cat("controls: ", actuator_label(actuators, i), ": not a finite number"));
    if (a.ctrl_limited && !(u >= a.ctrl_min && u <= a.ctrl_max))
      throw InputError(cat("controls: ", actuator_label(actuators, i), ": ", format_number(u), " outside its ctrlrange [",
                           format_number(a.ctrl_min), ", ", format_number(a.ctrl_max), "]"));
  }
}

namespace {

// Each dof's state, its spring's explicit force, and its drive row's armature and damping (the
// armature's q_dot0 the last solve's rate where there is one) and friction row's bounds.
void passive_terms(const Mechanism& m, double dt, std::span<const double> last_rates, ChainFits* fits,
                   std::span<DofState> states, std::span<DofRow> rows) {
  for (size_t d = 0; d < m.dofs.size(); ++d) {
    const DofDynamics& dof = m.dofs[d];
    DofState& s = states[d] = dof_state(dof, m.bodies, fits ? fits->dof(m, static_cast<int>(d)) : nullptr);
    s.force = -dof.stiffness * (s.q - dof.springref);
    if (dof.drive >= 0) {
      rows[dof.drive] = DofRow{0, 0, -kUnbounded, kUnbounded};
      const double inertial = dof.armature + dt * dof.damping;
      const bool last = !last_rates.empty() && std::isfinite(last_rates[d]);
      if (inertial > 0) add_to_drive(&rows[dof.drive], inertial, dof.armature * (last ? last_rates[d] : s.rate) / inertial);
    }
    if (dof.friction >= 0) rows[dof.friction] = DofRow{0, 0, -dof.frictionloss * dt, dof.frictionloss * dt};
  }
}

// Each actuator's force: its velocity term implicit (a motor row, or a term of the drive row),
// the rest explicit onto its dof's force.
void actuator_terms(const Mechanism& m, std::span<const double> controls, double dt, std::span<DofState> states,
                    std::span<DofRow> rows) {
  for (size_t i = 0; i < m.actuators.size() && m.actuation; ++i) {
    const Actuator& a = m.actuators[i];
    if (a.dof < 0) continue;  // kept for the controls' order only
    DofState& s = states[a.dof];
    const double c = a.gain * controls[i] + a.bias[0] + a.bias[1] * a.gear * s.q;
    if (a.bias[2] < 0 && a.gear != 0) {
      // the velocity term implicit: lambda = dt gear (c + bias2 gear q_dot1)
      const double inverse_compliance = -a.bias[2] * a.gear * a.gear * dt, target = c / (-a.bias[2] * a.gear);
      if (a.motor >= 0) {
        const double lo = dt * a.gear * a.force_min, hi = dt * a.gear * a.force_max;
        rows[a.motor] = DofRow{target, 1 / inverse_compliance, std::min(lo, hi), std::max(lo, hi)};
      } else {
        assert(m.dofs[a.dof].drive >= 0);
        add_to_drive(&rows[m.dofs[a.dof].drive], inverse_compliance, target);
      }
      continue;
    }
    double force = c + a.bias[2] * a.gear * s.rate;
    if (a.force_limited) force = std::clamp(force, a.force_min, a.force_max);
    s.force += a.gear * force;
  }
}

// The explicit force goes into the dof's drive row where it has one (lambda = dt tau - (q_dot1 -
// target) / C: the target moves by dt tau C), else onto the bodies; then the drive rows are
// resolved. The step is the same; but a rotor's force on a light link, V* = V0 + dt M^-1 z tau,
// would otherwise outrun every speculative limit before the armature row slows it
// (papers/physics.md, "MJCF models").
void explicit_forces(const Mechanism& m, double dt, std::span<const DofState> states, std::span<double> load,
                     std::span<DofRow> rows) {
  for (size_t d = 0; d < m.dofs.size(); ++d) {
    const DofDynamics& dof = m.dofs[d];
    if (dof.drive >= 0 && rows[dof.drive].compliance > 0) {
      rows[dof.drive].target += dt * states[d].force;  // (in the accumulated form: sum target / C)
    } else {
      add_generalized_force(dof.coordinate, states[d], states[d].force, load);
    }
    if (dof.drive >= 0) finish_drive(&rows[dof.drive]);
  }
}

}  // namespace

void joint_dynamics(const Mechanism& m, std::span<const double> controls, double dt,
                    std::span<const double> last_rates, std::span<DofState> states, std::span<double> load,
                    std::span<DofRow> rows, ChainFits* fits) {
  assert(states.size() == m.dofs.size() && rows.size() == m.constraints.size() &&
         controls.size() == m.actuators.size() && (last_rates.empty() || last_rates.size() == m.dofs.size()));
  passive_terms(m, dt, last_rates, fits, states, rows);
  actuator_terms(m, controls, dt, states, rows);
  explicit_forces(m, dt, states, load, rows);
}

}  // namespace ldlpgs
