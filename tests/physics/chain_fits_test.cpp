// ChainFits: one fit per chain and pose, shared by the constraints on the chain. The reference is
// each constraint evaluated on its own (fitting its chain from its own last coordinates), which
// must give the same rows at every pose of a walk; and equal chains share a slot, others do not.
#include "ldlpgs/physics/chain_fits.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "tests/support/random_poses.h"

namespace ldlpgs {
namespace {

using Eigen::Vector3d;

// A static base and a body on three hinges whose axes do not meet (a hip), each with a range and
// a drive row, and the dofs' coordinates; plus a second set (a slide) between the same bodies.
Mechanism hip() {
  Mechanism m;
  m.bodies.resize(2);
  m.bodies[0].is_static = true;
  m.bodies[1].position = Vector3d(0.1, 0.2, 1.0);
  const std::vector<ChainJoint> joints = {{ChainJointType::hinge, Vector3d::UnitX(), Vector3d(0, 0.2, 1.0)},
                                          {ChainJointType::hinge, Vector3d::UnitY(), Vector3d(0.1, 0.25, 1.1)},
                                          {ChainJointType::hinge, Vector3d(0, 0.6, 0.8), Vector3d(0.1, 0.2, 0.9)}};
  const Constraint set = make_joint_set(0, m.bodies[0], 1, m.bodies[1], joints);
  m.constraints.push_back(set);
  for (int k = 0; k < 3; ++k) {
    m.constraints.push_back(make_coordinate_limit(set, k, -0.5, 0.5));
    m.constraints.push_back(make_dof_row(ConstraintType::dof_drive, set, k));
    DofDynamics dof;
    dof.coordinate = make_dof_row(ConstraintType::dof_drive, set, k);
    m.dofs.push_back(dof);
  }
  m.constraints.push_back(make_joint_set(0, m.bodies[0], 1, m.bodies[1], {{ChainJointType::slide, Vector3d::UnitZ()}}));
  return m;
}

TEST(ChainFits, EqualChainsBetweenTheSameBodiesShareOneSlot) {
  const Mechanism m = hip();
  EXPECT_EQ(ChainFits(m).chains(), 2);  // the hip's (its set, ranges, rows, dofs) and the slide's
}

// Along a walk of small random moves of the body, every constraint's rows from the shared fit
// equal its own evaluation, and each dof's state equals its own; the fit follows every move
// (a fit is current only at the pose it was made at).
TEST(ChainFits, SharedFitsGiveEachConstraintsOwnRowsAlongAWalk) {
  Mechanism m = hip();
  const std::vector<Constraint> own = m.constraints;  // their own coordinates, fitted apart
  std::vector<DofDynamics> own_dofs = m.dofs;
  ChainFits fits(m);
  std::mt19937 rng(17);
  RigidBody& b = m.bodies[1];
  for (int step = 0; step < 40; ++step) {
    b.position += testing::random_vector(rng, 0.02);
    b.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(0.05, testing::random_vector(rng, 1).normalized())) *
                     b.orientation).normalized();
    b.linear_velocity = testing::random_vector(rng, 1);
    b.angular_velocity = testing::random_vector(rng, 1);
    for (int pass = 0; pass < 2; ++pass) {  // the second pass reuses the fits
      for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
        const ConstraintRows shared = evaluate(m.constraints[k], m.bodies[0], b, fits.constraint(m, k));
        const ConstraintRows alone = evaluate(own[k], m.bodies[0], b);
        ASSERT_EQ(shared.rows, alone.rows);
        for (int r = 0; r < shared.rows; ++r) {
          EXPECT_NEAR(shared.c[r], alone.c[r], 1e-12) << "step " << step << ", constraint " << k << ", row " << r;
          for (int x = 0; x < 12; ++x)
            EXPECT_NEAR(shared.jacobian[12 * r + x], alone.jacobian[12 * r + x], 1e-10)
                << "step " << step << ", constraint " << k << ", row " << r;
        }
      }
      for (int d = 0; d < static_cast<int>(m.dofs.size()); ++d) {
        const DofState shared = dof_state(m.dofs[d], m.bodies, fits.dof(m, d));
        const DofState alone = dof_state(own_dofs[d], m.bodies);
        EXPECT_NEAR(shared.q, alone.q, 1e-12) << "step " << step << ", dof " << d;
        EXPECT_NEAR(shared.rate, alone.rate, 1e-10) << "step " << step << ", dof " << d;
      }
    }
  }
}

}  // namespace
}  // namespace ldlpgs
