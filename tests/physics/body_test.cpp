// Rigid bodies: the world-frame inertia and its inverse against each other and against a
// hand-rotated tensor, and the kinetic energy of hand-computed cases.
#include "ldlpgs/physics/body.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>

#include "tests/support/random_poses.h"

namespace ldlpgs {
namespace {

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

using testing::random_rotation;

RigidBody random_body(std::mt19937& rng) {
  std::uniform_real_distribution<double> moment(0.1, 10);
  RigidBody b;
  b.mass = 3;
  b.inertia = Vector3d(moment(rng), moment(rng), moment(rng));
  b.orientation = random_rotation(rng);
  return b;
}

TEST(Body, InverseInertiaTimesInertiaIsIdentity) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 50; ++trial) {
    const RigidBody b = random_body(rng);
    // Moments in [0.1, 10]: condition number <= 100, so products are exact to ~1e-14.
    EXPECT_TRUE((b.inverse_inertia_world() * b.inertia_world()).isIdentity(1e-12)) << "trial " << trial;
    EXPECT_TRUE((b.inertia_world() * b.inverse_inertia_world()).isIdentity(1e-12)) << "trial " << trial;
  }
}

// A quarter turn about z maps the body's x to the world's y: the world tensor swaps the x and y
// moments, and is symmetric.
TEST(Body, InertiaWorldOfAQuarterTurn) {
  RigidBody b;
  b.inertia = Vector3d(1, 2, 3);
  b.orientation = Quaterniond(AngleAxisd(std::numbers::pi / 2, Vector3d::UnitZ()));
  EXPECT_TRUE(b.inertia_world().isApprox(Vector3d(2, 1, 3).asDiagonal().toDenseMatrix(), 1e-15));
  EXPECT_TRUE(b.inverse_inertia_world().isApprox(Vector3d(0.5, 1, 1.0 / 3).asDiagonal().toDenseMatrix(), 1e-15));
  std::mt19937 rng(2);
  const RigidBody r = random_body(rng);
  EXPECT_TRUE(r.inertia_world().isApprox(r.inertia_world().transpose(), 1e-15));
}

TEST(Body, StaticBodyHasZeroInverseInertiaAndMass) {
  std::mt19937 rng(3);
  RigidBody b = random_body(rng);
  b.is_static = true;
  EXPECT_TRUE(b.inverse_inertia_world().isZero(0));
  EXPECT_EQ(b.inverse_mass(), 0);
}

// m = 2, v = (1, 2, 3): 1/2 * 2 * 14 = 14. Moments (1, 2, 3), a quarter turn about z, w = world
// x: in the body frame w = -y (R^T x = -y), so 1/2 * 2 * 1 = 1. Total 15.
TEST(Body, KineticEnergyOfAKnownCase) {
  RigidBody b;
  b.mass = 2;
  b.inertia = Vector3d(1, 2, 3);
  b.orientation = Quaterniond(AngleAxisd(std::numbers::pi / 2, Vector3d::UnitZ()));
  b.linear_velocity = Vector3d(1, 2, 3);
  b.angular_velocity = Vector3d(1, 0, 0);
  EXPECT_NEAR(b.kinetic_energy(), 15, 1e-14);
  // Spinning about the world z (the body's z): 1/2 * 3 * 4 = 6 more than translation alone.
  b.angular_velocity = Vector3d(0, 0, 2);
  EXPECT_NEAR(b.kinetic_energy(), 14 + 6, 1e-14);
}

TEST(Body, StaticBodyHasNoKineticEnergy) {
  RigidBody b;
  b.is_static = true;
  b.linear_velocity = Vector3d(1, 2, 3);
  b.angular_velocity = Vector3d(4, 5, 6);
  EXPECT_EQ(b.kinetic_energy(), 0);
}

// The kinetic energy does not depend on the frame it is computed in: for any orientation,
// 1/2 w^T I_world w equals the body-frame sum 1/2 sum_i I_i (R^T w)_i^2 (computed here by hand).
TEST(Body, KineticEnergyMatchesBodyFrameSum) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    RigidBody b = random_body(rng);
    b.linear_velocity = Vector3d(u(rng), u(rng), u(rng));
    b.angular_velocity = Vector3d(u(rng), u(rng), u(rng));
    const Vector3d w = b.orientation.toRotationMatrix().transpose() * b.angular_velocity;
    double expected = 0.5 * b.mass * b.linear_velocity.squaredNorm();
    for (int i = 0; i < 3; ++i) expected += 0.5 * b.inertia[i] * w[i] * w[i];
    EXPECT_NEAR(b.kinetic_energy(), expected, 1e-12) << "trial " << trial;
    EXPECT_NEAR(b.kinetic_energy(),
                0.5 * b.mass * b.linear_velocity.squaredNorm() +
                    0.5 * b.angular_velocity.dot(b.inertia_world() * b.angular_velocity),
                1e-12)
        << "trial " << trial;
  }
}

TEST(Body, ToWorldRotatesThenTranslates) {
  RigidBody b;
  b.position = Vector3d(1, 2, 3);
  b.orientation = Quaterniond(AngleAxisd(std::numbers::pi / 2, Vector3d::UnitZ()));
  EXPECT_TRUE(b.to_world(Vector3d(1, 0, 0)).isApprox(Vector3d(1, 3, 3), 1e-15));
}

}  // namespace
}  // namespace ldlpgs
