// The step's integrate stage: the solved velocities into the bodies, then their poses.
#include "ldlpgs/physics/step_stages.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace ldlpgs {
namespace step_stages {

// ContactOptions::implicit_gyroscopic applies: it is on and the mechanism has shapes.
bool implicit_gyroscopic(const Mechanism& m, const StepOptions& options) {
  return options.contacts.implicit_gyroscopic && has_shapes(m);
}

// w' with I (w' - w) + dt w' x I w' = 0 in the body frame (the gyroscopic term implicit), by one
// Newton step from w, whose Jacobian is I + dt ([w]x I - [I w]x).
Eigen::Vector3d gyroscopic_velocity(const RigidBody& b, double dt) {
  const Eigen::Vector3d w = b.orientation.conjugate() * b.angular_velocity;
  const Eigen::Vector3d iw = b.inertia.cwiseProduct(w);
  const auto cross_matrix = [](const Eigen::Vector3d& a) {
    Eigen::Matrix3d m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
  };
  const Eigen::Matrix3d jacobian = Eigen::Matrix3d(b.inertia.asDiagonal()) +
                                   dt * (cross_matrix(w) * b.inertia.asDiagonal() - cross_matrix(iw));
  return b.orientation * (w - jacobian.partialPivLu().solve(dt * w.cross(iw)));
}

// q <- exp(dtheta) q, dtheta a world-frame rotation vector (left product: world frame; the right
// product would rotate about the body-frame axis, the same only where the two coincide, as on
// planar scenes), then normalized.
void rotate(RigidBody& b, const Eigen::Vector3d& dtheta) {
  const double angle = dtheta.norm();
  if (angle > 0) b.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, dtheta / angle)) * b.orientation).normalized();
}

}  // namespace step_stages

using namespace step_stages;

// V1 = V0 + W F dt + W J^T lambda into the bodies, then their poses moved by V1 over the step
// (semi-implicit Euler).
void Simulation::integrate() {
  Mechanism& m = mechanism_;
  const double dt = m.timestep;
  const bool gyroscopic = implicit_gyroscopic(m, options_);
  int c = 0;
  for (RigidBody& b : m.bodies) {
    if (b.is_static) continue;
    // V1 = V0 + W F dt + W J^T lambda
    const double* v0 = v0_.data() + 6 * c;
    const double* dv = dv_.data() + 6 * c;
    ++c;
    b.linear_velocity = Eigen::Vector3d(v0[0] + dv[0], v0[1] + dv[1], v0[2] + dv[2]);
    b.angular_velocity = Eigen::Vector3d(v0[3] + dv[3], v0[4] + dv[4], v0[5] + dv[5]);
    b.position += b.linear_velocity * dt;
    // q <- exp(w dt) q (world-frame w), renormalized. Unless the free motion took the gyroscopic
    // term implicitly, the body's angular momentum I w is kept through the rotation
    // (w <- I_new^-1 I_old w): without it a free asymmetric body's angular momentum would drift,
    // since semi-implicit Euler drops the gyroscopic term w x I w. (I_world w = R (I .* (R^T w))
    // by quaternion rotations: no rotation matrix is built)
    if (gyroscopic) {
      rotate(b, b.angular_velocity * dt);
      continue;
    }
    const Eigen::Vector3d momentum = b.orientation * b.inertia.cwiseProduct(b.orientation.conjugate() * b.angular_velocity);
    rotate(b, b.angular_velocity * dt);
    b.angular_velocity = b.orientation * (b.orientation.conjugate() * momentum).cwiseQuotient(b.inertia);
  }
  evaluated_valid_ = false;  // the pose moved
}
}  // namespace ldlpgs
