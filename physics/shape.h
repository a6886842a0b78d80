#pragma once
// Collision shapes carried by a rigid body (RigidBody::shapes). A shape is placed in its body's
// frame; the collision detector (collision.h) turns touching pairs into contact points.
//
//   type     parameters                        geometry (shape frame)
//   plane    normal (body frame)               the half space below the plane through
//                                              `position` with that normal; static bodies only
//   sphere   radius                            ball about the origin
//   capsule  radius, half_length               segment from -half_length to +half_length on z,
//                                              swept by the radius (half_length excludes the caps)
//   box      half_extents                      [-hx, hx] x [-hy, hy] x [-hz, hz]
//
// Pair rules (as Box2D mixes them): friction sqrt(mu_a mu_b), restitution max(e_a, e_b); two
// shapes may touch when (a.contype & b.conaffinity) || (b.contype & a.conaffinity) (MuJoCo's
// filter); shapes of one body never touch, nor do two bodies joined by a constraint unless that
// constraint says `collide`.
#include <cstdint>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ldlpgs {

enum class ShapeType { plane, sphere, capsule, box };
const char* to_string(ShapeType type);
bool shape_type_from_string(std::string_view name, ShapeType* type);  // false: unknown name

struct Shape {
  ShapeType type = ShapeType::sphere;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // body frame (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // shape -> body frame (unused by a plane)
  double radius = 0;                                                // sphere, capsule (m)
  double half_length = 0;                                           // capsule (m)
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();           // box (m)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();                // plane, body frame (unit after checks)
  double friction = 0.5;                                            // Coulomb mu, >= 0
  double restitution = 0;                                           // [0, 1]
  uint32_t contype = 1, conaffinity = 1;                            // the pair filter above
};

// What is wrong with `shape` on a body (static or not), one phrase ("radius -1 is not > 0", "a
// plane on a dynamic body"), or empty when nothing is: the check every reader and
// Simulation::add_shape make. Lengths must lie in (0, 1e9] m (MechanismRanges), a normal
// must be finite and not shorter than 1e-12, friction finite and >= 0, restitution in [0, 1].
std::string shape_problem(const Shape& shape, bool body_is_static);

double combined_friction(const Shape& a, const Shape& b);
double combined_restitution(const Shape& a, const Shape& b);
bool may_collide(const Shape& a, const Shape& b);

}  // namespace ldlpgs
