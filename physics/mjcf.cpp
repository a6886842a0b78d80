// MJCF -> Mechanism in maximal coordinates (the table and the universal joint: mjcf.h). MuJoCo
// compiles the file; we read the compiled mjModel and the kinematics of mj_kinematics at qpos0:
// xipos/ximat (each body's centre of mass and principal frame, our RigidBody's pose), xanchor
// and xaxis (each joint's point and axis, world frame), xpos/xquat (body frames, for the
// equalities' data, which MuJoCo gives in body frames).
#include "ldlpgs/physics/mjcf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "ldlpgs/physics/mjcf_input.h"
#include "ldlpgs/physics/scene.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

#ifdef LDLPGS_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace ldlpgs {

bool is_mjcf_path(const std::string& path) { return std::filesystem::path(path).extension() == ".xml"; }

std::string describe(const MjcfDropped& dropped) {
  std::string s;
  auto add = [&s](int n, const char* what) {
    if (n == 0) return;
    s += s.empty() ? "dropped: " : ", ";
    s += std::to_string(n);
    s += " ";
    s += what;
  };
  add(dropped.geoms, "geoms of types without a shape (hfield, ellipsoid, cylinder, mesh: no contacts)");
  add(dropped.contact_pairs, "contact pairs and excludes");
  add(dropped.tendons, "tendons");
  add(dropped.actuators, "actuators");
  add(dropped.sensors, "sensors");
  add(dropped.joint_dynamics, "joints' stiffness/damping/armature/friction loss");
  add(dropped.ranges, "joint ranges (ball joints, 3-hinge sets)");
  add(dropped.inactive_equalities, "inactive equalities");
  add(dropped.static_equalities, "equalities between static bodies");
  add(dropped.keyframes, "keyframes (we start at qpos0, at rest)");
  return s;
}

#ifndef LDLPGS_HAVE_MUJOCO

bool mjcf_supported() { return false; }

Mechanism load_mjcf(const std::string& path, MjcfDropped*) {
  throw InputError(path + ": MJCF models need MuJoCo (Debian's libmujoco-dev); rebuild with it installed");
}

#else

bool mjcf_supported() { return true; }

namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// A hinge and a slide share one axis when |n1 x n2| of their unit axes is below this: MuJoCo's
// kinematics give the axes exact to rounding.
constexpr double kSameAxis = 1e-9;
// Hinge axes meet when the point closest to all their lines lies within this (relative to the
// anchors' distance from the origin) of each: MuJoCo's kinematics are exact to rounding.
constexpr double kMeet = 1e-9;
// Independent hinge axes: the sine s = |n1 x n2| (two axes) or |det(n1, n2, n3)| (three) must
// satisfy s^2 >= eps / kMeet (s >= 4.7e-4 rad, 0.027 degrees). The axes are exact only to
// rounding, eps ~ 2.2e-16; the closest points of two lines (the universal joint below) and the
// meeting point of three (the solve with sum_i Q_i, whose smallest eigenvalue is ~ s^2) divide by
// s^2, so their error is ~ eps |anchors| / s^2, and the meeting test needs it within kMeet
// |anchors|. The rows themselves shrink with s too (the universal joint's rod between P + L n1
// and P + L n2 has length L s). A fixed 1e-9 on s let axes 1e-8 apart through, where 1 - k^2
// rounded to 0 and H was all NaN; the test is relative to the anchors' scale, which
// the tolerance on the points carries.
const double kIndependent = std::sqrt(std::numeric_limits<double>::epsilon() / kMeet);
// A weld's relpose equals the pose at qpos0 to this (relative position, quaternion vector part).
constexpr double kSamePose = 1e-9;

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

Vector3d vec3(const mjtNum* p) { return Vector3d(p[0], p[1], p[2]); }
Quaterniond quat(const mjtNum* wxyz) { return Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized(); }

const char* joint_type_name(int type) {
  switch (type) {
    case mjJNT_FREE: return "free";
    case mjJNT_BALL: return "ball";
    case mjJNT_SLIDE: return "slide";
    case mjJNT_HINGE: return "hinge";
  }
  return "unknown";
}

const char* equality_type_name(int type) {
  switch (type) {
    case mjEQ_CONNECT: return "connect";
    case mjEQ_WELD: return "weld";
    case mjEQ_JOINT: return "joint";
    case mjEQ_TENDON: return "tendon";
    case mjEQ_DISTANCE: return "distance";
  }
  return "unknown";
}

// Orthonormal columns (u, n x u, n): u = the part of `toward` across the unit axis n.
Matrix3d frame_about(const Vector3d& n, const Vector3d& toward) {
  const Vector3d u = (toward - toward.dot(n) * n).normalized();
  Matrix3d f;
  f.col(0) = u;
  f.col(1) = n.cross(u);
  f.col(2) = n;
  return f;
}

// Orthonormal columns (x, v, x cross v) with the unit x first.
Matrix3d frame_from(const Vector3d& x) {
  const Vector3d v = x.unitOrthogonal();
  Matrix3d f;
  f.col(0) = x;
  f.col(1) = v;
  f.col(2) = x.cross(v);
  return f;
}

// "path: what: problem", the path escaped and bounded; `what` and `problem` hold names already
// escaped, but as many as the body has joints: cut too.
[[noreturn]] void refuse_model(const std::string& path, const std::string& what, const std::string& problem) {
  auto cut = [](std::string text) {
    constexpr size_t kMax = 300;
    if (text.size() > kMax) text.replace(kMax, std::string::npos, "...");
    return text;
  };
  std::string s = printable(path);
  s += ": ";
  s += cut(what);
  s += ": ";
  s += cut(problem);
  throw InputError(s);
}

// One joint of a body, world frame at qpos0; its range relative to qpos0 (our limits measure
// from the initial pose, MuJoCo's from q = 0).
struct Joint {
  int id = -1, type = mjJNT_HINGE;
  Vector3d anchor, axis;  // axis unit
  bool limited = false;
  double lo = 0, hi = 0;
};

class Converter {
 public:
  Converter(const std::string& path, const mjModel* m, const mjData* d, Mechanism* out, MjcfDropped* dropped)
      : path_(path), m_(m), d_(d), out_(out), dropped_(dropped) {}

  void run() {
    out_->gravity = (m_->opt.disableflags & mjDSBL_GRAVITY) ? Vector3d::Zero() : vec3(m_->opt.gravity);
    out_->timestep = m_->opt.timestep;
    for (int b = 0; b < m_->nbody; ++b) out_->add_body(body(b));
    for (int g = 0; g < m_->ngeom; ++g) geom(g);
    for (int b = 1; b < m_->nbody; ++b) joint_rows(b);
    for (int e = 0; e < m_->neq; ++e) equality(e);
    for (Constraint& c : out_->constraints) c.collide = mujoco_may_collide(c.body_a, c.body_b);
    dropped_->contact_pairs = m_->npair + m_->nexclude;
    dropped_->tendons = m_->ntendon;
    dropped_->actuators = m_->nu;
    dropped_->sensors = m_->nsensor;
    dropped_->keyframes = m_->nkey;
    for (int j = 0; j < m_->njnt; ++j) {
      const int dofs = m_->jnt_type[j] == mjJNT_FREE ? 6 : m_->jnt_type[j] == mjJNT_BALL ? 3 : 1;
      bool dynamics = m_->jnt_stiffness[j] != 0;
      for (int k = m_->jnt_dofadr[j]; k < m_->jnt_dofadr[j] + dofs; ++k)
        dynamics = dynamics || m_->dof_damping[k] != 0 || m_->dof_armature[k] != 0 || m_->dof_frictionloss[k] != 0;
      dropped_->joint_dynamics += dynamics ? 1 : 0;
    }
  }

 private:
  std::string name(int adr, const char* kind, int id) const {
    std::string s = printable(m_->names + adr, 80);
    if (s.empty()) {
      s = kind;
      s += std::to_string(id);
    }
    return s;
  }
  std::string body_name(int b) const { return name(m_->name_bodyadr[b], "body", b); }

  [[noreturn]] void fail(const std::string& what, const std::string& problem) const { refuse_model(path_, what, problem); }
  std::string body_label(int b) const {
    std::string s = "body \"";
    s += body_name(b);
    s += "\"";
    return s;
  }

  RigidBody body(int b) const {
    RigidBody r;
    r.name = body_name(b);
    // Welded to the world (no joint on the path to it; mocap bodies are): MuJoCo never moves it.
    r.is_static = b == 0 || m_->body_weldid[b] == 0;
    r.mass = m_->body_mass[b];
    r.inertia = vec3(m_->body_inertia + 3 * b);
    r.position = vec3(d_->xipos + 3 * b);
    // ximat: the principal (inertial) frame -> world, row-major 3x3
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> ximat(d_->ximat + 9 * b);
    r.orientation = Quaterniond(Matrix3d(ximat)).normalized();
    if (!r.is_static && !(r.mass > 0 && r.inertia.minCoeff() > 0)) {
      std::string problem = "a moving body needs a positive mass and inertia, got mass ";
      problem += format_number(r.mass);
      problem += " and inertia";
      for (int k = 0; k < 3; ++k) {
        problem += k ? ", " : " [";
        problem += format_number(r.inertia[k]);
      }
      problem += "]";
      fail(body_label(b), problem);
    }
    return r;
  }

  Joint joint(int j) const {
    Joint J;
    J.id = j;
    J.type = m_->jnt_type[j];
    J.anchor = vec3(d_->xanchor + 3 * j);
    J.axis = vec3(d_->xaxis + 3 * j).normalized();
    J.limited = m_->jnt_limited[j] && !(m_->opt.disableflags & mjDSBL_LIMIT);
    if (J.limited && (J.type == mjJNT_HINGE || J.type == mjJNT_SLIDE)) {
      const double q0 = m_->qpos0[m_->jnt_qposadr[j]];
      J.lo = m_->jnt_range[2 * j] - q0;
      J.hi = m_->jnt_range[2 * j + 1] - q0;
    }
    return J;
  }

  // A geom of a type shape.h has becomes a Shape on its body; the others are dropped. MuJoCo
  // gives the geom's pose in its body frame, ours is the inertial frame (ipos, iquat in that
  // body frame), so: position = iquat^-1 (pos - ipos), orientation = iquat^-1 quat.
  void geom(int g) {
    const int b = m_->geom_bodyid[g];
    const mjtNum* size = m_->geom_size + 3 * g;  // (size 3) per type (mjmodel.h)
    Shape s;
    switch (m_->geom_type[g]) {
      case mjGEOM_PLANE: s.type = ShapeType::plane; break;  // size: its extent drawn; infinite in contacts
      case mjGEOM_SPHERE:
        s.type = ShapeType::sphere;
        s.radius = size[0];
        break;
      case mjGEOM_CAPSULE:  // size[0] radius, size[1] half length of the segment on the geom's z
        s.type = ShapeType::capsule;
        s.radius = size[0];
        s.half_length = size[1];
        break;
      case mjGEOM_BOX:
        s.type = ShapeType::box;
        s.half_extents = vec3(size);
        break;
      default: ++dropped_->geoms; return;  // hfield, ellipsoid, cylinder, mesh
    }
    const Quaterniond to_inertial = quat(m_->body_iquat + 4 * b).conjugate();
    s.position = to_inertial * (vec3(m_->geom_pos + 3 * g) - vec3(m_->body_ipos + 3 * b));
    const Quaterniond orientation = to_inertial * quat(m_->geom_quat + 4 * g);
    if (s.type == ShapeType::plane) {
      s.normal = orientation * Vector3d::UnitZ();  // MuJoCo's plane: the geom's z up
    } else {
      s.orientation = orientation;
    }
    s.friction = m_->geom_friction[3 * g];  // sliding; torsional and rolling are dropped
    // MuJoCo's bit masks are int: the same bits
    s.contype = static_cast<uint32_t>(m_->geom_contype[g]);
    s.conaffinity = static_cast<uint32_t>(m_->geom_conaffinity[g]);
    const std::string problem = shape_problem(s, at(b).is_static);
    if (!problem.empty()) {
      std::string what = "geom \"";
      what += name(m_->name_geomadr[g], "geom", g);
      what += "\" on ";
      what += body_label(b);
      fail(what, problem);
    }
    out_->bodies[b].shapes.push_back(s);
  }

  // MuJoCo's body-pair filter (mj_collision): bodies of one weld group (body_weldid) never touch,
  // nor a weld group and its parent's unless one is the world or filterparent is disabled.
  bool mujoco_may_collide(int b1, int b2) const {
    const int w1 = m_->body_weldid[b1], w2 = m_->body_weldid[b2];
    if (w1 == w2) return false;
    const int parent1 = m_->body_weldid[m_->body_parentid[w1]], parent2 = m_->body_weldid[m_->body_parentid[w2]];
    const bool filter_parent = !(m_->opt.disableflags & mjDSBL_FILTERPARENT);
    return !(filter_parent && w1 != 0 && w2 != 0 && (w1 == parent2 || w2 == parent1));
  }

  int add(const Constraint& c) { return out_->add_constraint(c); }
  const RigidBody& at(int b) const { return out_->bodies[b]; }

  void angular_limit(int p, int b, const Joint& j) {
    if (j.limited) add(out_->angular_limit(p, b, j.axis, j.lo, j.hi));
  }
  void positional_limit(int p, int b, const Vector3d& anchor, const Joint& j) {
    if (j.limited) add(out_->positional_limit(p, b, anchor, j.axis, j.lo, j.hi));
  }

  // The joints of body b (in MuJoCo's order), and a label naming them for refusals.
  struct JointSet {
    int parent = -1, body = -1;
    std::vector<Joint> hinges, slides, all;  // (sizes: the body's joints)
    std::string label;
  };
  JointSet joint_set(int b) const {
    JointSet set;
    set.parent = m_->body_parentid[b];
    set.body = b;
    for (int j = m_->body_jntadr[b]; j < m_->body_jntadr[b] + m_->body_jntnum[b]; ++j) {
      set.all.push_back(joint(j));
      if (set.all.back().type == mjJNT_HINGE) set.hinges.push_back(set.all.back());
      if (set.all.back().type == mjJNT_SLIDE) set.slides.push_back(set.all.back());
    }
    set.label = body_label(b);
    if (!set.all.empty()) {
      set.label += ": joints";
      for (size_t k = 0; k < set.all.size(); ++k) {
        set.label += k ? ", " : " ";
        set.label += name(m_->name_jntadr[set.all[k].id], "joint", set.all[k].id);
        set.label += " (";
        set.label += joint_type_name(set.all[k].type);
        set.label += ")";
      }
    }
    return set;
  }
  // A joint set our constraint types cannot express.
  [[noreturn]] void refuse(const JointSet& set, const std::string& why) const {
    std::string s = why;
    s += "; our constraint types (physics/constraint.h) have no such rows";
    fail(set.label, s);
  }

  // The joints between body b and its parent as rows (the table in mjcf.h): what rows a set
  // needs is 3 - (independent slides) translational and 3 - (independent hinges; 3 with a ball)
  // rotational.
  void joint_rows(int b) {
    if (at(b).is_static) return;  // welded to the world: no joints, nothing to hold
    const JointSet set = joint_set(b);
    const int p = set.parent;
    const size_t hinges = set.hinges.size(), slides = set.slides.size();
    if (set.all.empty()) {  // rigidly attached to a moving parent
      add(out_->axial(ConstraintType::weld, p, b, at(b).position, Vector3d::UnitX()));
    } else if (set.all.size() == 1 && set.all[0].type == mjJNT_FREE) {
      // six degrees of freedom: no rows
    } else if (set.all.size() == 1 && set.all[0].type == mjJNT_BALL) {
      add(out_->ball(p, b, set.all[0].anchor));
      if (m_->jnt_limited[set.all[0].id] && !(m_->opt.disableflags & mjDSBL_LIMIT)) ++dropped_->ranges;  // a cone
    } else if (hinges + slides != set.all.size()) {
      refuse(set, "a free or ball joint combined with other joints");
    } else if (hinges + slides == 1 || (hinges == 1 && slides == 1)) {
      axial_rows(set);
    } else if (slides > 0) {
      refuse_slides(set);
    } else if (hinges > 3) {
      refuse(set, "more than three hinges");
    } else {
      require_independent_hinges(set);
      if (hinges == 3) meeting_hinges_rows(set);
      else universal_rows(set);
    }
  }

  // One hinge, one slide, or a hinge and a slide on one axis: a hinge, prismatic or cylindrical
  // joint with the limits of its coordinates.
  void axial_rows(const JointSet& set) {
    const int p = set.parent, b = set.body;
    if (set.slides.empty()) {
      const Joint& h = set.hinges[0];
      add(out_->axial(ConstraintType::hinge, p, b, h.anchor, h.axis));
      angular_limit(p, b, h);
    } else if (set.hinges.empty()) {
      const Joint& s = set.slides[0];
      add(out_->axial(ConstraintType::prismatic, p, b, at(b).position, s.axis));
      positional_limit(p, b, at(b).position, s);
    } else {
      const Joint &h = set.hinges[0], &s = set.slides[0];
      if (h.axis.cross(s.axis).norm() > kSameAxis)
        refuse(set, "a hinge and a slide on different axes (1 rotational and 1 translational degree of freedom off "
                    "one axis: 2 translational and 2 rotational rows not of a cylindrical joint)");
      add(out_->axial(ConstraintType::cylindrical, p, b, h.anchor, h.axis));
      angular_limit(p, b, h);
      positional_limit(p, b, h.anchor, s);
    }
  }

  [[noreturn]] void refuse_slides(const JointSet& set) const {
    const size_t slides = set.slides.size(), hinges = set.hinges.size();
    std::string why = std::to_string(slides);
    why += " slides and ";
    why += std::to_string(hinges);
    why += " hinges (would need ";
    why += std::to_string(3 - static_cast<int>(slides));
    why += " translational and ";
    why += std::to_string(3 - static_cast<int>(hinges));
    why += " rotational rows";
    why += slides == 3 && hinges == 0 ? ": an orientation-only constraint)" : ")";
    refuse(set, why);
  }

  // Two or three hinges with independent axes (parallel ones would be a hinge with a redundant
  // coordinate).
  void require_independent_hinges(const JointSet& set) const {
    const std::vector<Joint>& h = set.hinges;
    const double sine = h.size() == 2 ? h[0].axis.cross(h[1].axis).norm()
                                      : std::abs(h[0].axis.dot(h[1].axis.cross(h[2].axis)));
    if (!(sine >= kIndependent)) {
      std::string why = "hinges with dependent (parallel or coplanar) axes (sine ";
      why += format_number(sine);
      why += ", below ";
      why += format_number(kIndependent);
      why += ": the rows would be singular to rounding)";
      refuse(set, why);
    }
  }

  // The anchors' scale, for the meeting tolerance.
  static double anchor_scale(const JointSet& set) {
    double size = 1;
    for (const Joint& h : set.hinges) size = std::max(size, h.anchor.norm());
    return size;
  }

  // Three hinges whose axes meet in one point P: P stays fixed in both bodies and all rotation is
  // free, a ball. P minimizes sum_i |(I - n_i n_i^T)(P - a_i)|^2: (sum_i Q_i) P = sum_i Q_i a_i,
  // Q_i the projector across axis i (invertible for independent axes).
  void meeting_hinges_rows(const JointSet& set) {
    const int p = set.parent, b = set.body;
    Matrix3d q_sum = Matrix3d::Zero();
    Vector3d rhs = Vector3d::Zero();
    for (const Joint& h : set.hinges) {
      const Matrix3d q = Matrix3d::Identity() - h.axis * h.axis.transpose();
      q_sum += q;
      rhs += q * h.anchor;
    }
    const Vector3d point = q_sum.fullPivLu().solve(rhs);
    const double size = anchor_scale(set);
    for (const Joint& h : set.hinges) {
      const double miss = ((Matrix3d::Identity() - h.axis * h.axis.transpose()) * (point - h.anchor)).norm();
      if (miss > kMeet * size) {
        std::string why = "three hinges whose axes do not meet in one point (";
        why += format_number(miss);
        why += " m off): the child's translation then depends on its rotation";
        refuse(set, why);
      }
    }
    add(out_->ball(p, b, point));
    // Their ranges bound Euler angles, which our limits (one angle about one axis) cannot
    // measure.
    for (const Joint& h : set.hinges) dropped_->ranges += h.limited ? 1 : 0;
  }

  // Universal joint (mjcf.h): the closest points P1 = a1 + s n1 (on the parent) and
  // P2 = a2 + t n2 (on the child) of the two axis lines, from (P2 - P1) . n1 = (P2 - P1) . n2 = 0:
  // with w = a1 - a2, k = n1.n2: s = (k (n2.w) - n1.w) / (1 - k^2), t = (n2.w - k (n1.w)) / (1 - k^2).
  void universal_rows(const JointSet& set) {
    const int p = set.parent, b = set.body;
    const RigidBody& child = at(b);
    const Joint &h1 = set.hinges[0], &h2 = set.hinges[1];
    const Vector3d &n1 = h1.axis, &n2 = h2.axis;
    const Vector3d w = h1.anchor - h2.anchor;
    // 1 - k^2 = |n1 x n2|^2, the latter without the cancellation of 1 - k^2 near parallel axes
    const double k = n1.dot(n2), denominator = n1.cross(n2).squaredNorm();
    const Vector3d p1 = h1.anchor + ((k * n2.dot(w) - n1.dot(w)) / denominator) * n1;
    const Vector3d p2 = h2.anchor + ((n2.dot(w) - k * n1.dot(w)) / denominator) * n2;
    const double offset = (p2 - p1).norm();
    const double length = kUniversalRodLength;
    if (offset <= kMeet * anchor_scale(set)) {
      add(out_->ball(p, b, (p1 + p2) / 2));
      add(out_->distance(ConstraintType::rod, p, b, p1 + length * n1, p2 + length * n2));
    } else {
      add(out_->distance(ConstraintType::rod, p, b, p1, p2));
      add(out_->distance(ConstraintType::rod, p, b, p1 + length * n1, p2));
      add(out_->distance(ConstraintType::rod, p, b, p1, p2 + length * n2));
      add(out_->distance(ConstraintType::rod, p, b, p1 + length * n1, p2 + length * n2));
    }
    // q1 turns the child about n1 (parent-fixed) and leaves n2 (child-fixed) alone, so q1 is the
    // angle of the child's n2 about the parent's n1, measured from its qpos0 direction: an
    // angular_limit with u_a = n2's part across n1 on the parent and u_b = n2 on the child
    // (hinge_angle reads only those and n_a; the part of u_b along n_a changes neither s nor k).
    const Matrix3d rp = at(p).orientation.toRotationMatrix(), rc = child.orientation.toRotationMatrix();
    if (h1.limited) {
      Constraint c = out_->angular_limit(p, b, n1, h1.lo, h1.hi);
      c.frame_a = rp.transpose() * frame_about(n1, n2);
      c.frame_b = rc.transpose() * frame_from(n2);
      add(c);
    }
    // q2 turns the child about n2 (child-fixed) after q1, which leaves n1 (parent-fixed) alone, so
    // seen from the child the parent's n1 turns by -q2 about n2: the limit with a = child.
    if (h2.limited) {
      Constraint c = out_->angular_limit(b, p, n2, -h2.hi, -h2.lo);
      c.frame_a = rc.transpose() * frame_about(n2, n1);
      c.frame_b = rp.transpose() * frame_from(n1);
      add(c);
    }
  }

  void equality(int e) {
    std::string label = "equality \"";
    label += name(m_->name_eqadr[e], "equality", e);
    label += "\" (";
    label += equality_type_name(m_->eq_type[e]);
    label += ")";
    if (!m_->eq_active[e] || (m_->opt.disableflags & mjDSBL_EQUALITY)) {
      ++dropped_->inactive_equalities;
      return;
    }
    const int type = m_->eq_type[e];
    if (type != mjEQ_CONNECT && type != mjEQ_WELD)
      fail(label, "couples joint values or tendon lengths; our constraints (physics/constraint.h) hold bodies only");
    const int b1 = m_->eq_obj1id[e], b2 = m_->eq_obj2id[e];
    if (at(b1).is_static && at(b2).is_static) {
      ++dropped_->static_equalities;
      return;
    }
    const mjtNum* data = m_->eq_data + mjNEQDATA * e;  // (size mjNEQDATA)
    const Vector3d x1 = vec3(d_->xpos + 3 * b1), x2 = vec3(d_->xpos + 3 * b2);
    const Quaterniond q1 = quat(d_->xquat + 4 * b1), q2 = quat(d_->xquat + 4 * b2);
    if (type == mjEQ_CONNECT) {
      // data[0..2]: the anchor in body1's frame, data[3..5]: in body2's (MuJoCo computes it at
      // qpos0); both kept, so a connect that starts apart is pulled together as in MuJoCo.
      Constraint c = out_->ball(b1, b2, x1 + q1 * vec3(data));
      c.anchor_b = at(b2).orientation.conjugate() * (x2 + q2 * vec3(data + 3) - at(b2).position);
      add(c);
      return;
    }
    // weld: data[3..5] and data[6..9] are body2's pose in body1's frame (relpose). Our weld holds
    // the pose the bodies have, so it must be the relpose.
    const Vector3d relpos = q1.conjugate() * (x2 - x1);
    const Quaterniond relquat = q1.conjugate() * q2;
    const Quaterniond wanted = quat(data + 6);
    const double pose_error = (relpos - vec3(data + 3)).norm() / (1 + relpos.norm());
    const double angle_error = (wanted.conjugate() * relquat).vec().norm();
    if (!(pose_error <= kSamePose && angle_error <= kSamePose))
      fail(label, "its relpose differs from the bodies' relative pose at qpos0 (we weld bodies where they are)");
    add(out_->axial(ConstraintType::weld, b1, b2, at(b2).position, Vector3d::UnitX()));
  }

  const std::string& path_;
  const mjModel* m_;
  const mjData* d_;
  Mechanism* out_;
  MjcfDropped* dropped_;
};


// What the converter reads of the compiled model must be finite, and the timestep positive:
// MuJoCo steps a negative or infinite timestep without complaint.
void check_compiled(const std::string& path, const mjModel* m, const mjData* d) {
  auto fail = [&](const std::string& what, const std::string& problem) { refuse_model(path, what, problem); };
  if (!(m->opt.timestep > 0) || !std::isfinite(m->opt.timestep))
    fail("option timestep", "must be finite and > 0, got " + format_number(m->opt.timestep));
  auto finite = [](const mjtNum* p, int n) { return std::all_of(p, p + n, [](mjtNum x) { return std::isfinite(x); }); };
  if (!finite(m->opt.gravity, 3)) fail("option gravity", "not finite");
  for (int b = 0; b < m->nbody; ++b) {
    if (finite(m->body_mass + b, 1) && finite(m->body_inertia + 3 * b, 3) && finite(d->xipos + 3 * b, 3) &&
        finite(d->ximat + 9 * b, 9) && finite(d->xpos + 3 * b, 3) && finite(d->xquat + 4 * b, 4))
      continue;
    std::string what = "body \"";
    what += printable(m->names + m->name_bodyadr[b], 80);
    what += "\"";
    fail(what, "its compiled mass, inertia or pose is not finite");
  }
  for (int j = 0; j < m->njnt; ++j) {
    if (finite(d->xanchor + 3 * j, 3) && finite(d->xaxis + 3 * j, 3) && finite(m->jnt_range + 2 * j, 2)) continue;
    std::string what = "joint \"";
    what += printable(m->names + m->name_jntadr[j], 80);
    what += "\"";
    fail(what, "its compiled anchor, axis or range is not finite");
  }
  if (!finite(m->qpos0, m->nq)) fail("qpos0", "not finite");
  if (!finite(m->eq_data, mjNEQDATA * m->neq)) fail("equality data", "not finite");
}

}  // namespace

Mechanism load_mjcf(const std::string& path, MjcfDropped* dropped) {
  check_mjcf_numbers(path);
  char error[1024] = "";
  std::unique_ptr<mjModel, ModelDeleter> model(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
  if (!model) {
    std::string s = printable(path);
    s += ": MuJoCo cannot load it: ";
    std::string message = error;
    for (char& ch : message)
      if (ch == '\n') ch = ' ';  // one line
    while (!message.empty() && message.back() == ' ') message.pop_back();
    s += message.empty() ? "unknown error" : printable(message);
    throw InputError(s);
  }
  std::unique_ptr<mjData, DataDeleter> data(mj_makeData(model.get()));  // qpos = qpos0, qvel = 0
  mj_kinematics(model.get(), data.get());  // poses only: no collision detection, no dynamics
  check_compiled(path, model.get(), data.get());
  Mechanism m;
  m.name = std::filesystem::path(path).stem().string();
  MjcfDropped ignored;
  Converter(path, model.get(), data.get(), &m, dropped ? dropped : &ignored).run();
  check_ranges(m, path);
  return m;
}

#endif

}  // namespace ldlpgs
