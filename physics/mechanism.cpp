// A mechanism's bookkeeping and its two graphs (the talk's symbolic phase starts here).
#include "ldlpgs/physics/mechanism.h"

#include <cassert>
#include <cmath>
#include <utility>

#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

int Mechanism::find_body(std::string_view body_name) const {
  for (size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].name == body_name) return static_cast<int>(b);
  return -1;
}

int Mechanism::add_body(RigidBody body) {
  assert(body.is_static || (body.mass > 0 && body.inertia.minCoeff() > 0));
  bodies.push_back(std::move(body));
  return static_cast<int>(bodies.size()) - 1;
}

int Mechanism::add_constraint(Constraint constraint) {
  const int n = static_cast<int>(bodies.size());
  assert(constraint.body_a >= 0 && constraint.body_a < n && constraint.body_b >= 0 && constraint.body_b < n);
  assert(constraint.body_a != constraint.body_b);
  assert(!(bodies[constraint.body_a].is_static && bodies[constraint.body_b].is_static));
  static_cast<void>(n);
  constraints.push_back(std::move(constraint));
  return static_cast<int>(constraints.size()) - 1;
}

int Mechanism::num_rows() const {
  int rows = 0;
  for (const Constraint& c : constraints) rows += ldlpgs::num_rows(c);
  return rows;
}

int Mechanism::first_inequality() const {
  for (size_t c = 0; c < constraints.size(); ++c)
    if (!is_equality(constraints[c].type)) return static_cast<int>(c);
  return -1;
}

int Mechanism::num_dynamic_bodies() const {
  int n = 0;
  for (const RigidBody& b : bodies) n += b.is_static ? 0 : 1;
  return n;
}

namespace {
// Two distinct bodies of m (the builders below, like add_constraint, assert it).
[[maybe_unused]] bool body_pair(const Mechanism& m, int a, int b) {
  const int n = static_cast<int>(m.bodies.size());
  return a >= 0 && a < n && b >= 0 && b < n && a != b;
}
}  // namespace

Constraint Mechanism::ball(int a, int b, const Eigen::Vector3d& anchor) const {
  assert(body_pair(*this, a, b));
  return make_ball(a, bodies[a], b, bodies[b], anchor);
}
Constraint Mechanism::axial(ConstraintType type, int a, int b, const Eigen::Vector3d& anchor,
                            const Eigen::Vector3d& axis) const {
  assert(body_pair(*this, a, b));
  return make_axial(type, a, bodies[a], b, bodies[b], anchor, axis);
}
Constraint Mechanism::distance(ConstraintType type, int a, int b, const Eigen::Vector3d& anchor_on_a,
                               const Eigen::Vector3d& anchor_on_b, double length) const {
  assert(body_pair(*this, a, b));
  return make_distance(type, a, bodies[a], b, bodies[b], anchor_on_a, anchor_on_b, length);
}
Constraint Mechanism::angular_limit(int a, int b, const Eigen::Vector3d& axis, double min, double max) const {
  assert(body_pair(*this, a, b));
  return make_angular_limit(a, bodies[a], b, bodies[b], axis, min, max);
}
Constraint Mechanism::positional_limit(int a, int b, const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis,
                                       double min, double max) const {
  assert(body_pair(*this, a, b));
  return make_positional_limit(a, bodies[a], b, bodies[b], anchor, axis, min, max);
}

Constraint Mechanism::joint_set(int a, int b, const std::vector<ChainJoint>& world_joints) const {
  assert(body_pair(*this, a, b));
  return make_joint_set(a, bodies[a], b, bodies[b], world_joints);
}

// The constraint graph of sparse/families.h over the bodies and the chosen constraints.
BlockPattern Mechanism::constraint_graph(bool equality_only) const {
  BodyGraph graph;
  graph.is_static.reserve(bodies.size());
  for (const RigidBody& b : bodies) graph.is_static.push_back(b.is_static);
  for (const Constraint& c : constraints)
    if (!equality_only || is_equality(c.type)) graph.joints.push_back({c.body_a, c.body_b, ldlpgs::num_rows(c)});
  return ldlpgs::constraint_graph(graph);
}

std::vector<std::pair<int, int>> Mechanism::body_graph() const {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(constraints.size());
  for (const Constraint& c : constraints) edges.emplace_back(c.body_a, c.body_b);
  return edges;
}

std::string body_label(const Mechanism& m, int body) {
  std::string s = "body \"";
  s += printable(m.bodies[body].name, 80);
  s += "\"";
  return s;
}

std::string constraint_label(const Mechanism& m, int constraint) {
  const Constraint& c = m.constraints[constraint];
  std::string s = "constraint ";
  s += std::to_string(constraint);
  s += " (";
  s += to_string(c.type);
  s += " between ";
  s += body_label(m, c.body_a);
  s += " and ";
  s += body_label(m, c.body_b);
  s += ")";
  return s;
}

void check_range(const std::string& source, const std::string& what, const char* quantity, double x, double min,
                 double max, const char* unit) {
  if (min > 0 ? x >= min && x <= max : std::abs(x) <= max) return;
  std::string s = printable(source);
  s += ": ";
  if (!what.empty()) {
    s += what;
    s += ": ";
  }
  s += quantity;
  s += " ";
  s += format_number(x);
  s += min > 0 ? " outside [" : " beyond +-";
  if (min > 0) {
    s += format_number(min);
    s += ", ";
  }
  s += format_number(max);
  s += min > 0 ? "] " : " ";
  s += unit;
  s += " (physics/mechanism.h: MechanismRanges; beyond them what is computed from it overflows)";
  throw InputError(s);
}

void check_ranges(const Mechanism& m, const std::string& source) {
  using R = MechanismRanges;
  auto check = [&](const std::string& what, const char* quantity, double x, double min, double max, const char* unit) {
    check_range(source, what, quantity, x, min, max, unit);
  };
  auto check3 = [&](const std::string& what, const char* quantity, const Eigen::Vector3d& v, double min, double max,
                    const char* unit) {
    for (int k = 0; k < 3; ++k) check(what, quantity, v[k], min, max, unit);
  };
  check("timestep", "timestep", m.timestep, R::timestep_min, R::timestep_max, "s");
  check3("gravity", "component", m.gravity, 0, R::velocity_max, "m/s^2");
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const RigidBody& b = m.bodies[i];
    const std::string what = body_label(m, static_cast<int>(i));
    check3(what, "position", b.position, 0, R::coordinate_max, "m");
    if (b.is_static) continue;
    check(what, "mass", b.mass, R::mass_min, R::mass_max, "kg");
    check3(what, "inertia", b.inertia, R::mass_min, R::mass_max, "kg m^2");
    check3(what, "linear velocity", b.linear_velocity, 0, R::velocity_max, "m/s");
    check3(what, "angular velocity", b.angular_velocity, 0, R::velocity_max, "rad/s");
    check3(what, "force", b.applied_force, 0, R::load_max, "N");
    check3(what, "torque", b.applied_torque, 0, R::load_max, "N m");
  }
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const Constraint& c = m.constraints[i];
    const std::string what = constraint_label(m, static_cast<int>(i));
    check3(what, "anchor", m.bodies[c.body_a].to_world(c.anchor_a), 0, R::coordinate_max, "m");
    check3(what, "anchor", m.bodies[c.body_b].to_world(c.anchor_b), 0, R::coordinate_max, "m");
    check(what, "length", c.length, 0, 2 * R::coordinate_max, "m");
    check(what, "min", c.min, 0, R::coordinate_max, "m or rad");
    check(what, "max", c.max, 0, R::coordinate_max, "m or rad");
  }
}

}  // namespace ldlpgs
