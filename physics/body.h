#pragma once
// A rigid body in maximal coordinates (the talk: each body has its own position and orientation,
// joints are constraints between bodies). Velocities are in the world frame; the inertia is
// given by its principal moments in the body frame.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ldlpgs/physics/shape.h"

namespace ldlpgs {

struct RigidBody {
  std::string name;
  bool is_static = false;                      // infinite mass: W = 0, never moves
  double mass = 1;                             // kg (dynamic bodies: > 0)
  Eigen::Vector3d inertia{1, 1, 1};            // principal moments, body frame (kg m^2, > 0)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();         // centre of mass, world (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world, unit
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();  // world (m/s)
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(); // world (rad/s)
  // A constant external load besides gravity, applied every step (scene files' "force" and
  // "torque"): a force through the centre of mass (N) and a torque (N m), world frame.
  Eigen::Vector3d applied_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d applied_torque = Eigen::Vector3d::Zero();
  std::vector<Shape> shapes;  // collision geometry (physics/shape.h); none: the body touches nothing

  // World-frame inverse inertia R diag(1/I) R^T (zero for a static body).
  Eigen::Matrix3d inverse_inertia_world() const;
  // World-frame inertia tensor R diag(I) R^T.
  Eigen::Matrix3d inertia_world() const;
  double inverse_mass() const { return is_static ? 0.0 : 1.0 / mass; }
  // A point given in the body frame, in world coordinates.
  Eigen::Vector3d to_world(const Eigen::Vector3d& local) const { return position + orientation * local; }
  // 1/2 m v^2 + 1/2 w^T I w (zero for a static body).
  double kinetic_energy() const;
};

}  // namespace ldlpgs
