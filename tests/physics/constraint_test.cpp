// Constraints: every type's Jacobian against central finite differences of its own c at random
// poses (the independent reference: c is differentiated by moving the bodies along their
// velocities), c = 0 where the builders put the bodies, the motions each joint allows (analytic:
// rotating about the hinge axis, sliding along the prismatic axis), full rank at the initial pose,
// the limits' nearer side, and the names.
#include "ldlpgs/physics/constraint.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <ostream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/random_poses.h"

namespace ldlpgs {

// Test names and failure messages print the type's name.
static void PrintTo(ConstraintType type, std::ostream* os) { *os << to_string(type); }

namespace {

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr ConstraintType kAllTypes[] = {ConstraintType::ball,          ConstraintType::hinge,
                                        ConstraintType::prismatic,     ConstraintType::cylindrical,
                                        ConstraintType::weld,          ConstraintType::rod,
                                        ConstraintType::rope,          ConstraintType::angular_limit,
                                        ConstraintType::positional_limit, ConstraintType::joint_set,
                                        ConstraintType::coordinate_limit, ConstraintType::dof_drive,
                                        ConstraintType::dof_motor};

bool is_limit(ConstraintType type) {
  return type == ConstraintType::angular_limit || type == ConstraintType::positional_limit ||
         type == ConstraintType::coordinate_limit;
}
bool has_chain(ConstraintType type) {
  return type == ConstraintType::joint_set || type == ConstraintType::coordinate_limit;
}

using testing::random_rotation;
using testing::random_vector;

RigidBody random_body(std::mt19937& rng, bool is_static = false) {
  RigidBody b;
  b.is_static = is_static;
  b.position = random_vector(rng, 2);
  b.orientation = random_rotation(rng);
  return b;
}

// Random velocities (zero for a static body, which never moves).
void set_random_velocities(std::mt19937& rng, RigidBody* b) {
  b->linear_velocity = b->is_static ? Vector3d::Zero() : random_vector(rng, 1);
  b->angular_velocity = b->is_static ? Vector3d::Zero() : random_vector(rng, 1);
}

// 1 to 3 joints as MuJoCo allows them on one body (a ball first and followed by slides only),
// with independent dofs (at most 3 rotational), random axes and anchors near b; world frame.
std::vector<ChainJoint> random_joints(std::mt19937& rng, const RigidBody& b) {
  std::uniform_int_distribution<int> kind(0, 2), count(1, 3);
  std::vector<ChainJoint> joints;
  int rotations = 0;
  bool ball = false;
  for (int k = 0, n = count(rng); k < n; ++k) {
    ChainJoint j;
    j.type = static_cast<ChainJointType>(kind(rng));  // hinge, slide, ball
    if (j.type == ChainJointType::ball && rotations > 0) j.type = ChainJointType::hinge;
    if (ball) j.type = ChainJointType::slide;
    rotations += j.type == ChainJointType::hinge ? 1 : j.type == ChainJointType::ball ? 3 : 0;
    ball = ball || j.type == ChainJointType::ball;
    j.anchor = b.position + random_vector(rng, 0.5);
    j.axis = random_vector(rng, 1).normalized();
    joints.push_back(j);
  }
  return joints;
}

// A constraint of `type` built by its make_* from random world data at the bodies' current pose
// (limits: range [-1, 1]; a coordinate_limit bounds the last joint of a random set).
Constraint random_constraint(ConstraintType type, std::mt19937& rng, const RigidBody& a, const RigidBody& b) {
  const Vector3d anchor = 0.5 * (a.position + b.position) + random_vector(rng, 1);
  const Vector3d axis = random_vector(rng, 3);  // not unit: the builders normalize
  switch (type) {
    case ConstraintType::ball: return make_ball(0, a, 1, b, anchor);
    case ConstraintType::hinge:
    case ConstraintType::prismatic:
    case ConstraintType::cylindrical:
    case ConstraintType::weld: return make_axial(type, 0, a, 1, b, anchor, axis);
    case ConstraintType::rod:
    case ConstraintType::rope:
      return make_distance(type, 0, a, 1, b, a.position + random_vector(rng, 1), b.position + random_vector(rng, 1));
    case ConstraintType::angular_limit: return make_angular_limit(0, a, 1, b, axis, -1, 1);
    case ConstraintType::positional_limit: return make_positional_limit(0, a, 1, b, anchor, axis, -1, 1);
    case ConstraintType::joint_set: return make_joint_set(0, a, 1, b, random_joints(rng, b));
    case ConstraintType::coordinate_limit: {  // of a hinge or a slide (a ball's cone: mjcf_test)
      std::vector<ChainJoint> joints = random_joints(rng, b);
      if (joints.back().type == ChainJointType::ball) joints.push_back({ChainJointType::slide, Vector3d::UnitZ(), b.position});
      const Constraint set = make_joint_set(0, a, 1, b, joints);
      return make_coordinate_limit(set, static_cast<int>(joints.size()) - 1, -1, 1);
    }
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: {  // on a random dof of a random set
      const Constraint set = make_joint_set(0, a, 1, b, random_joints(rng, b));
      return make_dof_row(type, set, std::uniform_int_distribution<int>(0, set.chain->dofs - 1)(rng));
    }
  }
  return {};
}

// The child's pose in the parent's frame after the chain's joints move by q (hinges and slides
// by q_k, a ball by the rotation vector q_k..q_k+2), composed as MuJoCo's kinematics do: each
// joint in the child's frame as the joints before it left it (written here apart from
// joint_set.cpp, from its definition in joint_set.h).
Eigen::Isometry3d chain_pose(const JointChain& chain, const std::vector<double>& q) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = chain.rotation;
  t.translation() = chain.translation;
  size_t k = 0;
  for (const ChainJoint& j : chain.joints) {
    Eigen::Isometry3d g = Eigen::Isometry3d::Identity();
    if (j.type == ChainJointType::slide) {
      g.translation() = q[k++] * j.axis;
    } else {
      const Vector3d theta = j.type == ChainJointType::hinge ? (q[k] * j.axis).eval() : Vector3d(q[k], q[k + 1], q[k + 2]);
      k += j.type == ChainJointType::hinge ? 1 : 3;
      g = Eigen::Translation3d(j.anchor) * AngleAxisd(theta.norm(), theta.norm() > 0 ? theta.normalized() : Vector3d::UnitX()) *
          Eigen::Translation3d(-j.anchor);
    }
    t = t * g;
  }
  return t;
}

// For the chain types: moves the bodies (the dynamic one, or b if both are) to a random pose the
// chain reaches, q in [-0.6, 0.6] per coordinate; the constraint's fit is walked there from q = 0
// in small steps, as stepping moves it (joint_set.h: the fit starts where the last one ended).
void move_along_chain(std::mt19937& rng, const Constraint& c, RigidBody* a, RigidBody* b) {
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<double> q(c.chain->dofs);
  for (double& x : q) x = u(rng);
  if (!a->is_static && !b->is_static) *a = random_body(rng);
  const Eigen::Isometry3d pose_a = Eigen::Translation3d(a->position) * a->orientation;
  const Eigen::Isometry3d pose_b = Eigen::Translation3d(b->position) * b->orientation;
  constexpr int kSteps = 10;
  for (int s = 1; s <= kSteps; ++s) {
    std::vector<double> qs = q;
    for (double& x : qs) x *= static_cast<double>(s) / kSteps;
    const Eigen::Isometry3d relative = chain_pose(*c.chain, qs);
    RigidBody* moved = b->is_static ? a : b;
    const Eigen::Isometry3d pose = b->is_static ? pose_b * relative.inverse() : pose_a * relative;
    moved->position = pose.translation();
    moved->orientation = Quaterniond(pose.linear());
    evaluate(c, *a, *b);
  }
}

// The body moved along its velocities for a time h: p += h v, q <- exp(h w) q (world-frame w).
RigidBody advanced(RigidBody b, double h) {
  b.position += h * b.linear_velocity;
  const double speed = b.angular_velocity.norm();
  if (speed > 0) b.orientation = Quaterniond(AngleAxisd(h * speed, b.angular_velocity / speed)) * b.orientation;
  return b;
}

// Row r of J times V = (v_a, w_a, v_b, w_b).
double row_times_velocity(const ConstraintRows& rows, int r, const RigidBody& a, const RigidBody& b) {
  Eigen::Matrix<double, 12, 1> v;
  v << a.linear_velocity, a.angular_velocity, b.linear_velocity, b.angular_velocity;
  return Eigen::Map<const Eigen::Matrix<double, 12, 1>>(rows.jacobian.data() + 12 * r).dot(v);
}

// Rotates the body rigidly about the world line through `point` along `axis` by `angle`.
void rotate_about(RigidBody* b, const Vector3d& point, const Vector3d& axis, double angle) {
  const AngleAxisd rotation(angle, axis.normalized());
  b->position = point + rotation * (b->position - point);
  b->orientation = Quaterniond(rotation) * b->orientation;
}

// The world axis and anchor the constraint was built with (a's frame, back in the world).
Vector3d world_axis(const Constraint& c, const RigidBody& a) { return a.orientation * c.frame_a.col(2); }
Vector3d world_anchor(const Constraint& c, const RigidBody& a) { return a.to_world(c.anchor_a); }

double max_abs_c(const ConstraintRows& rows) {
  double m = 0;
  for (int r = 0; r < rows.rows; ++r) m = std::max(m, std::abs(rows.c[r]));
  return m;
}

// ---- the finite-difference check ----

enum class Side { none, min, max };  // which side of a limit is the nearer one
struct JacobianCase {
  ConstraintType type;
  Side side;
};

std::string case_name(JacobianCase c) {
  std::string name = to_string(c.type);
  if (c.side == Side::min) name += "_min_side";
  if (c.side == Side::max) name += "_max_side";
  return name;
}
void PrintTo(JacobianCase c, std::ostream* os) { *os << case_name(c); }

class ConstraintJacobian : public ::testing::TestWithParam<JacobianCase> {};

// dc/dt = J V against the central difference (c(pose + h V) - c(pose - h V)) / (2h), h = 1e-6, at
// 20 random poses with both bodies dynamic and 10 with one static (5 each side), every pose away
// from the one the constraint was built at. Error measure: |J V - fd| / max(|J V|, 1). The poses
// (|p| <= 2, anchors within ~3 of the centres) and velocities (components in [-1, 1]) make the
// rates O(1) in m/s or rad/s, so the floor 1 is the rates' scale: the measure is relative where a
// rate is O(1) and absolute (1e-6 per second) where it nearly cancels, there the difference's
// rounding (~1e-16 |c| / h ~ 1e-10) would dominate a purely relative one. The truncation error
// is O(h^2 c''') ~ 1e-12. A wrong sign or a missing term shows as an O(1) error.
TEST_P(ConstraintJacobian, MatchesCentralFiniteDifferences) {
  const auto [type, side] = GetParam();
  std::mt19937 rng(1234 + static_cast<int>(type) * 10 + static_cast<int>(side));
  constexpr double h = 1e-6;
  constexpr int kPoses = 30;
  double worst = 0;
  for (int pose = 0; pose < kPoses; ++pose) {
    const bool a_static = pose >= 20 && pose < 25, b_static = pose >= 25;
    RigidBody a = random_body(rng, a_static), b = random_body(rng, b_static);
    Constraint c = random_constraint(type, rng, a, b);
    // Away from the initial pose: the dynamic bodies move to new random poses (a chain's to one
    // it reaches: its J is the derivative of its c there, joint_set.h).
    if (has_chain(type)) {
      move_along_chain(rng, c, &a, &b);
    } else {
      if (!a.is_static) a = random_body(rng);
      if (!b.is_static) b = random_body(rng);
    }
    set_random_velocities(rng, &a);
    set_random_velocities(rng, &b);
    if (side != Side::none) {
      // The range around the current value, 0.25 from the nearer end and 0.5 from the other.
      const double value = limit_value(c, a, b);
      c.min = value - (side == Side::min ? 0.25 : 0.5);
      c.max = value + (side == Side::min ? 0.5 : 0.25);
    }
    const ConstraintRows rows = evaluate(c, a, b);
    ASSERT_EQ(rows.rows, num_rows(c));
    const ConstraintRows plus = evaluate(c, advanced(a, h), advanced(b, h));
    const ConstraintRows minus = evaluate(c, advanced(a, -h), advanced(b, -h));
    for (int r = 0; r < rows.rows; ++r) {
      const double jv = row_times_velocity(rows, r, a, b);
      const double fd = (plus.c[r] - minus.c[r]) / (2 * h);
      const double error = std::abs(jv - fd) / std::max(std::abs(jv), 1.0);
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-6) << "pose " << pose << " row " << r << ": J V = " << jv << ", finite difference " << fd
                             << (a_static ? " (a static)" : "") << (b_static ? " (b static)" : "");
    }
    if (side != Side::none) {
      EXPECT_NEAR(rows.c[0], 0.25, 1e-12) << "pose " << pose << ": not the nearer side";
    }
  }
  std::ostringstream text;
  text << worst;
  RecordProperty("worst_error", text.str());
}

INSTANTIATE_TEST_SUITE_P(
    AllTypes, ConstraintJacobian,
    ::testing::Values(JacobianCase{ConstraintType::ball, Side::none}, JacobianCase{ConstraintType::hinge, Side::none},
                    JacobianCase{ConstraintType::prismatic, Side::none},
                    JacobianCase{ConstraintType::cylindrical, Side::none},
                    JacobianCase{ConstraintType::weld, Side::none}, JacobianCase{ConstraintType::rod, Side::none},
                    JacobianCase{ConstraintType::rope, Side::none},
                    JacobianCase{ConstraintType::angular_limit, Side::min},
                    JacobianCase{ConstraintType::angular_limit, Side::max},
                    JacobianCase{ConstraintType::positional_limit, Side::min},
                    JacobianCase{ConstraintType::positional_limit, Side::max},
                    JacobianCase{ConstraintType::joint_set, Side::none},
                    JacobianCase{ConstraintType::coordinate_limit, Side::min},
                    JacobianCase{ConstraintType::coordinate_limit, Side::max}),
    [](const ::testing::TestParamInfo<JacobianCase>& info) { return case_name(info.param); });

// Dof i's rate (MuJoCo's qvel) when the coordinates move at dq: dq_i for a hinge or a slide; for
// a ball, its child-frame angular velocity J_r(theta) dtheta (SO(3)'s right Jacobian).
double dof_rate(const JointChain& chain, const std::vector<double>& q, const std::vector<double>& dq, int dof) {
  int first = 0;
  for (const ChainJoint& j : chain.joints) {
    const int n = j.type == ChainJointType::ball ? 3 : 1;
    if (dof >= first + n) {
      first += n;
      continue;
    }
    if (n == 1) return dq[dof];
    const Vector3d theta(q[first], q[first + 1], q[first + 2]), rate(dq[first], dq[first + 1], dq[first + 2]);
    const double angle = theta.norm();
    Eigen::Matrix3d k;
    k << 0, -theta.z(), theta.y(), theta.z(), 0, -theta.x(), -theta.y(), theta.x(), 0;
    const Eigen::Matrix3d right = Eigen::Matrix3d::Identity() - (1 - std::cos(angle)) / (angle * angle) * k +
                                  (angle - std::sin(angle)) / (angle * angle * angle) * k * k;
    return (right * rate)[dof - first];
  }
  return 0;
}

// A dof_drive's or dof_motor's row is the rate of its dof's coordinate on every motion the joints
// allow: b moved along the chain, q* + t dq, its velocity from the poses at t = +-h (central
// differences, h = 1e-5), J V = dq_dof to 1e-8. (Off the joints' motions the row is S^+'s least
// squares rate, which the joints' own rows make moot.) c is always 0.
TEST(DofRows, RateIsTheDofsCoordinateRateOnTheJointsMotions) {
  std::mt19937 rng(4321);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  constexpr double h = 1e-5;
  for (int pose = 0; pose < 30; ++pose) {
    RigidBody a = random_body(rng, pose >= 25), b = random_body(rng);
    const ConstraintType type = pose % 2 ? ConstraintType::dof_motor : ConstraintType::dof_drive;
    Constraint c = random_constraint(type, rng, a, b);
    const JointChain& chain = *c.chain;
    std::vector<double> q(chain.dofs), dq(chain.dofs);
    for (int k = 0; k < chain.dofs; ++k) {
      q[k] = u(rng);
      dq[k] = u(rng);
    }
    const Eigen::Isometry3d pose_a = Eigen::Translation3d(a.position) * a.orientation;
    const auto pose_b = [&](double t) {
      std::vector<double> qt(q);
      for (int k = 0; k < chain.dofs; ++k) qt[k] += t * dq[k];
      return Eigen::Isometry3d(pose_a * chain_pose(chain, qt));
    };
    for (int s = 1; s <= 10; ++s) {  // the fit walked there, as stepping moves it
      const Eigen::Isometry3d p = Eigen::Translation3d(a.position) * a.orientation *
                                  chain_pose(chain, [&] { std::vector<double> qs(q); for (double& x : qs) x *= s / 10.0; return qs; }());
      b.position = p.translation();
      b.orientation = Quaterniond(p.linear());
      evaluate(c, a, b);
    }
    const Eigen::Isometry3d plus = pose_b(h), minus = pose_b(-h);
    a.linear_velocity = a.angular_velocity = Vector3d::Zero();
    b.linear_velocity = (plus.translation() - minus.translation()) / (2 * h);
    const AngleAxisd turn(Eigen::Matrix3d(plus.linear() * minus.linear().transpose()));
    b.angular_velocity = turn.angle() * turn.axis() / (2 * h);
    const ConstraintRows rows = evaluate(c, a, b);
    ASSERT_EQ(rows.rows, 1);
    EXPECT_EQ(rows.c[0], 0.0);
    EXPECT_NEAR(row_times_velocity(rows, 0, a, b), dof_rate(chain, q, dq, c.joint), 1e-8) << "pose " << pose << ", dof " << c.joint;
  }
}

// A fit's rates are S^+ of its twists, against Eigen's complete orthogonal decomposition (the
// reference): by the normal equations on independent joints (random sets), and least-norm on
// redundant ones, where the normal equations are refused: two hinges on one axis and anchor, a
// hinge beside a ball, and hinges 1e-7 rad apart (where they would be 2e5 off).
TEST(DofRows, RatesAreThePseudoInverseOfTheTwistsAlsoWhereJointsAreRedundant) {
  std::mt19937 rng(99);
  const auto expect_pseudo_inverse = [](const ChainFit& fit, const std::string& what) {
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Eigen::MatrixXd(fit.twists));
    cod.setThreshold(1e-10);
    const Eigen::MatrixXd reference = cod.pseudoInverse();
    ASSERT_EQ(fit.rates.rows(), reference.rows()) << what;
    EXPECT_LT((Eigen::MatrixXd(fit.rates) - reference).cwiseAbs().maxCoeff(), 1e-8 * (1 + reference.cwiseAbs().maxCoeff()))
        << what;
  };
  for (int pose = 0; pose < 20; ++pose) {
    const RigidBody a = random_body(rng), b = random_body(rng);
    const Constraint set = make_joint_set(0, a, 1, b, random_joints(rng, b));
    ChainCoordinates q{};
    expect_pseudo_inverse(fit_chain(*set.chain, a, b, &q), "random set " + std::to_string(pose));
  }
  const RigidBody a = random_body(rng), b = random_body(rng);
  const Vector3d p = b.position, z = Vector3d::UnitZ(), x = Vector3d::UnitX();
  const std::vector<std::pair<std::string, std::vector<ChainJoint>>> redundant = {
      {"two hinges on one axis", {{ChainJointType::hinge, z, p}, {ChainJointType::hinge, z, p}, {ChainJointType::slide, x, p}}},
      {"hinges 1e-7 rad apart",
       {{ChainJointType::hinge, z, p}, {ChainJointType::hinge, Vector3d(1e-7, 0, 1).normalized(), p}}},
      {"ball and hinge", {{ChainJointType::hinge, x, p}, {ChainJointType::ball, z, p}}}};
  for (const auto& [what, joints] : redundant) {
    const Constraint set = make_joint_set(0, a, 1, b, joints);
    ChainCoordinates q{};
    expect_pseudo_inverse(fit_chain(*set.chain, a, b, &q), what);
  }
}

// ---- per-type claims over all types ----

class EveryType : public ::testing::TestWithParam<ConstraintType> {};

std::string type_name(const ::testing::TestParamInfo<ConstraintType>& info) { return to_string(info.param); }

// Right after make_*: an equality's c is 0, a rope built at its current length is taut (c = 0),
// a limit's value is 0 (the initial pose is its zero).
TEST_P(EveryType, ZeroAtTheInitialPose) {
  const ConstraintType type = GetParam();
  std::mt19937 rng(77 + static_cast<int>(type));
  for (int trial = 0; trial < 20; ++trial) {
    const RigidBody a = random_body(rng, trial == 0), b = random_body(rng);
    const Constraint c = random_constraint(type, rng, a, b);
    const ConstraintRows rows = evaluate(c, a, b);
    if (is_limit(type)) {
      EXPECT_NEAR(limit_value(c, a, b), 0, 1e-12) << "trial " << trial;
    } else {
      for (int r = 0; r < rows.rows; ++r) EXPECT_NEAR(rows.c[r], 0, 1e-12) << "trial " << trial << " row " << r;
    }
  }
}

// The talk's regularity: at the initial pose J has full row rank d, and so has each body's half
// (the solver keeps only the dynamic body's columns when the other is static). Measured by the
// singular values: sigma_min / sigma_max > 1e-3 (the anchors and axes are O(1), so a rank
// deficiency would show as a ratio ~1e-16).
TEST_P(EveryType, FullRankAtTheInitialPose) {
  const ConstraintType type = GetParam();
  std::mt19937 rng(99 + static_cast<int>(type));
  for (int trial = 0; trial < 20; ++trial) {
    const RigidBody a = random_body(rng), b = random_body(rng);
    const Constraint c = random_constraint(type, rng, a, b);
    const ConstraintRows rows = evaluate(c, a, b);
    const Eigen::MatrixXd j =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 12, Eigen::RowMajor>>(rows.jacobian.data(), rows.rows, 12);
    for (int half = 0; half < 3; ++half) {  // all 12 columns, a's 6, b's 6
      const Eigen::MatrixXd part = half == 0 ? j : j.middleCols(6 * (half - 1), 6);
      const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(part).singularValues();
      EXPECT_GT(sigma.minCoeff(), 1e-3 * sigma.maxCoeff()) << "trial " << trial << " columns " << half;
    }
  }
}

// Moving both bodies by one rigid motion changes nothing: c (and a limit's value) stays 0.
TEST_P(EveryType, InvariantUnderACommonRigidMotion) {
  const ConstraintType type = GetParam();
  std::mt19937 rng(111 + static_cast<int>(type));
  for (int trial = 0; trial < 20; ++trial) {
    RigidBody a = random_body(rng), b = random_body(rng);
    const Constraint c = random_constraint(type, rng, a, b);
    const Vector3d point = random_vector(rng, 2), axis = random_vector(rng, 1), shift = random_vector(rng, 2);
    const double angle = std::uniform_real_distribution<double>(-3, 3)(rng);
    for (RigidBody* body : {&a, &b}) {
      rotate_about(body, point, axis, angle);
      body->position += shift;
    }
    if (is_limit(type)) {
      EXPECT_NEAR(limit_value(c, a, b), 0, 1e-12) << "trial " << trial;
    } else {
      EXPECT_LT(max_abs_c(evaluate(c, a, b)), 1e-12) << "trial " << trial;
    }
  }
}

// Each row is radians or metres as the table in constraint.h says (ball and slide rows metres,
// dot rows and the angle radians).
TEST_P(EveryType, RowKinds) {
  const ConstraintType type = GetParam();
  std::vector<bool> expected;
  switch (type) {
    case ConstraintType::ball: expected = {false, false, false}; break;
    case ConstraintType::hinge: expected = {false, false, false, true, true}; break;
    case ConstraintType::prismatic: expected = {false, false, true, true, true}; break;
    case ConstraintType::cylindrical: expected = {false, false, true, true}; break;
    case ConstraintType::weld: expected = {false, false, false, true, true, true}; break;
    case ConstraintType::rod:
    case ConstraintType::rope:
    case ConstraintType::positional_limit: expected = {false}; break;
    case ConstraintType::angular_limit: expected = {true}; break;
    case ConstraintType::joint_set:  // angular rows first (joint_set.h), counted below
    case ConstraintType::coordinate_limit:
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: break;
  }
  std::mt19937 rng(5);
  const RigidBody a = random_body(rng), b = random_body(rng);
  const Constraint c = random_constraint(type, rng, a, b);
  if (type == ConstraintType::joint_set) {
    expected.assign(c.chain->angular_rows, true);
    expected.resize(c.chain->rows(), false);
  }
  if (type == ConstraintType::coordinate_limit) expected = {c.chain->joints[c.joint].type != ChainJointType::slide};
  if (type == ConstraintType::dof_drive || type == ConstraintType::dof_motor) expected = {dof_is_angular(*c.chain, c.joint)};
  const ConstraintRows rows = evaluate(c, a, b);
  ASSERT_EQ(rows.rows, static_cast<int>(expected.size()));
  for (int r = 0; r < rows.rows; ++r) EXPECT_EQ(rows.angular[r], expected[r]) << "row " << r;
}

// evaluate fills num_rows(constraint) rows, num_rows(type) for the types of fixed size.
TEST_P(EveryType, EvaluateFillsNumRows) {
  const ConstraintType type = GetParam();
  std::mt19937 rng(6);
  const RigidBody a = random_body(rng), b = random_body(rng);
  const Constraint c = random_constraint(type, rng, a, b);
  EXPECT_EQ(evaluate(c, a, b).rows, num_rows(c));
  if (type != ConstraintType::joint_set) {
    EXPECT_EQ(num_rows(c), num_rows(type));
  }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, EveryType, ::testing::ValuesIn(kAllTypes), type_name);

// ---- the table and the names ----

TEST(Constraint, RowCountsAndKindsFollowTheTable) {
  EXPECT_EQ(num_rows(ConstraintType::ball), 3);
  EXPECT_EQ(num_rows(ConstraintType::hinge), 5);
  EXPECT_EQ(num_rows(ConstraintType::prismatic), 5);
  EXPECT_EQ(num_rows(ConstraintType::cylindrical), 4);
  EXPECT_EQ(num_rows(ConstraintType::weld), 6);
  EXPECT_EQ(num_rows(ConstraintType::rod), 1);
  EXPECT_EQ(num_rows(ConstraintType::rope), 1);
  EXPECT_EQ(num_rows(ConstraintType::angular_limit), 1);
  EXPECT_EQ(num_rows(ConstraintType::positional_limit), 1);
  EXPECT_EQ(num_rows(ConstraintType::coordinate_limit), 1);
  for (ConstraintType t : kAllTypes) {
    if (t != ConstraintType::joint_set) {
      EXPECT_LE(num_rows(t), kMaxConstraintRows) << to_string(t);
    }
  }
  for (ConstraintType t : {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                           ConstraintType::cylindrical, ConstraintType::weld, ConstraintType::rod,
                           ConstraintType::joint_set, ConstraintType::dof_drive})
    EXPECT_TRUE(is_equality(t)) << to_string(t);
  for (ConstraintType t : {ConstraintType::rope, ConstraintType::angular_limit, ConstraintType::positional_limit,
                           ConstraintType::coordinate_limit, ConstraintType::dof_motor})
    EXPECT_FALSE(is_equality(t)) << to_string(t);
}

TEST(Constraint, NamesAsScenesSpellThem) {
  const char* names[] = {"ball", "hinge",         "prismatic",        "cylindrical", "weld",
                         "rod",  "rope",          "angular_limit",    "positional_limit",
                         "joint_set", "coordinate_limit", "dof_drive", "dof_motor"};
  static_assert(std::size(names) == std::size(kAllTypes));
  for (size_t i = 0; i < std::size(kAllTypes); ++i) EXPECT_STREQ(to_string(kAllTypes[i]), names[i]);
}

TEST(Constraint, NameRoundTrip) {
  for (ConstraintType t : kAllTypes) {
    ConstraintType parsed = t == ConstraintType::ball ? ConstraintType::weld : ConstraintType::ball;
    ASSERT_TRUE(constraint_type_from_string(to_string(t), &parsed)) << to_string(t);
    EXPECT_EQ(parsed, t) << to_string(t);
  }
}

TEST(Constraint, UnknownNamesRejected) {
  for (const char* bad : {"hinj", "", "Ball", "ball ", "angular-limit", "hinge2"}) {
    ConstraintType parsed = ConstraintType::rope;
    EXPECT_FALSE(constraint_type_from_string(bad, &parsed)) << '"' << bad << '"';
    EXPECT_EQ(parsed, ConstraintType::rope) << "changed on failure: \"" << bad << '"';
  }
}

// ---- the motions each joint allows and removes (analytic) ----

struct Built {
  RigidBody a, b;
  Constraint c;
};
Built build(ConstraintType type, std::mt19937& rng) {
  Built x{random_body(rng), random_body(rng), {}};
  x.c = random_constraint(type, rng, x.a, x.b);
  return x;
}

// A unit vector perpendicular to `axis`, random.
Vector3d random_perpendicular(std::mt19937& rng, const Vector3d& axis) {
  const Vector3d n = axis.normalized();
  const Vector3d v = random_vector(rng, 1);
  return (v - v.dot(n) * n).normalized();
}

TEST(Constraint, HingeAllowsRotationAboutItsAxisOnly) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::hinge, rng);
    const Vector3d anchor = world_anchor(x.c, x.a), axis = world_axis(x.c, x.a);
    for (double angle : {0.3, -1.2, 2.5, 3.1}) {
      RigidBody b = x.b;
      rotate_about(&b, anchor, axis, angle);
      EXPECT_LT(max_abs_c(evaluate(x.c, x.a, b)), 1e-12) << "trial " << trial << " angle " << angle;
      // About a perpendicular axis the axes separate by the angle: the dot rows see sin(0.5).
      b = x.b;
      rotate_about(&b, anchor, random_perpendicular(rng, axis), 0.5);
      const ConstraintRows r = evaluate(x.c, x.a, b);
      EXPECT_NEAR(std::hypot(r.c[3], r.c[4]), std::sin(0.5), 1e-12) << "trial " << trial;
    }
  }
}

TEST(Constraint, PrismaticAllowsSlideAlongItsAxisOnly) {
  std::mt19937 rng(22);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::prismatic, rng);
    const Vector3d axis = world_axis(x.c, x.a).normalized();
    for (double s : {0.5, -2.0, 7.0}) {
      RigidBody b = x.b;
      b.position += s * axis;
      EXPECT_LT(max_abs_c(evaluate(x.c, x.a, b)), 1e-12) << "trial " << trial << " slide " << s;
      // Across the axis the slide rows see the offset's length.
      b = x.b;
      b.position += s * random_perpendicular(rng, axis);
      const ConstraintRows r = evaluate(x.c, x.a, b);
      EXPECT_NEAR(std::hypot(r.c[0], r.c[1]), std::abs(s), 1e-12) << "trial " << trial;
    }
    // Rotation about the axis is removed: u_a . w_b = -sin(angle).
    RigidBody b = x.b;
    rotate_about(&b, world_anchor(x.c, x.a), axis, 0.4);
    EXPECT_NEAR(evaluate(x.c, x.a, b).c[4], -std::sin(0.4), 1e-12) << "trial " << trial;
  }
}

TEST(Constraint, CylindricalAllowsSlideAndRotationAlongItsAxis) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::cylindrical, rng);
    const Vector3d anchor = world_anchor(x.c, x.a), axis = world_axis(x.c, x.a).normalized();
    RigidBody b = x.b;
    rotate_about(&b, anchor, axis, 1.7);
    b.position += -1.3 * axis;
    EXPECT_LT(max_abs_c(evaluate(x.c, x.a, b)), 1e-12) << "trial " << trial;
  }
}

TEST(Constraint, WeldRemovesRotationAboutEveryAxis) {
  std::mt19937 rng(24);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::weld, rng);
    const Vector3d anchor = world_anchor(x.c, x.a);
    RigidBody b = x.b;
    rotate_about(&b, anchor, random_vector(rng, 1), 0.5);
    const ConstraintRows r = evaluate(x.c, x.a, b);
    // The ball rows stay 0 (b turned about the anchor); the three angle rows do not all vanish:
    // for a small rotation they are the rotation vector's components (here of length 0.5).
    EXPECT_LT(std::abs(r.c[0]) + std::abs(r.c[1]) + std::abs(r.c[2]), 1e-12);
    EXPECT_GT(std::sqrt(r.c[3] * r.c[3] + r.c[4] * r.c[4] + r.c[5] * r.c[5]), 0.3) << "trial " << trial;
  }
}

TEST(Constraint, BallAllowsEveryRotationAboutItsAnchor) {
  std::mt19937 rng(25);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::ball, rng);
    const Vector3d anchor = world_anchor(x.c, x.a);
    RigidBody a = x.a, b = x.b;
    rotate_about(&a, anchor, random_vector(rng, 1), 2.0);
    rotate_about(&b, anchor, random_vector(rng, 1), -1.0);
    EXPECT_LT(max_abs_c(evaluate(x.c, a, b)), 1e-12) << "trial " << trial;
    // A translation of b by t shows as c = -t (c = anchor on a - anchor on b).
    const Vector3d t = random_vector(rng, 1);
    b.position += t;
    const ConstraintRows r = evaluate(x.c, a, b);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.c[k], -t[k], 1e-12) << "trial " << trial;
  }
}

// Rod and rope at a known distance: anchors at the centres 5 m apart (3-4-5), length 4.
TEST(Constraint, RodAndRopeMeasureTheDistance) {
  RigidBody a, b;
  a.orientation = Quaterniond(AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()));
  b.position = Vector3d(3, 4, 0);
  const ConstraintRows rod = evaluate(make_distance(ConstraintType::rod, 0, a, 1, b, a.position, b.position, 4), a, b);
  const ConstraintRows rope = evaluate(make_distance(ConstraintType::rope, 0, a, 1, b, a.position, b.position, 4), a, b);
  EXPECT_NEAR(rod.c[0], 1, 1e-15);    // |d| - length: too long
  EXPECT_NEAR(rope.c[0], -1, 1e-15);  // length - |d|: overstretched, violated
  // The rod row pulls b towards a along n = (0.6, 0.8, 0): v_b coefficient n.
  EXPECT_NEAR(rod.jacobian[6], 0.6, 1e-15);
  EXPECT_NEAR(rod.jacobian[7], 0.8, 1e-15);
  EXPECT_NEAR(rope.jacobian[6], -0.6, 1e-15);
  // length < 0: the current distance.
  EXPECT_DOUBLE_EQ(make_distance(ConstraintType::rope, 0, a, 1, b, a.position, b.position).length, 5);
}

// Rotating b about the limit's axis by phi (within (-pi, pi)) moves the angle to phi, rotating a
// moves it to -phi (the angle is b's relative to a).
TEST(Constraint, AngularLimitMeasuresTheHingeAngle) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::angular_limit, rng);
    const Vector3d axis = world_axis(x.c, x.a);
    for (double phi : {0.2, -0.9, 2.0, -3.0}) {
      RigidBody b = x.b;
      rotate_about(&b, random_vector(rng, 2), axis, phi);  // any point: the angle ignores translation
      EXPECT_NEAR(limit_value(x.c, x.a, b), phi, 1e-12) << "trial " << trial;
      // Rotating a instead turns the angle the other way.
      RigidBody a = x.a;
      rotate_about(&a, random_vector(rng, 2), axis, phi);
      EXPECT_NEAR(limit_value(x.c, a, x.b), -phi, 1e-12) << "trial " << trial;
    }
  }
}

TEST(Constraint, PositionalLimitMeasuresTheSlide) {
  std::mt19937 rng(32);
  for (int trial = 0; trial < 10; ++trial) {
    const Built x = build(ConstraintType::positional_limit, rng);
    const Vector3d axis = world_axis(x.c, x.a).normalized();
    for (double s : {0.4, -1.5}) {
      RigidBody b = x.b;
      b.position += s * axis + 0.7 * random_perpendicular(rng, axis);  // across the axis: not counted
      EXPECT_NEAR(limit_value(x.c, x.a, b), s, 1e-12) << "trial " << trial;
    }
  }
}

// The row is the nearer end written as c >= 0: value - min inside near min, max - value near max,
// negative beyond either end; the Jacobian's sign follows (d c / d value = +1 near min, -1 near max).
TEST(Constraint, LimitRowIsTheNearerEnd) {
  std::mt19937 rng(33);
  const Built x = build(ConstraintType::angular_limit, rng);
  const Vector3d axis = world_axis(x.c, x.a);
  struct Expect {
    double value, c, sign;
  };
  // range [-0.5, 1.0], midpoint 0.25
  for (const Expect& e : {Expect{-0.8, -0.3, 1}, Expect{-0.2, 0.3, 1}, Expect{0.2, 0.7, 1}, Expect{0.3, 0.7, -1},
                          Expect{0.9, 0.1, -1}, Expect{1.4, -0.4, -1}}) {
    Constraint c = x.c;
    c.min = -0.5;
    c.max = 1.0;
    RigidBody b = x.b;
    rotate_about(&b, b.position, axis, e.value);
    b.angular_velocity = axis.normalized();  // d value / dt = 1
    const ConstraintRows r = evaluate(c, x.a, b);
    EXPECT_NEAR(r.c[0], e.c, 1e-12) << "value " << e.value;
    EXPECT_NEAR(row_times_velocity(r, 0, x.a, b), e.sign, 1e-12) << "value " << e.value;
  }
}

}  // namespace
}  // namespace ldlpgs
