// MuJoCo's inertia-box fluid model (physics/fluid.h), term for term as mj_passive computes it, so
// that a model with density or viscosity moves as it does in MuJoCo.
#include "ldlpgs/physics/fluid.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace ldlpgs {

void fluid_wrench(const RigidBody& body, const FluidMedium& medium, Eigen::Vector3d* force,
                  Eigen::Vector3d* torque) {
  force->setZero();
  torque->setZero();
  // MuJoCo skips bodies lighter than mjMINVAL (1e-15), whose box would be undefined.
  constexpr double kMinVal = 1e-15;
  if (body.is_static || !medium.active() || body.mass < kMinVal) return;

  // The equivalent box's sides; a moment on the triangle inequality's edge (a flat body) gives a
  // side of sqrt(6e-15 / m), MuJoCo's floor, not a NaN from rounding below zero.
  const Eigen::Vector3d& inertia = body.inertia;
  const auto side = [&](int i, int j, int k) {
    return std::sqrt(std::max(kMinVal, inertia[j] + inertia[k] - inertia[i]) / body.mass * 6.0);
  };
  const Eigen::Vector3d box(side(0, 1, 2), side(1, 0, 2), side(2, 0, 1));

  // Velocities in the principal frame; the linear one relative to the medium.
  const Eigen::Matrix3d rotation = body.orientation.toRotationMatrix();
  const Eigen::Vector3d w = rotation.transpose() * body.angular_velocity;
  const Eigen::Vector3d v = rotation.transpose() * (body.linear_velocity - medium.wind);

  Eigen::Vector3d local_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d local_torque = Eigen::Vector3d::Zero();
  if (medium.viscosity > 0) {
    // Stokes drag on the sphere of the mean diameter: 6 pi mu r v and 8 pi mu r^3 w.
    const double diameter = (box[0] + box[1] + box[2]) / 3.0;
    local_torque = -std::numbers::pi * diameter * diameter * diameter * medium.viscosity * w;
    local_force = -3.0 * std::numbers::pi * diameter * medium.viscosity * v;
  }
  if (medium.density > 0) {
    // Along each axis, the dynamic pressure 1/2 rho v^2 on the face across it. About each axis,
    // that pressure from the speed w r on the two faces the turn sweeps, times the lever arm r:
    // a face of width a and length L gives 2 int_0^{L/2} 1/2 rho w^2 r^3 a dr = rho a L^4 w^2 / 64.
    for (int i = 0; i < 3; ++i) {
      const int j = i == 0 ? 1 : 0;
      const int k = i == 2 ? 1 : 2;
      local_force[i] -= 0.5 * medium.density * box[j] * box[k] * std::abs(v[i]) * v[i];
      const double bj2 = box[j] * box[j];
      const double bk2 = box[k] * box[k];
      local_torque[i] -= medium.density * box[i] * (bj2 * bj2 + bk2 * bk2) * std::abs(w[i]) * w[i] / 64.0;
    }
  }
  *force = rotation * local_force;
  *torque = rotation * local_torque;
}

}  // namespace ldlpgs
