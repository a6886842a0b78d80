// MuJoCo's inertia-box fluid model (physics/fluid.h), checked against MuJoCo itself: for one free
// body whose principal frame is neither the body frame nor centred on its origin, at random poses
// and velocities under several media (density only, viscosity only, both, with wind), the wrench
// fluid_wrench gives equals the one MuJoCo's mj_passive puts in qfrc_passive. Then the cases that
// need no reference: no medium, and a body carried by the wind.
#include "ldlpgs/physics/fluid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "tests/support/temp_files.h"

#ifdef LDLPGS_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace ldlpgs {
namespace {

using Eigen::Vector3d;

// A tumbling body of unequal moments, off the origin.
RigidBody tumbling_body() {
  RigidBody body;
  body.mass = 2.5;
  body.inertia = {0.04, 0.07, 0.09};
  body.position = {0.3, -1.0, 2.0};
  body.orientation = Eigen::Quaterniond(0.8, 0.1, -0.4, 0.3).normalized();
  body.linear_velocity = {1.5, -0.7, 0.4};
  body.angular_velocity = {-2.0, 3.0, 0.5};
  return body;
}

TEST(Fluid, NoMediumNoWrench) {
  const FluidMedium medium;  // density = viscosity = 0
  EXPECT_FALSE(medium.active());
  Vector3d force = Vector3d::Constant(1), torque = Vector3d::Constant(1);
  fluid_wrench(tumbling_body(), medium, &force, &torque);
  EXPECT_EQ(force, Vector3d::Zero());
  EXPECT_EQ(torque, Vector3d::Zero());
}

TEST(Fluid, ABodyCarriedByTheWindFeelsNothing) {
  RigidBody body = tumbling_body();
  body.angular_velocity.setZero();
  const FluidMedium medium{1000, 0.001, body.linear_velocity};
  Vector3d force, torque;
  fluid_wrench(body, medium, &force, &torque);
  EXPECT_EQ(force, Vector3d::Zero());
  EXPECT_EQ(torque, Vector3d::Zero());
}

TEST(Fluid, DragOpposesTheMotion) {
  // Each term dissipates: the wrench's power on the body's velocities is negative.
  const RigidBody body = tumbling_body();
  for (const FluidMedium& medium : {FluidMedium{1.2, 0, {}}, FluidMedium{0, 0.5, {}}}) {
    Vector3d force, torque;
    fluid_wrench(body, medium, &force, &torque);
    EXPECT_LT(force.dot(body.linear_velocity), 0);
    EXPECT_LT(torque.dot(body.angular_velocity), 0);
  }
}

#ifdef LDLPGS_HAVE_MUJOCO

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

// One free body in a medium; `inertial` is the body's <inertial> or geoms, whatever sets its mass.
std::string free_body_model(const FluidMedium& medium, const std::string& inertial) {
  char option[256];
  std::snprintf(option, sizeof option, R"(<option density="%.17g" viscosity="%.17g" wind="%.17g %.17g %.17g"/>)",
                medium.density, medium.viscosity, medium.wind.x(), medium.wind.y(), medium.wind.z());
  return std::string("<mujoco>") + option + R"(<worldbody><body pos="0.1 0.2 0.3"><freejoint/>)" + inertial +
         "</body></worldbody></mujoco>";
}

// The principal frame turned from the body frame and off its origin: explicit, from a box geom,
// and flat (I_x = I_y + I_z: a side of the box is MuJoCo's floor, sqrt(6e-15 / m)).
const std::string kInertials[] = {
    R"(<inertial pos="0.05 -0.02 0.03" quat="0.9 0.1 0.3 -0.2" mass="1.7" diaginertia="0.02 0.03 0.04"/>)",
    R"(<geom type="box" size="0.3 0.1 0.05" pos="0.1 0 -0.05" euler="10 20 30" density="500"/>)",
    R"(<inertial pos="0 0.1 0" quat="0.6 -0.3 0.2 0.1" mass="0.8" diaginertia="0.3 0.1 0.2"/>)",
};

const FluidMedium kMedia[] = {
    {1.2, 0, {0, 0, 0}},           // density only (air)
    {0, 0.5, {0, 0, 0}},           // viscosity only (syrup: the Stokes terms as large as the drag)
    {1000, 0.001, {0, 0, 0}},      // both (water)
    {1.2, 0.2, {3.0, -1.0, 0.5}},  // both, with wind
    {1000, 0, {-0.5, 2.0, 1.0}},   // density, with wind
};

TEST(Fluid, MatchesMuJoCosPassiveForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  const auto random3 = [&](double scale) -> Vector3d { return Vector3d(unit(rng), unit(rng), unit(rng)) * scale; };
  double max_force_error = 0, max_torque_error = 0;
  for (const std::string& inertial : kInertials) {
    for (const FluidMedium& medium : kMedia) {
      const std::string path = testing::temp_file("fluid.xml", free_body_model(medium, inertial));
      char error[1024] = "";
      std::unique_ptr<mjModel, ModelDeleter> m(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
      ASSERT_TRUE(m) << error;
      std::unique_ptr<mjData, DataDeleter> d(mj_makeData(m.get()));
      ASSERT_EQ(m->nbody, 2);
      ASSERT_EQ(m->nv, 6);
      FluidMedium read;  // the medium as MuJoCo read it
      read.density = m->opt.density;
      read.viscosity = m->opt.viscosity;
      read.wind = Eigen::Map<const Vector3d>(m->opt.wind);
      EXPECT_EQ(read.density, medium.density);
      EXPECT_EQ(read.viscosity, medium.viscosity);
      EXPECT_EQ(read.wind, medium.wind);

      for (int sample = 0; sample < 20; ++sample) {
        // qpos: the body origin and its orientation; qvel: the origin's velocity (world) and
        // the angular velocity in the body frame.
        const Vector3d origin = random3(2);
        const Eigen::Quaterniond q = Eigen::Quaterniond::UnitRandom();
        const Vector3d origin_velocity = random3(3), body_angular = random3(5);
        for (int i = 0; i < 3; ++i) {
          d->qpos[i] = origin[i];
          d->qvel[i] = origin_velocity[i];
          d->qvel[3 + i] = body_angular[i];
        }
        d->qpos[3] = q.w(), d->qpos[4] = q.x(), d->qpos[5] = q.y(), d->qpos[6] = q.z();
        mj_forward(m.get(), d.get());

        // The same body as ours: centre of mass xipos, principal frame ximat; the centre's
        // velocity is the origin's plus w x (xipos - xpos).
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> xmat(d->xmat + 9);
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> ximat(d->ximat + 9);
        const Eigen::Map<const Vector3d> xpos(d->xpos + 3), xipos(d->xipos + 3);
        RigidBody body;
        body.mass = m->body_mass[1];
        body.inertia = Eigen::Map<const Vector3d>(m->body_inertia + 3);
        body.position = xipos;
        body.orientation = Eigen::Quaterniond(Eigen::Matrix3d(ximat)).normalized();
        body.angular_velocity = xmat * body_angular;
        body.linear_velocity = origin_velocity + body.angular_velocity.cross(xipos - xpos);
        // (and MuJoCo's own velocity of the centre agrees: [w; v] at xipos, world frame)
        mjtNum com_velocity[6];
        mj_objectVelocity(m.get(), d.get(), mjOBJ_BODY, 1, com_velocity, 0);
        ASSERT_LT((Eigen::Map<const Vector3d>(com_velocity) - body.angular_velocity).norm(), 1e-12);
        ASSERT_LT((Eigen::Map<const Vector3d>(com_velocity + 3) - body.linear_velocity).norm(), 1e-12);

        // MuJoCo's wrench from qfrc_passive (nothing else passive in the model): the translational
        // dofs take the force; the rotational ones, about the origin along the body's axes, take
        // xmat^T (torque + (xipos - xpos) x force).
        const Vector3d mujoco_force = Eigen::Map<const Vector3d>(d->qfrc_passive);
        const Vector3d mujoco_torque =
            xmat * Eigen::Map<const Vector3d>(d->qfrc_passive + 3) - (xipos - xpos).cross(mujoco_force);

        Vector3d force, torque;
        fluid_wrench(body, read, &force, &torque);
        const double force_error = (force - mujoco_force).norm() / mujoco_force.norm();
        const double torque_error = (torque - mujoco_torque).norm() / mujoco_torque.norm();
        EXPECT_LT(force_error, 1e-10) << inertial << " sample " << sample << "\n"
                                      << force.transpose() << "\n" << mujoco_force.transpose();
        EXPECT_LT(torque_error, 1e-10) << inertial << " sample " << sample << "\n"
                                       << torque.transpose() << "\n" << mujoco_torque.transpose();
        max_force_error = std::max(max_force_error, force_error);
        max_torque_error = std::max(max_torque_error, torque_error);
      }
    }
  }
  std::printf("largest relative differences: force %.2e, torque %.2e\n", max_force_error, max_torque_error);
}

TEST(Fluid, MuJoCoWithoutAMediumAppliesNothing) {
  // The reference's side of NoMediumNoWrench: our zero is MuJoCo's zero.
  const std::string path = testing::temp_file("still.xml", free_body_model(FluidMedium{}, kInertials[0]));
  char error[1024] = "";
  std::unique_ptr<mjModel, ModelDeleter> m(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
  ASSERT_TRUE(m) << error;
  std::unique_ptr<mjData, DataDeleter> d(mj_makeData(m.get()));
  for (int i = 0; i < 6; ++i) d->qvel[i] = i + 1.0;
  mj_forward(m.get(), d.get());
  for (int i = 0; i < 6; ++i) EXPECT_EQ(d->qfrc_passive[i], 0) << i;
}

#endif  // LDLPGS_HAVE_MUJOCO

}  // namespace
}  // namespace ldlpgs
