#pragma once
// Two mechanisms compared field by field in tests (scene files against built-ins, round trips).
#include <gtest/gtest.h>

#include <string>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::testing {

// Every body (loads included) and every constraint's local data equal to within tol (static
// bodies: name, position and orientation, the only data a file gives them).
void expect_same(const Mechanism& a, const Mechanism& b, double tol) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_LE((a.gravity - b.gravity).norm(), tol);
  EXPECT_NEAR(a.timestep, b.timestep, tol);
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (size_t i = 0; i < a.bodies.size(); ++i) {
    const RigidBody &x = a.bodies[i], &y = b.bodies[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.is_static, y.is_static);
    EXPECT_LE((x.position - y.position).norm(), tol);
    EXPECT_LE((x.orientation.coeffs() - y.orientation.coeffs()).norm(), tol);
    if (x.is_static) continue;
    EXPECT_NEAR(x.mass, y.mass, tol * x.mass);
    EXPECT_LE((x.inertia - y.inertia).norm(), tol * x.inertia.norm());
    EXPECT_LE((x.linear_velocity - y.linear_velocity).norm(), tol);
    EXPECT_LE((x.angular_velocity - y.angular_velocity).norm(), tol);
    EXPECT_LE((x.applied_force - y.applied_force).norm(), tol * (1 + x.applied_force.norm()));
    EXPECT_LE((x.applied_torque - y.applied_torque).norm(), tol * (1 + x.applied_torque.norm()));
  }
  ASSERT_EQ(a.constraints.size(), b.constraints.size());
  for (size_t i = 0; i < a.constraints.size(); ++i) {
    const Constraint &x = a.constraints[i], &y = b.constraints[i];
    SCOPED_TRACE(std::string("constraint ") + std::to_string(i) + " (" + to_string(x.type) + ")");
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.body_a, y.body_a);
    EXPECT_EQ(x.body_b, y.body_b);
    EXPECT_LE((x.anchor_a - y.anchor_a).norm(), tol);
    EXPECT_LE((x.anchor_b - y.anchor_b).norm(), tol);
    EXPECT_LE((x.frame_a - y.frame_a).norm(), tol);
    EXPECT_LE((x.frame_b - y.frame_b).norm(), tol);
    EXPECT_NEAR(x.length, y.length, tol);
    EXPECT_NEAR(x.min, y.min, tol);
    EXPECT_NEAR(x.max, y.max, tol);
  }
}

}  // namespace ldlpgs::testing
