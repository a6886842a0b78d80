#pragma once
// The forces a still or moving medium (air, water) applies on a rigid body: MuJoCo's inertia-box
// fluid model, the one mj_passive applies to every body when <option> sets density or viscosity.
// The body is replaced by the uniform box of its mass and principal moments: a box of sides
// (a, b, c) has I_x = m (b^2 + c^2) / 12, so a = sqrt(6 (I_y + I_z - I_x) / m) and likewise b, c.
// In the principal frame, with w the angular velocity and v the velocity of the centre of mass
// relative to the wind:
//   viscosity mu (Stokes, on the sphere of diameter d = (a + b + c) / 3):
//     force -3 pi mu d v,   torque -pi mu d^3 w
//   density rho (quadratic drag, each axis on its own):
//     force_x  -1/2 rho b c |v_x| v_x,   torque_x  -rho a (b^4 + c^4) / 64 |w_x| w_x   (and cyclic)
// The model is explicit: the wrench is computed from the velocities at the start of the step and
// applied as an external load for that step, as MuJoCo applies it.
#include <Eigen/Core>

#include "ldlpgs/physics/body.h"

namespace ldlpgs {

// The medium bodies move in (MuJoCo's option density, viscosity and wind); SI units.
struct FluidMedium {
  double density = 0;    // kg/m^3
  double viscosity = 0;  // Pa s
  Eigen::Vector3d wind = Eigen::Vector3d::Zero();  // the medium's velocity, world (m/s)
  bool active() const { return density > 0 || viscosity > 0; }
};

// The force (N, through the centre of mass) and torque (N m), world frame, the medium applies on
// a body moving with its current velocities. Zero for a static body and for an inactive medium.
void fluid_wrench(const RigidBody& body, const FluidMedium& medium, Eigen::Vector3d* force,
                  Eigen::Vector3d* torque);

}  // namespace ldlpgs
