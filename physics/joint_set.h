#pragma once
// A set of joints on one body, composed in order as MuJoCo composes a body's hinges, slides and
// balls (mj_kinematics): in the parent's frame, the child's frame is
//   F(q) = B G_1(q_1) G_2(q_2) ... G_n(q_n),
// B the child's pose at q = 0 and each G_k a motion in the child's frame as the joints before it
// left it (so joint 1's axis is fixed in the parent, the last joint's in the child):
//   hinge  rotation by q about the unit axis a through the anchor p   twist (a; p x a)
//   slide  translation by q along a                                   twist (0; a)
//   ball   rotation exp(theta) about p (theta a rotation vector)      twists (e_i; p x e_i)
// Twists are (w; v) in the child's frame: a point x moves at w x x + v.
//
// The set allows the motions its twists span and the joint_set constraint (constraint.h) removes
// the rest, whatever the joints. At the current relative pose T the coordinates q* minimise
// |r(q)|^2, r = (log dR; dp) of dT = F(q)^-1 T (Gauss-Newton, from the last q*: the coordinates
// stay continuous, a hinge can turn past pi). The rows are covectors y with S(q*)^T y = 0, S the
// twists moved to the child's frame, and c = y . r:
//   angular rows        (u; 0): u across the rotations the twists span (w_k, the twists' w parts)
//   translational rows  (x; t): t across the translations that no rotation brings, x the lever
//                       arm that cancels the rest: with A = S_w S_w^T, C = S_v S_w^T and K = A^+,
//                       dof k brings the pure translation d_k = v_k - C K w_k, and x = -K C^T t
// so each row is in radians or metres. Their counts are the ranks at q = 0. The rows must be a
// continuous function of the pose (a step's impulses warm-start the next's, and the projection
// pairs one pose's J with another's c), so u and t are built from named twists, not from an
// eigenbasis: with r independent rotations and s pure translations,
//   r = 0: u = the child's axes      r = 1: u = two fixed axes across w_k1 (constant: all turns
//   r = 2: u = w_k1 x w_k2 (unit)      are about w_k1)                       r = 3: none
//   s = 0: t = the child's axes      s = 1: t = g and d x g across d = d_j1 (g fixed at q = 0)
//   s = 2: t = d_j1 x d_j2 (unit)    s = 3: none
// k1, k2, j1, j2 the dofs whose twists span best at q = 0. dc/dt = y . V_rel where r = 0, V_rel
// the child's twist relative to its parent: c holds where the joints can reach, and J is its
// derivative there.
//
// A coordinate's rate is its row of S^+ applied to V_rel (hinge, slide: q_k; ball: the angle
// |theta|, whose rate is theta/|theta| . its rates): a range becomes an inequality row
// (coordinate_limit) in MuJoCo's own coordinate.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "ldlpgs/physics/body.h"

namespace ldlpgs {

enum class ChainJointType { hinge, slide, ball };

struct ChainJoint {
  ChainJointType type = ChainJointType::hinge;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      // unit (hinge, slide)
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();     // the point turned about (hinge, ball)
};

constexpr int kMaxChainDofs = 6;  // MuJoCo allows a body 6
using ChainCoordinates = std::array<double, kMaxChainDofs>;  // q, in the joints' order (a ball: 3)
using Twist = Eigen::Matrix<double, 6, 1>;                   // (w; v), or a covector of one
using ChainTwists = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxChainDofs>;

struct JointChain {
  std::vector<ChainJoint> joints;  // in the child's frame (size: the body's joints)
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // B: the child's frame in the parent's, q = 0
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  // The chain's parent and child frames are a's and b's frames moved to these points (a's and
  // b's frames): 0 but where body shattering moved a body's frame under the chain.
  Eigen::Vector3d parent_origin = Eigen::Vector3d::Zero(), child_origin = Eigen::Vector3d::Zero();
  int dofs = 0;                     // hinges and slides 1, balls 3 (<= kMaxChainDofs)
  int angular_rows = 0, translational_rows = 0;  // the rows' counts, fixed at q = 0
  int rows() const { return angular_rows + translational_rows; }
  // The rows' construction (above): the dofs named, and the fixed axes (child's frame) across the
  // one rotation (r = 1) and across the one pure translation (s = 1).
  int rotation_dofs[2] = {-1, -1}, translation_dofs[2] = {-1, -1};
  Eigen::Vector3d rotation_reference = Eigen::Vector3d::UnitX(), translation_reference = Eigen::Vector3d::UnitX();
};

// The chain of `joints`, given in the world at the bodies' current pose (where q = 0), between
// the parent a and the child b (b's frame is the child's frame). At most kMaxChainDofs; axes
// nonzero (programmer errors: the MJCF converter checks what it passes).
std::shared_ptr<const JointChain> make_joint_chain(const RigidBody& a, const RigidBody& b,
                                                   const std::vector<ChainJoint>& world_joints);

// The same chain on a body whose frame moved by `shift` in its own frame (the parent if `parent`,
// else the child): what body shattering needs (shatter.h). The rows stay the same rows.
std::shared_ptr<const JointChain> shift_chain(const JointChain& chain, bool parent, const Eigen::Vector3d& shift);

// The chain fitted at the bodies' pose: q* (searched from *q, which receives it), the residual r,
// the twists S at q*, and S^+ (row i: the covector of dof i's rate).
struct ChainFit {
  ChainCoordinates q{};  // q*
  Twist residual = Twist::Zero();
  ChainTwists twists;
  Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxChainDofs, 6> rates;
};
ChainFit fit_chain(const JointChain& chain, const RigidBody& a, const RigidBody& b, ChainCoordinates* q);

// The rows' covectors (columns, angular rows first), at most 6.
using ChainCovectors = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;
ChainCovectors chain_row_covectors(const JointChain& chain, const ChainFit& fit);

// Joint k's coordinate at q (hinge, slide: q_k from q = 0; ball: its angle) and the covector of
// its rate.
double chain_coordinate(const JointChain& chain, const ChainFit& fit, int joint, Twist* covector);

// Dof i's coordinate q_i and the covector of its rate, MuJoCo's qvel entry (a ball's three dofs:
// its rotation vector and the child-frame angular velocity, as the ball composes on the right).
double chain_dof(const JointChain& chain, const ChainFit& fit, int dof, Twist* covector);
// Dof i turns (a hinge's or a ball's: radians) rather than slides (metres).
bool dof_is_angular(const JointChain& chain, int dof);

// A covector y (child's frame) of the relative twist as a row of 12 over [v_a w_a v_b w_b]
// (world): y . V_rel with V_rel = (R_b^T (w_b - w_a); R_b^T (v_b + w_b x (o - p_b) - v_a -
// w_a x (o - p_a))), o the chain's child origin in the world.
void chain_jacobian_row(const JointChain& chain, const Twist& covector, const RigidBody& a, const RigidBody& b,
                        double* row12);

}  // namespace ldlpgs
