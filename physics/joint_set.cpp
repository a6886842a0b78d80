// A body's joints as one chain (joint_set.h): its kinematics, the Gauss-Newton fit of its
// coordinates to a relative pose, and the rows that remove what the chain does not allow.
#include "ldlpgs/physics/joint_set.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/SVD>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace ldlpgs {

namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// x -> rotation x + translation
struct Motion {
  Matrix3d rotation = Matrix3d::Identity();
  Vector3d translation = Vector3d::Zero();
};

Motion compose(const Motion& x, const Motion& y) {
  return {x.rotation * y.rotation, x.rotation * y.translation + x.translation};
}

int joint_dofs(const ChainJoint& j) { return j.type == ChainJointType::ball ? 3 : 1; }

Quaterniond from_rotation_vector(const Vector3d& theta) {
  const double angle = theta.norm();
  if (angle == 0) return Quaterniond::Identity();
  return Quaterniond(Eigen::AngleAxisd(angle, theta / angle));
}

// log: the rotation vector of q, angle in [0, pi] (accurate near 0: atan2 of the vector part).
Vector3d rotation_vector(Quaterniond q) {
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double n = q.vec().norm();
  if (n == 0) return Vector3d::Zero();
  return q.vec() * (2 * std::atan2(n, q.w()) / n);
}

// G_k(q_k): the joint's motion in the frame the joints before it left.
Motion joint_motion(const ChainJoint& j, const double* q) {
  Motion m;
  switch (j.type) {
    case ChainJointType::hinge:
      m.rotation = Eigen::AngleAxisd(q[0], j.axis).toRotationMatrix();
      m.translation = j.anchor - m.rotation * j.anchor;
      break;
    case ChainJointType::slide: m.translation = q[0] * j.axis; break;
    case ChainJointType::ball:
      m.rotation = from_rotation_vector(Vector3d(q[0], q[1], q[2])).toRotationMatrix();
      m.translation = j.anchor - m.rotation * j.anchor;
      break;
  }
  return m;
}

// The joint's twists (columns) in the frame after its own motion: (a; p x a), (0; a) or
// (e_i; p x e_i). A hinge's or ball's motion about p commutes with its own increment, so
// G(q + dq) = G(q) exp(xi dq) (a ball's increment right-multiplied: q <- q exp(dq)).
void joint_twists(const ChainJoint& j, Eigen::Matrix<double, 6, 3>* xi) {
  switch (j.type) {
    case ChainJointType::hinge: xi->col(0) << j.axis, j.anchor.cross(j.axis); break;
    case ChainJointType::slide: xi->col(0) << Vector3d::Zero(), j.axis; break;
    case ChainJointType::ball:
      for (int i = 0; i < 3; ++i) xi->col(i) << Vector3d::Unit(i), j.anchor.cross(Vector3d::Unit(i));
      break;
  }
}

// F(q) and the twists S in the child's frame: joint k's twists moved through the motions after
// it, P_k = G_{k+1} ... G_n: Ad_{P_k^-1} (w; v) = (R^T w; R^T (v + w x t)) for P_k = (R, t).
Motion forward(const JointChain& chain, const ChainCoordinates& q, ChainTwists* twists) {
  twists->resize(6, chain.dofs);
  Motion after;  // P_k
  int dof = chain.dofs;
  for (int k = static_cast<int>(chain.joints.size()) - 1; k >= 0; --k) {
    const ChainJoint& j = chain.joints[k];
    const int n = joint_dofs(j);
    dof -= n;
    Eigen::Matrix<double, 6, 3> xi;
    joint_twists(j, &xi);
    for (int i = 0; i < n; ++i) {
      const Vector3d w = xi.col(i).head<3>(), v = xi.col(i).tail<3>();
      twists->col(dof + i) << after.rotation.transpose() * w,
          after.rotation.transpose() * (v + w.cross(after.translation));
    }
    after = compose(joint_motion(j, q.data() + dof), after);
  }
  return compose(Motion{chain.rotation, chain.translation}, after);
}

// r = (log dR; dp) of dT = F^-1 T.
Twist residual(const Motion& f, const Motion& t) {
  const Matrix3d dr = f.rotation.transpose() * t.rotation;
  Twist r;
  r << rotation_vector(Quaterniond(dr)), f.rotation.transpose() * (t.translation - f.translation);
  return r;
}

// q <- q (+) dq: hinges and slides add, a ball composes on the right.
using ChainVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxChainDofs, 1>;

void advance(const JointChain& chain, const ChainVector& dq, ChainCoordinates* q) {
  int dof = 0;
  for (const ChainJoint& j : chain.joints) {
    if (j.type == ChainJointType::ball) {
      const Vector3d theta(q->at(dof), q->at(dof + 1), q->at(dof + 2));
      const Vector3d next = rotation_vector(from_rotation_vector(theta) * from_rotation_vector(dq.segment<3>(dof)));
      for (int i = 0; i < 3; ++i) q->at(dof + i) = next[i];
      dof += 3;
    } else {
      q->at(dof) += dq[dof];
      dof += 1;
    }
  }
}

// The chain's child frame in its parent frame (at the bodies' pose).
Motion relative_pose(const JointChain& chain, const RigidBody& a, const RigidBody& b) {
  const Matrix3d ra = a.orientation.toRotationMatrix(), rb = b.orientation.toRotationMatrix();
  const Vector3d child = b.position + rb * chain.child_origin, parent = a.position + ra * chain.parent_origin;
  return {ra.transpose() * rb, ra.transpose() * (child - parent)};
}

// S^+, n x 6 (n <= 6 dofs). Where S has full column rank by a margin (every joint set but a
// redundant one) from the normal equations, S^+ = (S^T S)^-1 S^T: an n x n Cholesky, several times
// cheaper than the SVD that was most of a humanoid's step (papers/physics.md, "MJCF models").
// Else by singular values, those below kSingular of the largest taken as zero: the least-norm
// step where joints are redundant (two hinges on one axis). The normal equations square S's
// condition number, so they are taken only while it stays below 1/sqrt(kWellConditioned).
constexpr double kSingular = 1e-10;
constexpr double kWellConditioned = 1e-6;  // smallest pivot of S^T S over its largest diagonal
using TwistInverse = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxChainDofs, 6>;

// S^+ = (S^T S)^-1 S^T by a Cholesky factor G = L L^T of the n x n Gram matrix, in plain loops
// (n <= 6: Eigen's dynamic-size LDLT and triangular solves cost more than the arithmetic); false
// where a pivot falls below kWellConditioned of the largest diagonal.
bool normal_equations_inverse(const ChainTwists& s, TwistInverse* out) {
  const int n = static_cast<int>(s.cols());
  double l[kMaxChainDofs][kMaxChainDofs];
  double largest = 0;
  for (int i = 0; i < n; ++i) largest = std::max(largest, s.col(i).squaredNorm());
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) {
      double g = s.col(i).dot(s.col(j));
      for (int k = 0; k < j; ++k) g -= l[i][k] * l[j][k];
      if (i == j) {
        if (!(g > kWellConditioned * largest)) return false;
        l[j][j] = std::sqrt(g);
      } else {
        l[i][j] = g / l[j][j];
      }
    }
  }
  out->resize(n, 6);
  for (int c = 0; c < 6; ++c) {
    double x[kMaxChainDofs];
    for (int i = 0; i < n; ++i) {  // L y = (S^T)_c
      double v = s(c, i);
      for (int k = 0; k < i; ++k) v -= l[i][k] * x[k];
      x[i] = v / l[i][i];
    }
    for (int i = n - 1; i >= 0; --i) {  // L^T x = y
      double v = x[i];
      for (int k = i + 1; k < n; ++k) v -= l[k][i] * x[k];
      x[i] = v / l[i][i];
    }
    for (int i = 0; i < n; ++i) (*out)(i, c) = x[i];
  }
  return true;
}

TwistInverse pseudo_inverse(const ChainTwists& s) {
  const int n = static_cast<int>(s.cols());
  if (n == 0) return TwistInverse(0, 6);
  if (n == 1) return s.col(0).transpose() / s.col(0).squaredNorm();  // a hinge or a slide alone: exact
  TwistInverse out;
  if (normal_equations_inverse(s, &out)) return out;
  Eigen::JacobiSVD<ChainTwists> svd(s, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(kSingular);
  return svd.solve(Eigen::Matrix<double, 6, 6>::Identity());
}

// The fit stops once a step moves no coordinate by more than this (rad or m), or after
// kMaxIterations; a step is cut to kMaxStep (the search starts at the last q*, so a long step
// means a jump, where Gauss-Newton may overshoot).
constexpr double kConverged = 1e-14;
constexpr int kMaxIterations = 50;
constexpr double kMaxStep = 0.5;
// Eigenvalues of A = S_w S_w^T (squared singular values, rad^2) and lengths of pure
// translations (m, relative to the largest twist) below these are zero: MuJoCo's axes are exact
// to rounding, and a nearly dependent pair is treated as dependent, not as a singular row.
constexpr double kRankTolerance = 1e-12;
constexpr double kTranslationTolerance = 1e-6;

// The twists' rotational and translational parts: A = S_w S_w^T (its eigensystem), C = S_v S_w^T
// and K = A^+ over A's `rank` largest eigenvalues (continuous while they stay apart from the rest).
struct SplitTwists {
  Eigen::SelfAdjointEigenSolver<Matrix3d> rotations;  // of A, ascending
  Matrix3d c, k = Matrix3d::Zero();
};

SplitTwists split(const ChainTwists& s, int rank) {
  SplitTwists out;
  const auto w = s.topRows<3>();
  const auto v = s.bottomRows<3>();
  out.rotations.compute(w.lazyProduct(w.transpose()));
  out.c = v.lazyProduct(w.transpose());
  for (int i = 3 - rank; i < 3; ++i) {
    const double lambda = out.rotations.eigenvalues()[i];
    if (lambda > kRankTolerance) {
      const Vector3d u = out.rotations.eigenvectors().col(i);
      out.k += (u / lambda) * u.transpose();
    }
  }
  return out;
}

Vector3d rotation_of(const ChainTwists& s, int dof) { return s.col(dof).head<3>(); }

// d_k = v_k - C K w_k: what dof k moves the child's origin by, less what its rotation's share
// of the span brings (the translation no rotation accompanies).
Vector3d pure_translation(const ChainTwists& s, const SplitTwists& t, int dof) {
  return s.col(dof).tail<3>() - t.c * (t.k * rotation_of(s, dof));
}

// The dof whose vector (from `of`) is longest across the unit `across` (0: its plain length),
// and that length.
template <typename Of>
std::pair<int, double> best_dof(int dofs, const Vector3d& across, Of of) {
  std::pair<int, double> best{-1, 0.0};
  for (int k = 0; k < dofs; ++k) {
    const Vector3d x = of(k);
    const double length = across.isZero() ? x.norm() : x.cross(across).norm();
    if (length > best.second) best = {k, length};
  }
  return best;
}

// Unit x across the unit n: x less its part along n.
Vector3d across(const Vector3d& x, const Vector3d& n) { return (x - x.dot(n) * n).normalized(); }

// The ranks at q = 0 and the dofs (and fixed axis) that name the rows (joint_set.h).
void name_rows(const ChainTwists& s, JointChain* chain) {
  const int n = chain->dofs;
  const Vector3d none = Vector3d::Zero();
  int rotations = 0;
  const auto r1 = best_dof(n, none, [&](int k) { return rotation_of(s, k); });
  if (r1.second * r1.second > kRankTolerance) {
    rotations = 1;
    chain->rotation_dofs[0] = r1.first;
    const Vector3d w1 = rotation_of(s, r1.first).normalized();
    const auto r2 = best_dof(n, w1, [&](int k) { return rotation_of(s, k); });
    if (r2.second * r2.second > kRankTolerance) {
      rotations = 2;
      chain->rotation_dofs[1] = r2.first;
      const Vector3d w2 = rotation_of(s, r2.first);
      const Vector3d normal = w1.cross(w2).normalized();
      const auto r3 = best_dof(n, none, [&](int k) { return Vector3d(normal * rotation_of(s, k).dot(normal)); });
      if (r3.second * r3.second > kRankTolerance) rotations = 3;
    }
  }
  const SplitTwists t = split(s, rotations);
  double scale = 1;
  for (int k = 0; k < n; ++k) scale = std::max(scale, s.col(k).norm());
  const double tolerance = kTranslationTolerance * scale;
  int translations = 0;
  const auto d1 = best_dof(n, none, [&](int k) { return pure_translation(s, t, k); });
  if (d1.second > tolerance) {
    translations = 1;
    chain->translation_dofs[0] = d1.first;
    const Vector3d e1 = pure_translation(s, t, d1.first).normalized();
    const auto d2 = best_dof(n, e1, [&](int k) { return pure_translation(s, t, k); });
    if (d2.second > tolerance) {
      translations = 2;
      chain->translation_dofs[1] = d2.first;
      const Vector3d normal = e1.cross(pure_translation(s, t, d2.first)).normalized();
      const auto d3 = best_dof(n, none, [&](int k) { return Vector3d(normal * pure_translation(s, t, k).dot(normal)); });
      if (d3.second > tolerance) translations = 3;
    } else {
      // one pure translation d: g across it, the one rotation's axis if there is one and it is
      // well across d (d turns about that axis, so the angle between them stays), else any
      const Vector3d axis = rotations == 1 ? rotation_of(s, r1.first).normalized() : Vector3d::Zero();
      chain->translation_reference = axis.cross(e1).norm() > 0.5 ? axis : e1.unitOrthogonal();
    }
  }
  // one rotation: its axis is constant in the child's frame (every turn is about it)
  if (rotations == 1) chain->rotation_reference = rotation_of(s, r1.first).normalized().unitOrthogonal();
  chain->angular_rows = 3 - rotations;
  chain->translational_rows = 3 - translations;
}

}  // namespace


std::shared_ptr<const JointChain> make_joint_chain(const RigidBody& a, const RigidBody& b,
                                                   const std::vector<ChainJoint>& world_joints) {
  auto chain = std::make_shared<JointChain>();
  const Motion pose = relative_pose(*chain, a, b);
  chain->rotation = pose.rotation;
  chain->translation = pose.translation;
  const Matrix3d to_child = b.orientation.toRotationMatrix().transpose();
  for (const ChainJoint& w : world_joints) {
    assert(w.type == ChainJointType::ball || w.axis.squaredNorm() > 0);
    ChainJoint j = w;
    j.anchor = to_child * (w.anchor - b.position);
    if (w.type != ChainJointType::ball) j.axis = (to_child * w.axis).normalized();
    chain->joints.push_back(j);
    chain->dofs += joint_dofs(j);
  }
  assert(chain->dofs <= kMaxChainDofs);
  ChainCoordinates zero{};
  ChainTwists s;
  forward(*chain, zero, &s);
  name_rows(s, chain.get());
  return chain;
}

// The chain's frames stay where they are: in the body's moved frame their origin is -shift off.
std::shared_ptr<const JointChain> shift_chain(const JointChain& chain, bool parent, const Vector3d& shift) {
  auto moved = std::make_shared<JointChain>(chain);
  (parent ? moved->parent_origin : moved->child_origin) -= shift;
  return moved;
}

ChainFit fit_chain(const JointChain& chain, const RigidBody& a, const RigidBody& b, ChainCoordinates* q) {
  const Motion target = relative_pose(chain, a, b);
  ChainFit fit;
  for (int iteration = 0;; ++iteration) {
    fit.residual = residual(forward(chain, *q, &fit.twists), target);
    if (chain.dofs == 0 || iteration == kMaxIterations) break;
    ChainVector dq = pseudo_inverse(fit.twists) * fit.residual;
    const double step = dq.cwiseAbs().maxCoeff();
    if (!(step < 1e300)) break;  // not finite: keep the last pose's q
    if (step > kMaxStep) dq *= kMaxStep / step;
    advance(chain, dq, q);
    if (step <= kConverged) {
      fit.residual = residual(forward(chain, *q, &fit.twists), target);
      break;
    }
  }
  fit.rates = pseudo_inverse(fit.twists);
  fit.q = *q;
  return fit;
}

ChainCovectors chain_row_covectors(const JointChain& chain, const ChainFit& fit) {
  ChainCovectors rows(6, chain.rows());
  const ChainTwists& s = fit.twists;
  const SplitTwists t = split(s, 3 - chain.angular_rows);
  // angular: the child's axes; two fixed axes across the one rotation's (constant) axis; or the
  // normal of the two rotations
  if (chain.angular_rows == 3) {
    for (int i = 0; i < 3; ++i) rows.col(i) << Vector3d::Unit(i), Vector3d::Zero();
  } else if (chain.angular_rows == 2) {
    const Vector3d w = rotation_of(s, chain.rotation_dofs[0]).normalized();
    const Vector3d u = across(chain.rotation_reference, w);
    rows.col(0) << u, Vector3d::Zero();
    rows.col(1) << w.cross(u), Vector3d::Zero();
  } else if (chain.angular_rows == 1) {
    const Vector3d u = rotation_of(s, chain.rotation_dofs[0]).cross(rotation_of(s, chain.rotation_dofs[1]));
    rows.col(0) << u.normalized(), Vector3d::Zero();
  }
  // translational: t across the pure translations, x = -K C^T t
  Eigen::Matrix<double, 3, 3> dirs;  // (columns: the rows' t)
  const int m = chain.translational_rows, a = chain.angular_rows;
  if (m == 3) {
    dirs.setIdentity();
  } else if (m == 2) {
    const Vector3d d = pure_translation(s, t, chain.translation_dofs[0]).normalized();
    const Vector3d g = across(chain.translation_reference, d);
    dirs.col(0) = g;
    dirs.col(1) = d.cross(g);
  } else if (m == 1) {
    dirs.col(0) = pure_translation(s, t, chain.translation_dofs[0])
                      .cross(pure_translation(s, t, chain.translation_dofs[1]))
                      .normalized();
  }
  for (int i = 0; i < m; ++i) rows.col(a + i) << -(t.k * (t.c.transpose() * dirs.col(i))), dirs.col(i);
  return rows;
}

namespace {

int first_dof(const JointChain& chain, int joint) {
  int dof = 0;
  for (int k = 0; k < joint; ++k) dof += joint_dofs(chain.joints[k]);
  return dof;
}

}  // namespace

double chain_coordinate(const JointChain& chain, const ChainFit& fit, int joint, Twist* covector) {
  assert(joint >= 0 && joint < static_cast<int>(chain.joints.size()));
  const ChainCoordinates& q = fit.q;
  const int dof = first_dof(chain, joint);
  const auto rate = [&](int i) -> Twist { return fit.rates.row(i).transpose(); };
  if (chain.joints[joint].type != ChainJointType::ball) {
    *covector = rate(dof);
    return q[dof];
  }
  // the angle |theta|: its rate is theta/|theta| . (the ball's rates), the rotation vector's
  // direction being unchanged by the right Jacobian
  const Vector3d theta(q[dof], q[dof + 1], q[dof + 2]);
  const double angle = theta.norm();
  const Vector3d direction = angle > 0 ? (theta / angle).eval() : Vector3d::UnitX();
  *covector = direction[0] * rate(dof) + direction[1] * rate(dof + 1) + direction[2] * rate(dof + 2);
  return angle;
}

bool dof_is_angular(const JointChain& chain, int dof) {
  for (const ChainJoint& j : chain.joints) {
    if (dof < joint_dofs(j)) return j.type != ChainJointType::slide;
    dof -= joint_dofs(j);
  }
  assert(false && "dof_is_angular: no such dof");
  return false;
}

double chain_dof([[maybe_unused]] const JointChain& chain, const ChainFit& fit, int dof, Twist* covector) {
  assert(dof >= 0 && dof < chain.dofs);
  *covector = fit.rates.row(dof).transpose();
  return fit.q[dof];
}

void chain_jacobian_row(const JointChain& chain, const Twist& covector, const RigidBody& a, const RigidBody& b,
                        double* row12) {
  const Matrix3d rb = b.orientation.toRotationMatrix();
  const Vector3d x = rb * covector.head<3>(), t = rb * covector.tail<3>();
  const Vector3d origin = b.position + rb * chain.child_origin;
  // [v_a, w_a, v_b, w_b] = [-t, -x - (o - p_a) x t, t, x + (o - p_b) x t]
  const Vector3d wa = -x - (origin - a.position).cross(t), wb = x + (origin - b.position).cross(t);
  for (int k = 0; k < 3; ++k) {
    row12[k] = -t[k];
    row12[3 + k] = wa[k];
    row12[6 + k] = t[k];
    row12[9 + k] = wb[k];
  }
}

}  // namespace ldlpgs
