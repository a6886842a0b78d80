#pragma once
// A mechanism: rigid bodies and the constraints between them (the talk's unit of the symbolic
// phase). Its body graph has bodies as nodes and constraints as edges; its constraint graph (the
// edge graph of the body graph) has constraints as nodes, weighted by their row counts, and an
// edge wherever two constraints share a dynamic body: it is the block graph of H = J W J^T.
// Static bodies couple nothing (W = 0 there).
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/actuation.h"
#include "ldlpgs/physics/body.h"
#include "ldlpgs/physics/constraint.h"
#include "ldlpgs/physics/fluid.h"
#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

struct Mechanism {
  std::string name;
  Eigen::Vector3d gravity{0, -9.81, 0};  // m/s^2
  double timestep = 0.01;                // s
  std::vector<RigidBody> bodies;
  std::vector<Constraint> constraints;
  // MuJoCo's joint dynamics and actuators (physics/actuation.h; MJCF models): explicit loads and
  // the targets of the dof_drive and dof_motor constraints. `actuation` false: the actuators
  // apply nothing (MuJoCo's actuation flag; their controls are still taken).
  std::vector<DofDynamics> dofs;
  std::vector<Actuator> actuators;
  bool actuation = true;
  FluidMedium fluid;  // the medium's forces on every body (physics/fluid.h); none by default

  int find_body(std::string_view body_name) const;  // -1 if none has that name
  int add_body(RigidBody body);                      // returns its index
  int add_constraint(Constraint constraint);         // returns its index
  // constraint.h's builders (make_ball, ...) with the two bodies named once, by index, at their
  // current pose: m.add_constraint(m.ball(a, b, anchor)).
  Constraint ball(int a, int b, const Eigen::Vector3d& anchor) const;
  Constraint axial(ConstraintType type, int a, int b, const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis) const;
  Constraint distance(ConstraintType type, int a, int b, const Eigen::Vector3d& anchor_on_a,
                      const Eigen::Vector3d& anchor_on_b, double length = -1) const;
  Constraint angular_limit(int a, int b, const Eigen::Vector3d& axis, double min, double max) const;
  Constraint positional_limit(int a, int b, const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis, double min,
                              double max) const;
  Constraint joint_set(int a, int b, const std::vector<ChainJoint>& world_joints) const;
  int num_rows() const;                              // sum of the constraints' rows
  int num_dynamic_bodies() const;
  // The first limit or rope (an inequality row: the direct solver does not take it), -1 if none.
  int first_inequality() const;

  // Blocks = constraints (sizes = their rows), adjacency = a shared dynamic body. `equality_only`
  // keeps only the equality constraints (the block ldl-pgs factors), renumbered in order.
  BlockPattern constraint_graph(bool equality_only = false) const;
  // Edges (body_a, body_b) of the body graph, one per constraint.
  std::vector<std::pair<int, int>> body_graph() const;
};

// The ranges a mechanism's data must lie in so that nothing computed from it overflows or
// underflows: W (1/m, R diag(1/I) R^T), J (lever arms r = anchor - centre), H = J W J^T (entries
// up to 1/m + |r|^2 / I, at most 4e118 at the corners below), impulses, energies (m |v|^2 <=
// 1e68) and the velocity step (|W F dt| <= 1e103). "Finite and positive" is not enough: a mass
// of 1e-320 (1/m = inf), an anchor at 1e155 (|r|^2 = inf) or a coordinate of 1e308 gives an H of
// NaN and inf. These bound representability only: how accurately a solver handles a
// mechanism near them (a mass ratio of 1e12, a coordinate of 1e9 m whose rounding is 1e-7 m) is
// another matter (README, "Supported range").
struct MechanismRanges {
  static constexpr double mass_min = 1e-50, mass_max = 1e50;  // kg, and principal moments in kg m^2
  static constexpr double coordinate_max = 1e9;  // |position|, |anchor| (world), |limit min, max|, rod length (m)
  static constexpr double velocity_max = 1e9;    // |v| (m/s), |w| (rad/s), |gravity| (m/s^2)
  static constexpr double load_max = 1e50;       // |force| (N), |torque| (N m)
  static constexpr double timestep_min = 1e-12, timestep_max = 1e3;  // s
};
// "body \"hub\"" and "constraint 3 (ball between body \"a\" and body \"b\")" for messages
// (names escaped and bounded: sparse/error.h's printable).
std::string body_label(const Mechanism& mechanism, int body);
std::string constraint_label(const Mechanism& mechanism, int constraint);
// Throws an InputError "source: body \"hub\": mass 1e-320 outside [1e-50, 1e50] kg" naming the
// first body, constraint or setting outside MechanismRanges (non-finite values included).
void check_ranges(const Mechanism& mechanism, const std::string& source);
// One value against one range, with check_ranges' message ("source: what: quantity x outside
// [min, max] unit", "what: " left out when empty): x in [min, max] when min > 0, |x| <= max
// otherwise; NaN never is. For the setters of a running simulation (physics/step.h).
void check_range(const std::string& source, const std::string& what, const char* quantity, double x, double min,
                 double max, const char* unit);

}  // namespace ldlpgs
