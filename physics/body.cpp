// A rigid body's world-frame inertia and kinetic energy. The inertia is diagonal in the body
// frame, so in the world it is R diag(I) R^T (R = the orientation as a matrix), and its inverse is
// R diag(1/I) R^T (R^-1 = R^T): no 3x3 inversion.
#include "ldlpgs/physics/body.h"

#include <cassert>

namespace ldlpgs {

Eigen::Matrix3d RigidBody::inverse_inertia_world() const {
  if (is_static) return Eigen::Matrix3d::Zero();
  assert(inertia.minCoeff() > 0);
  const Eigen::Matrix3d r = orientation.toRotationMatrix();
  return r * inertia.cwiseInverse().asDiagonal() * r.transpose();
}

Eigen::Matrix3d RigidBody::inertia_world() const {
  const Eigen::Matrix3d r = orientation.toRotationMatrix();
  return r * inertia.asDiagonal() * r.transpose();
}

double RigidBody::kinetic_energy() const {
  if (is_static) return 0.0;
  // w^T (R diag(I) R^T) w = (R^T w)^T diag(I) (R^T w): the body-frame angular velocity.
  const Eigen::Vector3d w_body = orientation.conjugate() * angular_velocity;
  return 0.5 * mass * linear_velocity.squaredNorm() + 0.5 * w_body.dot(inertia.cwiseProduct(w_body));
}

}  // namespace ldlpgs
