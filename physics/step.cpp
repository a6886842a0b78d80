// The velocity step of the talk (semi-implicit Euler) around the constraint solver.
#include "physics/step.h"

#include <cassert>
#include <cmath>

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

ConstraintError constraint_error(const Mechanism& m) {
  ConstraintError e;
  double sum_p = 0, sum_a = 0;
  int n_p = 0, n_a = 0;
  for (const Constraint& c : m.constraints) {
    const ConstraintRows rows = evaluate(c, m.bodies[c.body_a], m.bodies[c.body_b]);
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

System build_system(const Mechanism& m, const StepOptions& options) {
  const std::vector<int> column = body_columns(m);
  const double dt = m.timestep;
  System s;
  s.num_columns = m.num_dynamic_bodies();
  s.inverse_mass.assign(36 * static_cast<size_t>(s.num_columns), 0.0);
  // V0 + W F dt per column (gravity is the only external force)
  std::vector<double> v0(6 * static_cast<size_t>(s.num_columns));
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const int c = column[b];
    if (c < 0) continue;
    const RigidBody& body = m.bodies[b];
    // W_b = blockdiag(I3 / m, R diag(1/I) R^T)
    double* w = s.inverse_mass.data() + 36 * c;
    const Eigen::Matrix3d inv_i = body.inverse_inertia_world();
    for (int i = 0; i < 3; ++i) {
      w[6 * i + i] = 1 / body.mass;
      for (int j = 0; j < 3; ++j) w[6 * (3 + i) + 3 + j] = inv_i(i, j);
    }
    const Eigen::Vector3d v = body.linear_velocity + m.gravity * dt;
    for (int i = 0; i < 3; ++i) {
      v0[6 * c + i] = v[i];
      v0[6 * c + 3 + i] = body.angular_velocity[i];
    }
  }
  for (const Constraint& con : m.constraints) {
    const ConstraintRows rows = evaluate(con, m.bodies[con.body_a], m.bodies[con.body_b]);
    const int ca = column[con.body_a], cb = column[con.body_b];
    const int k = s.add_block(rows.rows, ca, cb);
    if (!is_equality(con.type)) s.set_bounds(k, 0, kUnbounded);
    for (int r = 0; r < rows.rows; ++r) {
      const double* j = rows.jacobian.data() + 12 * r;
      std::copy(j, j + 6, s.cell_a(k) + 6 * r);
      std::copy(j + 6, j + 12, s.cell_b(k) + 6 * r);
      double jv = 0;  // J (V0 + W F dt)
      for (int x = 0; x < 6; ++x) {
        if (ca >= 0) jv += j[x] * v0[6 * ca + x];
        if (cb >= 0) jv += j[6 + x] * v0[6 * cb + x];
      }
      const double cv = rows.c[r];
      double target = -options.baumgarte * cv / dt;
      if (!is_equality(con.type) && cv >= 0) target = -cv / dt;  // speculative: close the gap, not cross
      s.rhs[s.blocks[k].position + r] = target - jv;
    }
  }
  s.set_compliance(options.compliance);
  return s;
}

Simulation::Simulation(Mechanism mechanism, const StepOptions& options)
    : mechanism_(std::move(mechanism)),
      options_(options),
      solver_(build_system(mechanism_, options), options.solver),
      lambda_(mechanism_.num_rows(), 0.0),
      dv_(6 * static_cast<size_t>(mechanism_.num_dynamic_bodies()), 0.0) {}

StepReport Simulation::step() {
  Mechanism& m = mechanism_;
  const double dt = m.timestep;
  system_ = build_system(m, options_);
  StepReport report;
  const auto start = std::chrono::steady_clock::now();
  report.result = solver_.solve(system_, lambda_, dv_);
  report.solve_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  report.velocity_residual = velocity_residual(system_, lambda_, dv_);
  int c = 0;
  for (RigidBody& b : m.bodies) {
    if (b.is_static) continue;
    // V1 = V0 + W F dt + W J^T lambda
    b.linear_velocity += m.gravity * dt + Eigen::Vector3d(dv_[6 * c], dv_[6 * c + 1], dv_[6 * c + 2]);
    b.angular_velocity += Eigen::Vector3d(dv_[6 * c + 3], dv_[6 * c + 4], dv_[6 * c + 5]);
    ++c;
    b.position += b.linear_velocity * dt;
    // q <- exp(w dt) q (world-frame w), renormalized. The body's angular momentum I w is kept
    // through the rotation (w <- I_new^-1 I_old w): without it a free asymmetric body's angular
    // momentum would drift, since semi-implicit Euler drops the gyroscopic term w x I w.
    const Eigen::Vector3d momentum = b.inertia_world() * b.angular_velocity;
    const double angle = b.angular_velocity.norm() * dt;
    if (angle > 0)
      b.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, b.angular_velocity.normalized())) * b.orientation).normalized();
    b.angular_velocity = b.inverse_inertia_world() * momentum;
  }
  time_ += dt;
  report.error = constraint_error(m);
  report.energy = total_energy(m);
  return report;
}

}  // namespace ldlpgs
