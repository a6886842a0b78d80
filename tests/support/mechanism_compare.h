#pragma once
// Two mechanisms compared field by field in tests (scene files against built-ins, round trips).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::testing {

// Two shapes (physics/shape.h) equal to within tol, integers exactly.
void expect_same_shape(const Shape& x, const Shape& y, double tol) {
  EXPECT_EQ(x.type, y.type);
  EXPECT_LE((x.position - y.position).norm(), tol);
  if (x.type != ShapeType::plane) {  // a plane's orientation is its normal
    EXPECT_LE((x.orientation.coeffs() - y.orientation.coeffs()).norm(), tol);
  }
  EXPECT_NEAR(x.radius, y.radius, tol);
  EXPECT_NEAR(x.half_length, y.half_length, tol);
  EXPECT_LE((x.half_extents - y.half_extents).norm(), tol);
  EXPECT_LE((x.normal - y.normal).norm(), tol);
  EXPECT_NEAR(x.friction, y.friction, tol);
  EXPECT_NEAR(x.restitution, y.restitution, tol);
  EXPECT_EQ(x.contype, y.contype);
  EXPECT_EQ(x.conaffinity, y.conaffinity);
}

// Every body (loads and shapes included) and every constraint's local data equal to within tol
// (static bodies: name, position, orientation and shapes, the only data a file gives them).
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
    EXPECT_EQ(x.shapes.size(), y.shapes.size());
    for (size_t k = 0; k < std::min(x.shapes.size(), y.shapes.size()); ++k) {
      SCOPED_TRACE(std::string("shape ") + std::to_string(k));
      expect_same_shape(x.shapes[k], y.shapes[k], tol);
    }
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
    EXPECT_EQ(x.collide, y.collide);
  }
}

}  // namespace ldlpgs::testing
