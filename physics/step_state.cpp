// The state between steps: bodies' poses, velocities, forces, gravity, timestep and controls,
// each write checked in every build (step.h).
#include "ldlpgs/physics/step_stages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Geometry>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

using namespace step_stages;

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

void Simulation::set_controls(std::span<const double> controls) {
  check_controls(mechanism_.actuators, controls);
  std::copy(controls.begin(), controls.end(), controls_.begin());
}
}  // namespace ldlpgs
