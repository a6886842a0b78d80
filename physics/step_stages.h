#pragma once
// Internal to physics/: the stages of Simulation::step, one file each, and the helpers they share.
//   step.cpp              the step as its stages in order, the options, the constructor
//   step_contacts.cpp     collide: contact points, their rows' blocks, warm start, impulses kept
//   step_system.cpp       prepare: joint dynamics, loads, W, J, R, compliance (build_system too)
//   step_integrate.cpp    integrate: V1 into the bodies, then their poses
//   step_projection.cpp   project positions: post-stabilization
//   step_diagnostics.cpp  diagnostics: errors, energy, failure
//   step_state.cpp        the state API between steps
#include <span>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/step.h"

namespace ldlpgs::step_stages {

// column[b] = the velocity block of body b, -1 for a static body (size num_bodies)
std::vector<int> body_columns(const Mechanism& m);
// The structure of the step's System: one block per constraint in order, inequality blocks
// bounded below by 0. Values are written by write_velocity_system.
System system_structure(const Mechanism& m, const std::vector<int>& column);
// W_b = blockdiag(I3 / m, R diag(1/I) R^T) per column, at the current orientations.
void write_inverse_mass(const Mechanism& m, const std::vector<int>& column, System* s);
// Constraint k's rows (c and J, evaluated at the current pose) into the System's cells.
void write_jacobian(const ConstraintRows& rows, int k, System* s);
// The velocity step's values (step_system.cpp).
void write_velocity_system(const Mechanism& m, const StepOptions& options, const std::vector<int>& column,
                           std::span<const double> load, std::span<const double> predicted,
                           std::span<const ConstraintRows> known, ChainFits* fits, std::span<double> v0,
                           System* s);
void write_dof_rows(const Mechanism& m, std::span<const DofRow> rows, System* s);
void add_fluid_loads(const Mechanism& m, std::span<double> load);
// ContactOptions::implicit_gyroscopic applies: it is on and the mechanism has shapes.
bool implicit_gyroscopic(const Mechanism& m, const StepOptions& options);
// w' of the implicit gyroscopic term (step_integrate.cpp).
Eigen::Vector3d gyroscopic_velocity(const RigidBody& b, double dt);
// q <- exp(dtheta) q, dtheta a world-frame rotation vector, then normalized.
void rotate(RigidBody& b, const Eigen::Vector3d& dtheta);

}  // namespace ldlpgs::step_stages
