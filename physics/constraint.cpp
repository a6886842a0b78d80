// The constraint types as position errors c and velocity rows J (constraint.h), after the talk's
// ball in socket: c = (p_a + O_a x_a) - (p_b + O_b x_b), J = [Id, -[O_a x_a]x, -Id, [O_b x_b]x].
// Every type is built from three kinds of row, each differentiated with the bodies' world-frame
// velocities (dp/dt = v, d(R x)/dt = w x R x):
//   ball rows   (p_a + r_a) - (p_b + r_b)   3 translational rows
//   dot rows    x . y, x on a, y on b        angular: (x cross y) . (w_a - w_b)
//   slide rows  t . d, t on a                translational: d = (p_b + r_b) - (p_a + r_a)
// with r_a = R_a anchor_a, r_b = R_b anchor_b. A dot row between two vectors that are
// perpendicular at the initial pose is the small angle between them (radians).
#include "ldlpgs/physics/constraint.h"

#include <array>
#include <cassert>
#include <cmath>

namespace ldlpgs {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Indexed by ConstraintType (scene files spell the types this way).
constexpr std::array<const char*, 13> kNames = {
    "ball", "hinge", "prismatic", "cylindrical", "weld", "rod", "rope", "angular_limit", "positional_limit",
    "joint_set", "coordinate_limit", "dof_drive", "dof_motor"};
static_assert(kNames.size() == static_cast<size_t>(ConstraintType::dof_motor) + 1);

// The pose quantities every row uses, at the current pose.
struct Pose {
  Matrix3d ra, rb;  // orientations as matrices (body -> world)
  Vector3d r_a, r_b;  // world offsets of the anchors from the centres of mass
  Vector3d d;         // (p_b + r_b) - (p_a + r_a)
};

Pose pose_of(const Constraint& c, const RigidBody& a, const RigidBody& b) {
  Pose p;
  p.ra = a.orientation.toRotationMatrix();
  p.rb = b.orientation.toRotationMatrix();
  p.r_a = p.ra * c.anchor_a;
  p.r_b = p.rb * c.anchor_b;
  p.d = (b.position + p.r_b) - (a.position + p.r_a);
  return p;
}

void set_row(ConstraintRows* out, int row, double c, bool angular, const Vector3d& v_a, const Vector3d& w_a,
             const Vector3d& v_b, const Vector3d& w_b) {
  assert(row < kMaxConstraintRows);
  out->c[row] = c;
  out->angular[row] = angular;
  double* j = out->jacobian.data() + 12 * row;
  for (int k = 0; k < 3; ++k) {
    j[k] = v_a[k];
    j[3 + k] = w_a[k];
    j[6 + k] = v_b[k];
    j[9 + k] = w_b[k];
  }
}

// The row written as its opposite (-c, -J): the max side of a limit, a rope.
void negate_row(ConstraintRows* out, int row) {
  out->c[row] = -out->c[row];
  for (int k = 0; k < 12; ++k) out->jacobian[12 * row + k] = -out->jacobian[12 * row + k];
}

// Rows row..row+2: c = (p_a + r_a) - (p_b + r_b) = -d; row k has
// v_a: e_k, w_a: r_a x e_k, v_b: -e_k, w_b: -(r_b x e_k), i.e. J = [I, -[r_a]x, -I, [r_b]x].
void ball_rows(ConstraintRows* out, int row, const Pose& p) {
  for (int k = 0; k < 3; ++k) {
    const Vector3d e = Vector3d::Unit(k);
    set_row(out, row + k, -p.d[k], false, e, p.r_a.cross(e), -e, -p.r_b.cross(e));
  }
}

// c = x . y with x on a, y on b (world frame): dc/dt = (w_a x x).y + x.(w_b x y)
// = (x cross y).(w_a - w_b), so J = [0, x cross y, 0, -(x cross y)].
void dot_row(ConstraintRows* out, int row, const Vector3d& x, const Vector3d& y) {
  const Vector3d g = x.cross(y);
  set_row(out, row, x.dot(y), true, Vector3d::Zero(), g, Vector3d::Zero(), -g);
}

// c = t . d with t on a: dc/dt = (w_a x t).d + t.(v_b + w_b x r_b - v_a - w_a x r_a), so
// J = [-t, t x (d + r_a), t, r_b x t].
void slide_row(ConstraintRows* out, int row, const Vector3d& t, const Pose& p) {
  set_row(out, row, t.dot(p.d), false, -t, t.cross(p.d + p.r_a), t, p.r_b.cross(t));
}

// The frame columns (u, w, n) of a and b in the world.
Vector3d axis_a(const Constraint& c, const Pose& p, int col) { return p.ra * c.frame_a.col(col); }
Vector3d axis_b(const Constraint& c, const Pose& p, int col) { return p.rb * c.frame_b.col(col); }

// The hinge angle theta = atan2(s, k) of b's u about a's n, measured from a's u:
// a = R_a u_a, b = R_b u_b, n = R_a n_a, s = (a x b).n = b.(n x a), k = a.b.
// k and s are dot rows (n x a turns with a): dk = (a x b).(w_a - w_b),
// ds = ((n x a) x b).(w_a - w_b); dtheta = (k ds - s dk) / (s^2 + k^2). `gradient` is the
// coefficient of w_a (that of w_b is its opposite).
double hinge_angle(const Constraint& c, const Pose& p, Vector3d* gradient) {
  const Vector3d a = axis_a(c, p, 0), b = axis_b(c, p, 0), n = axis_a(c, p, 2);
  const Vector3d m = n.cross(a);
  const double s = b.dot(m), k = a.dot(b);
  const double r2 = s * s + k * k;  // 0 only when b lies along the axis: the angle is undefined
  if (gradient) *gradient = r2 > 0 ? ((k / r2) * m.cross(b) - (s / r2) * a.cross(b)).eval() : Vector3d::Zero();
  return std::atan2(s, k);
}

// The slide of b's anchor along a's axis, n = R_a n_a: n . d (a slide row).
double slide_value(const Constraint& c, const Pose& p) { return axis_a(c, p, 2).dot(p.d); }

// The coordinate a coordinate_limit bounds, and the covector of its rate.
double coordinate_value(const Constraint& c, const RigidBody& a, const RigidBody& b, const ChainFit* given,
                        Twist* covector) {
  ChainFit own;
  const ChainFit& fit = chain_fit(c, a, b, given, &own);
  return chain_coordinate(*c.chain, fit, c.joint, covector);
}

// The shared part of the builders: the bodies and the world anchors in each body's frame
// (frames: the identity, which ball, rod and rope ignore).
Constraint make_common(ConstraintType type, int ia, const RigidBody& a, int ib, const RigidBody& b,
                       const Vector3d& anchor_on_a, const Vector3d& anchor_on_b) {
  assert(ia >= 0 && ib >= 0 && ia != ib);
  Constraint c;
  c.type = type;
  c.body_a = ia;
  c.body_b = ib;
  c.anchor_a = a.orientation.conjugate() * (anchor_on_a - a.position);
  c.anchor_b = b.orientation.conjugate() * (anchor_on_b - b.position);
  return c;
}

// The frames from a world axis: F = (u, w, n) built deterministically, n = axis / |axis|,
// u = a unit vector perpendicular to n (Eigen's unitOrthogonal), w = n x u (so u x w = n);
// frame_a = R_a^T F, frame_b = R_b^T F (equal in the world at this pose).
void set_frames(const RigidBody& a, const RigidBody& b, const Vector3d& axis, Constraint* c) {
  assert(axis.squaredNorm() > 0);
  const Vector3d n = axis.normalized();
  const Vector3d u = n.unitOrthogonal();
  Matrix3d f;
  f.col(0) = u;
  f.col(1) = n.cross(u);
  f.col(2) = n;
  c->frame_a = a.orientation.toRotationMatrix().transpose() * f;
  c->frame_b = b.orientation.toRotationMatrix().transpose() * f;
}

}  // namespace

const ChainFit& chain_fit(const Constraint& c, const RigidBody& a, const RigidBody& b, const ChainFit* given,
                          ChainFit* own) {
  if (given) return *given;
  *own = fit_chain(*c.chain, a, b, &c.coordinates);
  return *own;
}

int num_rows(ConstraintType type) {
  switch (type) {
    case ConstraintType::ball: return 3;
    case ConstraintType::hinge: return 5;
    case ConstraintType::prismatic: return 5;
    case ConstraintType::cylindrical: return 4;
    case ConstraintType::weld: return 6;
    case ConstraintType::rod:
    case ConstraintType::rope:
    case ConstraintType::angular_limit:
    case ConstraintType::positional_limit:
    case ConstraintType::coordinate_limit:
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: return 1;
    case ConstraintType::joint_set: assert(false && "joint_set: its chain gives its rows"); return 0;
  }
  assert(false && "unknown constraint type");
  return 0;
}

int num_rows(const Constraint& constraint) {
  if (constraint.type == ConstraintType::joint_set) return constraint.chain->rows();
  return num_rows(constraint.type);
}

bool is_equality(ConstraintType type) {
  switch (type) {
    case ConstraintType::ball:
    case ConstraintType::hinge:
    case ConstraintType::prismatic:
    case ConstraintType::cylindrical:
    case ConstraintType::weld:
    case ConstraintType::rod:
    case ConstraintType::joint_set:
    case ConstraintType::dof_drive: return true;
    case ConstraintType::rope:
    case ConstraintType::dof_motor:
    case ConstraintType::angular_limit:
    case ConstraintType::positional_limit:
    case ConstraintType::coordinate_limit: return false;
  }
  assert(false && "unknown constraint type");
  return false;
}

const char* to_string(ConstraintType type) { return kNames[static_cast<size_t>(type)]; }

bool constraint_type_from_string(std::string_view name, ConstraintType* type) {
  for (size_t i = 0; i < kNames.size(); ++i)
    if (name == kNames[i]) {
      *type = static_cast<ConstraintType>(i);
      return true;
    }
  return false;
}

// Long: one case per constraint type, each with its Jacobian above its code (DEVELOPERS.md, the
// tagged type dispatched by a switch).
ConstraintRows evaluate(const Constraint& constraint, const RigidBody& a, const RigidBody& b, const ChainFit* fit_given) {
  const Constraint& c = constraint;
  const Pose p = pose_of(c, a, b);
  ConstraintRows out;
  out.rows = num_rows(c);
  // u_a, w_a, n_a = R_a frame_a's columns, u_b, w_b, n_b = R_b frame_b's columns (world)
  switch (c.type) {
    case ConstraintType::ball:
      // J = [I, -[r_a]x, -I, [r_b]x]
      ball_rows(&out, 0, p);
      break;
    case ConstraintType::hinge:
      // J = [I, -[r_a]x, -I, [r_b]x]                 (ball)
      //     [0, (u_a x n_b)^T, 0, -(u_a x n_b)^T]    (c = u_a . n_b)
      //     [0, (w_a x n_b)^T, 0, -(w_a x n_b)^T]    (c = w_a . n_b)
      ball_rows(&out, 0, p);
      dot_row(&out, 3, axis_a(c, p, 0), axis_b(c, p, 2));
      dot_row(&out, 4, axis_a(c, p, 1), axis_b(c, p, 2));
      break;
    case ConstraintType::prismatic:
      // J = [-u_a^T, (u_a x (d + r_a))^T, u_a^T, (r_b x u_a)^T]   (c = u_a . d)
      //     [-w_a^T, (w_a x (d + r_a))^T, w_a^T, (r_b x w_a)^T]   (c = w_a . d)
      //     [0, (u_a x n_b)^T, 0, -(u_a x n_b)^T]                 (c = u_a . n_b)
      //     [0, (w_a x n_b)^T, 0, -(w_a x n_b)^T]                 (c = w_a . n_b)
      //     [0, (u_a x w_b)^T, 0, -(u_a x w_b)^T]                 (c = u_a . w_b)
      slide_row(&out, 0, axis_a(c, p, 0), p);
      slide_row(&out, 1, axis_a(c, p, 1), p);
      dot_row(&out, 2, axis_a(c, p, 0), axis_b(c, p, 2));
      dot_row(&out, 3, axis_a(c, p, 1), axis_b(c, p, 2));
      dot_row(&out, 4, axis_a(c, p, 0), axis_b(c, p, 1));
      break;
    case ConstraintType::cylindrical:
      // J = [-u_a^T, (u_a x (d + r_a))^T, u_a^T, (r_b x u_a)^T]   (c = u_a . d)
      //     [-w_a^T, (w_a x (d + r_a))^T, w_a^T, (r_b x w_a)^T]   (c = w_a . d)
      //     [0, (u_a x n_b)^T, 0, -(u_a x n_b)^T]                 (c = u_a . n_b)
      //     [0, (w_a x n_b)^T, 0, -(w_a x n_b)^T]                 (c = w_a . n_b)
      slide_row(&out, 0, axis_a(c, p, 0), p);
      slide_row(&out, 1, axis_a(c, p, 1), p);
      dot_row(&out, 2, axis_a(c, p, 0), axis_b(c, p, 2));
      dot_row(&out, 3, axis_a(c, p, 1), axis_b(c, p, 2));
      break;
    case ConstraintType::weld:
      // J = [I, -[r_a]x, -I, [r_b]x]                 (ball)
      //     [0, (u_a x n_b)^T, 0, -(u_a x n_b)^T]    (c = u_a . n_b)
      //     [0, (w_a x n_b)^T, 0, -(w_a x n_b)^T]    (c = w_a . n_b)
      //     [0, (u_a x w_b)^T, 0, -(u_a x w_b)^T]    (c = u_a . w_b)
      ball_rows(&out, 0, p);
      dot_row(&out, 3, axis_a(c, p, 0), axis_b(c, p, 2));
      dot_row(&out, 4, axis_a(c, p, 1), axis_b(c, p, 2));
      dot_row(&out, 5, axis_a(c, p, 0), axis_b(c, p, 1));
      break;
    case ConstraintType::rod:
    case ConstraintType::rope: {
      // rod:  c = |d| - length, n = d / |d|: J = [-n^T, -(r_a x n)^T, n^T, (r_b x n)^T]
      // rope: c = length - |d| >= 0 while slack: the rod's row negated.
      // At d = 0 the distance has no gradient; any unit n is a subgradient (x is taken).
      const double distance = p.d.norm();
      const Vector3d n = distance > 0 ? (p.d / distance).eval() : Vector3d::UnitX();
      set_row(&out, 0, distance - c.length, false, -n, -p.r_a.cross(n), n, p.r_b.cross(n));
      if (c.type == ConstraintType::rope) negate_row(&out, 0);
      break;
    }
    case ConstraintType::angular_limit: {
      // theta = atan2(s, k) (hinge_angle): J = [0, g^T, 0, -g^T],
      // g = (k (n x a) x b - s a x b) / (s^2 + k^2); c = theta - min, or max - theta with -J.
      Vector3d g;
      const double theta = hinge_angle(c, p, &g);
      set_row(&out, 0, theta - c.min, true, Vector3d::Zero(), g, Vector3d::Zero(), -g);
      if (theta - c.min > c.max - theta) {
        out.c[0] = theta - c.max;  // negated below: max - theta
        negate_row(&out, 0);
      }
      break;
    }
    case ConstraintType::positional_limit: {
      // value = n_a . d: J = [-n_a^T, (n_a x (d + r_a))^T, n_a^T, (r_b x n_a)^T];
      // c = value - min, or max - value with -J.
      slide_row(&out, 0, axis_a(c, p, 2), p);
      const double value = out.c[0];
      out.c[0] = value - c.min;
      if (value - c.min > c.max - value) {
        out.c[0] = value - c.max;  // negated below: max - value
        negate_row(&out, 0);
      }
      break;
    }
    case ConstraintType::joint_set: {
      // c = y . r for each row covector y of the chain at its fitted coordinates, J = y . V_rel
      // (joint_set.h): J = [-t, -x - (o - p_a) x t, t, x + (o - p_b) x t] for y = (x; t) in b's
      // frame, o the chain's child origin.
      ChainFit own;
      const ChainFit& fit = chain_fit(c, a, b, fit_given, &own);
      const ChainCovectors y = chain_row_covectors(*c.chain, fit);
      for (int i = 0; i < out.rows; ++i) {
        out.c[i] = y.col(i).dot(fit.residual);
        out.angular[i] = i < c.chain->angular_rows;
        chain_jacobian_row(*c.chain, y.col(i), a, b, out.jacobian.data() + 12 * i);
      }
      break;
    }
    case ConstraintType::coordinate_limit: {
      // value = q_k (or a ball's angle), its rate z . V_rel with z the row of S^+ (joint_set.h):
      // J as joint_set's; c = value - min, or max - value with -J (a ball's angle: max only).
      Twist z;
      const double value = coordinate_value(c, a, b, fit_given, &z);
      const ChainJointType joint = c.chain->joints[c.joint].type;
      out.angular[0] = joint != ChainJointType::slide;
      out.c[0] = value - c.min;
      chain_jacobian_row(*c.chain, z, a, b, out.jacobian.data());
      if (joint == ChainJointType::ball || value - c.min > c.max - value) {
        out.c[0] = value - c.max;  // negated below: max - value
        negate_row(&out, 0);
      }
      break;
    }
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: {
      // J = the dof's rate covector (a row of S^+, joint_set.h); no position error: the step
      // sets the row's target rate, softness and bounds (physics/actuation.h)
      ChainFit own;
      const ChainFit& fit = chain_fit(c, a, b, fit_given, &own);
      Twist z;
      chain_dof(*c.chain, fit, c.joint, &z);
      out.angular[0] = dof_is_angular(*c.chain, c.joint);
      chain_jacobian_row(*c.chain, z, a, b, out.jacobian.data());
      break;
    }
  }
  return out;
}

Constraint make_ball(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& anchor) {
  return make_common(ConstraintType::ball, ia, a, ib, b, anchor, anchor);
}

Constraint make_axial(ConstraintType type, int ia, const RigidBody& a, int ib, const RigidBody& b,
                      const Eigen::Vector3d& anchor, const Eigen::Vector3d& axis) {
  assert(type == ConstraintType::hinge || type == ConstraintType::prismatic || type == ConstraintType::cylindrical ||
         type == ConstraintType::weld);
  Constraint c = make_common(type, ia, a, ib, b, anchor, anchor);
  set_frames(a, b, axis, &c);
  return c;
}

Constraint make_distance(ConstraintType type, int ia, const RigidBody& a, int ib, const RigidBody& b,
                         const Eigen::Vector3d& anchor_on_a, const Eigen::Vector3d& anchor_on_b, double length) {
  assert(type == ConstraintType::rod || type == ConstraintType::rope);
  Constraint c = make_common(type, ia, a, ib, b, anchor_on_a, anchor_on_b);
  c.length = length < 0 ? (anchor_on_b - anchor_on_a).norm() : length;
  return c;
}

Constraint make_angular_limit(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& axis,
                              double min, double max) {
  assert(min <= max);
  // The angle needs no anchor; a's centre of mass stands in (never read).
  Constraint c = make_common(ConstraintType::angular_limit, ia, a, ib, b, a.position, a.position);
  set_frames(a, b, axis, &c);
  c.min = min;
  c.max = max;
  return c;
}

Constraint make_positional_limit(int ia, const RigidBody& a, int ib, const RigidBody& b, const Eigen::Vector3d& anchor,
                                 const Eigen::Vector3d& axis, double min, double max) {
  assert(min <= max);
  Constraint c = make_common(ConstraintType::positional_limit, ia, a, ib, b, anchor, anchor);
  set_frames(a, b, axis, &c);
  c.min = min;
  c.max = max;
  return c;
}

Constraint make_joint_set(int ia, const RigidBody& a, int ib, const RigidBody& b,
                          const std::vector<ChainJoint>& world_joints) {
  Constraint c = make_common(ConstraintType::joint_set, ia, a, ib, b, b.position, b.position);
  c.chain = make_joint_chain(a, b, world_joints);
  return c;
}

Constraint make_dof_row(ConstraintType type, const Constraint& joint_set, int dof) {
  assert((type == ConstraintType::dof_drive || type == ConstraintType::dof_motor) && joint_set.chain && dof >= 0 &&
         dof < joint_set.chain->dofs);
  Constraint c = joint_set;
  c.type = type;
  c.joint = dof;
  return c;
}

Constraint make_coordinate_limit(const Constraint& joint_set, int joint, double min, double max) {
  assert(joint_set.chain && joint >= 0 && joint < static_cast<int>(joint_set.chain->joints.size()) && min <= max);
  Constraint c = joint_set;
  c.type = ConstraintType::coordinate_limit;
  c.joint = joint;
  c.min = min;
  c.max = max;
  return c;
}

double limit_value(const Constraint& constraint, const RigidBody& a, const RigidBody& b) {
  const Pose p = pose_of(constraint, a, b);
  Twist unused;
  switch (constraint.type) {
    case ConstraintType::angular_limit: return hinge_angle(constraint, p, nullptr);
    case ConstraintType::positional_limit: return slide_value(constraint, p);
    case ConstraintType::coordinate_limit: return coordinate_value(constraint, a, b, nullptr, &unused);
    default: assert(false && "limit_value: not a limit"); return 0;
  }
}

}  // namespace ldlpgs
