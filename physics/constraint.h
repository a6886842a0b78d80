#pragma once
// Constraints between two rigid bodies, as the talk defines them: a differentiable position error
// c(bodies) in R^d, zero when the constraint holds, regular (its Jacobian has rank d) on its zero
// set. The velocity rows are dc/dt = J V with V = (v_a, w_a, v_b, w_b), world frame.
//
// A tagged type dispatched by a switch (constraint.cpp); every type has the same verbs:
//   make_*     build it from world-frame anchors and axes at the initial pose (scene files give
//              those); anchors and axes are stored in each body's own frame.
//   evaluate   c, J and the row kinds at the current pose.
//
//   type              rows  removes                                  kind
//   ball                 3  relative translation of the anchor       equality
//   hinge                5  ball + 2 rows aligning the axes          equality
//   prismatic            5  all rotation + translation across axis   equality
//   cylindrical          4  translation across and rotation off axis equality
//   weld                 6  everything (rigid)                       equality
//   rod                  1  change of the anchors' distance          equality
//   rope                 1  distance above the length                inequality
//   angular_limit        1  hinge angle about the axis out of range  inequality
//   positional_limit     1  slide along the axis out of range        inequality
//   joint_set          0-6  what a set of joints does not allow      equality
//   coordinate_limit     1  one joint of a set out of its range      inequality
//   dof_drive            1  a dof's rate, softly (armature, damping) equality, soft
//   dof_motor            1  a dof's rate, bounded (friction loss)     inequality, bounded
// joint_set, coordinate_limit, dof_drive and dof_motor carry a JointChain (joint_set.h): any hinges, slides and balls
// on one body composed as MuJoCo composes them; the set's rows number 6 minus the motions its
// joints span. dof_drive and dof_motor have no position error: the step gives them a target rate,
// a softness and bounds every step (physics/actuation.h: MuJoCo's joint dynamics and actuators).
#include <array>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/body.h"
#include "ldlpgs/physics/joint_set.h"

namespace ldlpgs {

enum class ConstraintType {
  ball, hinge, prismatic, cylindrical, weld, rod, rope, angular_limit, positional_limit, joint_set, coordinate_limit,
  dof_drive, dof_motor
};

constexpr int kMaxConstraintRows = 6;
// The rows of every type but joint_set, whose count its chain gives (num_rows(Constraint)).
int num_rows(ConstraintType type);
bool is_equality(ConstraintType type);
// dof_drive and dof_motor: a joint dof's rate (no position error), not a joint's row.
inline bool acts_on_a_dof(ConstraintType type) {
  return type == ConstraintType::dof_drive || type == ConstraintType::dof_motor;
}
const char* to_string(ConstraintType type);
// false if `name` is not a type name (as scene files spell it)
bool constraint_type_from_string(std::string_view name, ConstraintType* type);

struct Constraint {
  ConstraintType type = ConstraintType::ball;
  int body_a = -1, body_b = -1;  // indices into the mechanism's bodies; a != b
  // The anchor point in each body's frame (rod, rope: the two attachment points; else the same
  // world point at the initial pose).
  Eigen::Vector3d anchor_a = Eigen::Vector3d::Zero(), anchor_b = Eigen::Vector3d::Zero();
  // Orthonormal frames (columns u, w, n; n = the axis) in each body's frame, equal in the world
  // at the initial pose. Ball, rod and rope ignore them.
  Eigen::Matrix3d frame_a = Eigen::Matrix3d::Identity(), frame_b = Eigen::Matrix3d::Identity();
  double length = 0;             // rod, rope (m)
  double min = 0, max = 0;       // limits: radians (angular_limit) or metres (positional_limit)
  // The two bodies' shapes touch each other (Box2D's collideConnected); by default bodies joined
  // by a constraint do not collide.
  bool collide = false;
  // joint_set, coordinate_limit: the joints (shared, immutable), and which joint's coordinate a
  // limit bounds (min, max in its unit from q = 0; a ball's angle: max only). dof_drive and
  // dof_motor: `joint` is the chain's dof whose rate they act on (a ball has 3).
  std::shared_ptr<const JointChain> chain;
  int joint = -1;
  // The chain's coordinates at the last evaluation, where the next fit starts (joint_set.h).
  mutable ChainCoordinates coordinates{};
};

int num_rows(const Constraint& constraint);

// Rows of one constraint at the current pose. For an inequality the row is the nearer side of
// the limit written as c >= 0 (rope: length - distance; limits: value - min or max - value), so
// its impulse is lambda >= 0 (the solver's bounds).
struct ConstraintRows {
  int rows = 0;
  std::array<double, kMaxConstraintRows> c{};             // position error
  std::array<bool, kMaxConstraintRows> angular{};         // radians (true) or metres (false)
  // dc/dt = J V, one row of 12 per constraint row: [v_a w_a v_b w_b] (row-major, rows x 12)
  std::array<double, kMaxConstraintRows * 12> jacobian{};
};

// The fit of a chain-carrying constraint's chain at the bodies' pose: `given` (a shared one,
// chain_fits.h) where not null, else fitted into *own from the constraint's own last coordinates
// (which receive the new ones).
const ChainFit& chain_fit(const Constraint& c, const RigidBody& a, const RigidBody& b, const ChainFit* given,
                          ChainFit* own);

// `fit`: the constraint's chain fitted at this pose (ChainFits, chain_fits.h), shared with the
// other constraints on the chain; null: fitted here from the constraint's own last coordinates.
ConstraintRows evaluate(const Constraint& constraint, const RigidBody& a, const RigidBody& b,
                        const ChainFit* fit = nullptr);

// Builders from world-frame data at the bodies' current pose. `axis` need not be unit; a zero
// axis is a programmer error here (scene files are validated before).
Constraint make_ball(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& anchor);
Constraint make_axial(ConstraintType type, int ia, const RigidBody& a, int ib, const RigidBody& b,
                      const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis);  // hinge, prismatic, cylindrical, weld
// rod, rope: anchors on a and b; length < 0 means the current distance.
Constraint make_distance(ConstraintType type, int ia, const RigidBody& a, int ib, const RigidBody& b,
                         const Eigen::Vector3d& anchor_on_a, const Eigen::Vector3d& anchor_on_b, double length = -1);
Constraint make_angular_limit(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& axis,
                              double min, double max);
Constraint make_positional_limit(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& anchor,
                                 const Eigen::Vector3d& axis, double min, double max);

// A set of joints on b, given in the world at the bodies' current pose (joint_set.h), and the
// range [min, max] of one of them (the coordinate from here; a ball's angle: [0, max]).
Constraint make_joint_set(int ia, const RigidBody& a, int ib, const RigidBody& b,
                          const std::vector<ChainJoint>& world_joints);
Constraint make_coordinate_limit(const Constraint& joint_set, int joint, double min, double max);
// A dof_drive or dof_motor on dof `dof` of a chain (any constraint carrying it).
Constraint make_dof_row(ConstraintType type, const Constraint& joint_set, int dof);

// The hinge angle of b relative to a about the axis (angular_limit; 0 at the initial pose), and
// the slide of b's anchor along a's axis (positional_limit; 0 at the initial pose), and the
// coordinate a coordinate_limit bounds.
double limit_value(const Constraint& constraint, const RigidBody& a, const RigidBody& b);

}  // namespace ldlpgs
