// MJCF -> Mechanism in maximal coordinates (the table and the universal joint: mjcf.h). MuJoCo
// compiles the file; we read the compiled mjModel and the kinematics of mj_kinematics at qpos0:
// xipos/ximat (each body's centre of mass and principal frame, our RigidBody's pose), xanchor
// and xaxis (each joint's point and axis, world frame), xpos/xquat (body frames, for the
// equalities' data, which MuJoCo gives in body frames).
#include "ldlpgs/physics/io/mjcf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "ldlpgs/physics/io/mjcf_input.h"
#include "ldlpgs/physics/io/scene.h"
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
  add(dropped.geoms, "geoms of types without a shape (no contacts)");
  add(dropped.contact_pairs, "contact pairs and excludes");
  add(dropped.tendons, "tendons");
  add(dropped.actuators, "actuators");
  add(dropped.sensors, "sensors");
  add(dropped.joint_dynamics, "free joints' stiffness/damping/armature/friction loss");
  add(dropped.ranges, "joint ranges (joints beside a free joint)");
  add(dropped.inactive_equalities, "inactive equalities");
  add(dropped.static_equalities, "equalities between static bodies");
  add(dropped.keyframes, "keyframes (we start at qpos0, at rest)");
  add(dropped.fluid, "geoms' ellipsoid fluid model (fluidshape)");
  return s;
}

#ifndef LDLPGS_HAVE_MUJOCO

bool mjcf_supported() { return false; }

Mechanism load_mjcf(const std::string& path, MjcfDropped*, bool) {
  throw InputError(path + ": MJCF models need MuJoCo (Debian's libmujoco-dev); rebuild with it installed");
}

#else

bool mjcf_supported() { return true; }

namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

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
    out_->gravity = disabled(mjDSBL_GRAVITY) ? Vector3d::Zero() : vec3(m_->opt.gravity);
    out_->timestep = m_->opt.timestep;
    for (int b = 0; b < m_->nbody; ++b) out_->add_body(body(b));
    for (int g = 0; g < m_->ngeom; ++g) geom(g);
    if (!contacts()) switch_off_contacts();
    for (int b = 1; b < m_->nbody; ++b) joint_rows(b);
    for (int j = 0; j < m_->njnt; ++j) joint_dynamics(j);
    for (int a = 0; a < m_->nu; ++a) actuator(a);
    for (int j = 0; j < m_->njnt; ++j) dynamics_rows(j);
    for (int e = 0; e < m_->neq; ++e) equality(e);
    out_->actuation = !disabled(mjDSBL_ACTUATION);
    for (Constraint& c : out_->constraints) c.collide = mujoco_may_collide(c.body_a, c.body_b);
    count_dropped();
  }

 private:
  // MuJoCo's <flag> switches (mjtDisableBit). "constraint" disables every constraint of MuJoCo's:
  // contacts, limits, equalities and friction loss (a joint is no constraint there).
  bool disabled(int flag) const { return (m_->opt.disableflags & flag) != 0; }
  bool contacts() const { return !disabled(mjDSBL_CONTACT) && !disabled(mjDSBL_CONSTRAINT); }
  bool limits() const { return !disabled(mjDSBL_LIMIT) && !disabled(mjDSBL_CONSTRAINT); }
  bool equalities() const { return !disabled(mjDSBL_EQUALITY) && !disabled(mjDSBL_CONSTRAINT); }

  // Contacts disabled: the shapes stay (they are drawn) but touch nothing.
  void switch_off_contacts() {
    for (RigidBody& body : out_->bodies)
      for (Shape& shape : body.shapes) shape.contype = shape.conaffinity = 0;
  }

  // What is not converted; what a flag switches off is not dropped. Each kind that changes the
  // dynamics is also described by its first element (MjcfDropped::unmodelled).
  void count_dropped() {
    dropped_->contact_pairs = contacts() ? m_->npair + m_->nexclude : 0;
    if (dropped_->contact_pairs > 0)
      unmodelled(m_->npair > 0 ? "contact pair 0" : "contact exclude 0", "explicit contact pairs and excludes are not modelled");
    for (int t = 0; t < m_->ntendon; ++t) tendon(t);
    dropped_->sensors = m_->nsensor;
    dropped_->keyframes = m_->nkey;
    fluid();
  }

  // MuJoCo's fluid forces: the inertia-box model (fluid.h) on every body, unless passive forces
  // are off; a geom with fluidshape="ellipsoid" puts its body on MuJoCo's other model, not modelled.
  void fluid() {
    if (disabled(mjDSBL_PASSIVE) || !(m_->opt.density > 0 || m_->opt.viscosity > 0)) return;
    out_->fluid.density = m_->opt.density;
    out_->fluid.viscosity = m_->opt.viscosity;
    out_->fluid.wind = vec3(m_->opt.wind);
    for (int g = 0; g < m_->ngeom; ++g) {
      if (m_->geom_fluid[mjNFLUID * g] == 0) continue;
      ++dropped_->fluid;
      unmodelled(quoted("geom", name(m_->name_geomadr[g], "geom", g)), "fluidshape=\"ellipsoid\" is not modelled (the inertia box is)");
    }
  }

  // A tendon changes the dynamics only through its range, spring, damper, friction loss or an
  // actuator (refused with the actuator); a bare one (humanoid's hip-knee couplings) is inert.
  void tendon(int t) {
    const bool passive = !disabled(mjDSBL_PASSIVE);
    const bool active = (m_->tendon_limited[t] && limits()) || (passive && m_->tendon_stiffness[t] != 0) ||
                        (passive && m_->tendon_damping[t] != 0) || (friction_loss() && m_->tendon_frictionloss[t] != 0);
    if (!active) return;
    ++dropped_->tendons;
    unmodelled(quoted("tendon", name(m_->name_tendonadr[t], "tendon", t)),
               "its range, stiffness, damping or friction loss is not modelled (tendons are not converted)");
  }

  void unmodelled(const std::string& element, const std::string& feature) {
    dropped_->unmodelled.push_back(element + ": " + feature);
  }
  static std::string quoted(const char* kind, const std::string& name) {
    std::string s = kind;
    s += " \"";
    s += name;
    s += "\"";
    return s;
  }
  bool friction_loss() const { return !disabled(mjDSBL_FRICTIONLOSS) && !disabled(mjDSBL_CONSTRAINT); }

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
    J.limited = m_->jnt_limited[j] && limits();
    if (J.limited && (J.type == mjJNT_HINGE || J.type == mjJNT_SLIDE)) {
      const double q0 = m_->qpos0[m_->jnt_qposadr[j]];
      J.lo = m_->jnt_range[2 * j] - q0;
      J.hi = m_->jnt_range[2 * j + 1] - q0;
    }
    if (J.limited && J.type == mjJNT_BALL) J.hi = m_->jnt_range[2 * j + 1];  // the cone's angle; lo = 0
    return J;
  }

  // A geom becomes a Shape on its body (a mesh: its convex hull, as MuJoCo collides it); a type
  // shape.h lacks is dropped. MuJoCo gives the geom's pose in its body frame, ours is the
  // inertial frame (ipos, iquat in that body frame), so: position = iquat^-1 (pos - ipos),
  // orientation = iquat^-1 quat.
  void geom(int g) {
    const int b = m_->geom_bodyid[g];
    const mjtNum* size = m_->geom_size + 3 * g;  // (size 3) per type (mjmodel.h)
    const auto refuse = [&](const std::string& problem) {
      std::string what = "geom \"";
      what += name(m_->name_geomadr[g], "geom", g);
      what += "\" on ";
      what += body_label(b);
      fail(what, problem);
    };
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
      case mjGEOM_CYLINDER:  // size[0] radius, size[1] half height on the geom's z
        s.type = ShapeType::cylinder;
        s.radius = size[0];
        s.half_length = size[1];
        break;
      case mjGEOM_ELLIPSOID:
        s.type = ShapeType::ellipsoid;
        s.half_extents = vec3(size);
        break;
      case mjGEOM_MESH: {
        // The compiled hull (mesh_graph: numvert, numface, vert_edgeadr[numvert],
        // vert_globalid[numvert], edge_localid[numvert + 3 numface], face_globalid[3 numface]),
        // its vertices already in the geom's frame. MuJoCo makes none for a mesh no geom can
        // collide with (contype = conaffinity = 0), nor with compiler convexhull="false".
        const int mesh = m_->geom_dataid[g], adr = m_->mesh_graphadr[mesh];
        if (adr < 0) {
          if (m_->geom_contype[g] == 0 && m_->geom_conaffinity[g] == 0) return;  // touches nothing: no shape needed
          refuse("its mesh has no convex hull compiled (compiler convexhull=\"false\"?): we collide meshes by theirs");
        }
        const int* graph = m_->mesh_graph + adr;
        const int hull_vertices = graph[0], hull_faces = graph[1];
        const int* vertex_id = graph + 2 + hull_vertices;
        const int* face_id = graph + 2 + 3 * hull_vertices + 3 * hull_faces;
        const float* vertex = m_->mesh_vert + 3 * m_->mesh_vertadr[mesh];
        std::vector<int> hull_index(m_->mesh_vertnum[mesh], -1);  // mesh vertex -> hull vertex
        std::vector<Vector3d> vertices;
        for (int i = 0; i < hull_vertices; ++i) {
          hull_index[vertex_id[i]] = i;
          vertices.emplace_back(vertex[3 * vertex_id[i]], vertex[3 * vertex_id[i] + 1], vertex[3 * vertex_id[i] + 2]);
        }
        std::vector<std::array<int, 3>> faces;
        for (int f = 0; f < hull_faces; ++f)
          faces.push_back({hull_index[face_id[3 * f]], hull_index[face_id[3 * f + 1]], hull_index[face_id[3 * f + 2]]});
        s.type = ShapeType::convex;
        s.hull = std::make_shared<const ConvexHull>(make_convex_hull(std::move(vertices), std::move(faces)));
        break;
      }
      case mjGEOM_HFIELD: {
        // hfield_size: (radius x, radius y, elevation z, base z); the data 0..1 scales to the
        // elevation, row r at y = -radius_y + r 2 radius_y / (nrow - 1), column c likewise in x
        // (mjc_ConvexHField)
        const int field = m_->geom_dataid[g];
        const mjtNum* field_size = m_->hfield_size + 4 * field;
        auto f = std::make_shared<HeightField>();
        f->rows = m_->hfield_nrow[field];
        f->cols = m_->hfield_ncol[field];
        f->half_x = field_size[0];
        f->half_y = field_size[1];
        f->base = field_size[3];
        const float* data = m_->hfield_data + m_->hfield_adr[field];
        for (int k = 0; k < f->rows * f->cols; ++k) f->heights.push_back(data[k] * field_size[2]);
        s.type = ShapeType::heightfield;
        s.field = std::move(f);
        break;
      }
      default: ++dropped_->geoms; return;  // a type MuJoCo 2.2.2 does not have
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
    if (!problem.empty()) refuse(problem);
    out_->bodies[b].shapes.push_back(s);
  }

  // MuJoCo's body-pair filter (mj_collision): bodies of one weld group (body_weldid) never touch,
  // nor a weld group and its parent's unless one is the world or filterparent is disabled.
  bool mujoco_may_collide(int b1, int b2) const {
    const int w1 = m_->body_weldid[b1], w2 = m_->body_weldid[b2];
    if (w1 == w2) return false;
    const int parent1 = m_->body_weldid[m_->body_parentid[w1]], parent2 = m_->body_weldid[m_->body_parentid[w2]];
    const bool filter_parent = !disabled(mjDSBL_FILTERPARENT);
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

  // The joints of body b, in MuJoCo's order.
  struct JointSet {
    int parent = -1, body = -1;
    std::vector<Joint> all;  // (size: the body's joints)
  };
  JointSet joint_set(int b) const {
    JointSet set;
    set.parent = m_->body_parentid[b];
    set.body = b;
    for (int j = m_->body_jntadr[b]; j < m_->body_jntadr[b] + m_->body_jntnum[b]; ++j) {
      set.all.push_back(joint(j));
    }
    return set;
  }

  // The joints between body b and its parent as rows (the table in mjcf.h): one hinge, slide or
  // ball keeps its own constraint type; any other set is one joint_set (joint_set.h), which
  // removes exactly what the set does not allow, and each range is a limit in MuJoCo's own
  // coordinate.
  void joint_rows(int b) {
    if (at(b).is_static) return;  // welded to the world: no joints, nothing to hold
    const JointSet set = joint_set(b);
    const int p = set.parent;
    const bool free = std::any_of(set.all.begin(), set.all.end(), [](const Joint& j) { return j.type == mjJNT_FREE; });
    if (set.all.empty()) {  // rigidly attached to a moving parent
      add(out_->axial(ConstraintType::weld, p, b, at(b).position, Vector3d::UnitX()));
    } else if (free) {
      // six degrees of freedom: no rows; the other joints' coordinates are redundant with it
      for (const Joint& j : set.all) {
        if (j.type == mjJNT_FREE || !j.limited) continue;
        ++dropped_->ranges;
        unmodelled(quoted("joint", joint_name(j.id)), "a range beside a free joint is not modelled");
      }
    } else if (set.all.size() == 1 && set.all[0].type != mjJNT_BALL) {
      axial_rows(set);
    } else {
      chain_rows(set);
    }
  }

  // One hinge or one slide: a hinge or prismatic joint with the limit of its coordinate.
  void axial_rows(const JointSet& set) {
    const int p = set.parent, b = set.body;
    const Joint& j = set.all[0];
    ChainJoint c;
    c.type = j.type == mjJNT_HINGE ? ChainJointType::hinge : ChainJointType::slide;
    c.anchor = j.anchor;
    c.axis = j.axis;
    chains_[b] = out_->joint_set(p, b, {c});  // measures the coordinate of its dynamics
    if (j.type == mjJNT_HINGE) {
      add(out_->axial(ConstraintType::hinge, p, b, j.anchor, j.axis));
      angular_limit(p, b, j);
    } else {
      add(out_->axial(ConstraintType::prismatic, p, b, at(b).position, j.axis));
      positional_limit(p, b, at(b).position, j);
    }
  }

  // Any other set (balls, hinges and slides, none free): a ball alone is a ball constraint, the
  // rest one joint_set; then each range as a coordinate_limit of the set's chain (a ball's: its
  // cone, the angle of its rotation).
  void chain_rows(const JointSet& set) {
    const int p = set.parent, b = set.body;
    const int dofs = m_->body_dofnum[b];
    if (dofs > kMaxChainDofs) {
      std::string why = std::to_string(dofs);
      why += " degrees of freedom in its joints, more than a body has (";
      why += std::to_string(kMaxChainDofs);
      why += ")";
      fail(body_label(b), why);
    }
    std::vector<ChainJoint> joints;  // (size: the body's joints)
    for (const Joint& j : set.all) {
      ChainJoint c;
      c.type = j.type == mjJNT_HINGE ? ChainJointType::hinge
               : j.type == mjJNT_SLIDE ? ChainJointType::slide
                                       : ChainJointType::ball;
      c.anchor = j.anchor;
      c.axis = j.axis;
      joints.push_back(c);
    }
    const Constraint chain = out_->joint_set(p, b, joints);
    chains_[b] = chain;
    if (set.all.size() == 1) {
      add(out_->ball(p, b, set.all[0].anchor));
    } else if (num_rows(chain) > 0) {
      add(chain);
    }
    for (size_t k = 0; k < set.all.size(); ++k)
      if (set.all[k].limited) add(make_coordinate_limit(chain, static_cast<int>(k), set.all[k].lo, set.all[k].hi));
  }

  std::string joint_name(int j) const { return name(m_->name_jntadr[j], "joint", j); }
  int joint_dofs(int j) const { return m_->jnt_type[j] == mjJNT_FREE ? 6 : m_->jnt_type[j] == mjJNT_BALL ? 3 : 1; }

  // Joint j's dofs' passive dynamics (actuation.h), on the chain of its body: armature always,
  // stiffness and damping unless passive forces are off, friction loss unless it is. A free
  // joint's, or one beside it, is not modelled.
  void joint_dynamics(int j) {
    const int b = m_->jnt_bodyid[j], type = m_->jnt_type[j];
    const int dofs = joint_dofs(j);
    const bool passive = !disabled(mjDSBL_PASSIVE);
    for (int k = 0; k < dofs; ++k) {
      const int dof = m_->jnt_dofadr[j] + k;
      DofDynamics d;
      d.armature = m_->dof_armature[dof];
      d.damping = passive ? m_->dof_damping[dof] : 0;
      d.stiffness = passive ? m_->jnt_stiffness[j] : 0;
      d.frictionloss = friction_loss() ? m_->dof_frictionloss[dof] : 0;
      if (type == mjJNT_HINGE || type == mjJNT_SLIDE) {
        d.offset = m_->qpos0[m_->jnt_qposadr[j]];
        d.springref = m_->qpos_spring[m_->jnt_qposadr[j]];
      }
      const bool moves = d.armature != 0 || d.damping != 0 || d.stiffness != 0 || d.frictionloss != 0;
      if (!moves || at(b).is_static) continue;
      if (!chains_[b]) {
        ++dropped_->joint_dynamics;
        unmodelled(quoted("joint", joint_name(j)), "its armature, damping, stiffness or friction loss on a free joint "
                   "(or beside one) is not modelled");
        return;
      }
      add_dof(j, k, d);
    }
  }

  // Dof k of joint j in Mechanism::dofs (once), measured on its body's chain.
  int add_dof(int j, int k, const DofDynamics& d) {
    const int key = m_->jnt_dofadr[j] + k;
    if (dof_index_[key] >= 0) return dof_index_[key];
    const int b = m_->jnt_bodyid[j];
    DofDynamics dof = d;
    dof.coordinate = make_dof_row(ConstraintType::dof_drive, *chains_[b], key - m_->body_dofadr[b]);
    out_->dofs.push_back(dof);
    return dof_index_[key] = static_cast<int>(out_->dofs.size()) - 1;
  }

  // Actuator a (actuation.h): on a hinge or slide, no activation dynamics, fixed gain, affine
  // bias. Others are not modelled.
  void actuator(int a) {
    const std::string label = quoted("actuator", name(m_->name_actuatoradr[a], "actuator", a));
    const int trn = m_->actuator_trntype[a], j = m_->actuator_trnid[2 * a];
    const char* problem = nullptr;
    if (trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT) problem = "a transmission other than a joint's";
    else if (m_->jnt_type[j] != mjJNT_HINGE && m_->jnt_type[j] != mjJNT_SLIDE) problem = "a ball or free joint's transmission";
    else if (!at(m_->jnt_bodyid[j]).is_static && !chains_[m_->jnt_bodyid[j]]) problem = "a joint beside a free joint";
    else if (m_->actuator_dyntype[a] != mjDYN_NONE) problem = "activation dynamics (dyntype)";
    else if (m_->actuator_gaintype[a] != mjGAIN_FIXED) problem = "a gain other than fixed";
    else if (m_->actuator_biastype[a] != mjBIAS_NONE && m_->actuator_biastype[a] != mjBIAS_AFFINE) problem = "a bias other than affine";
    Actuator act;
    act.name = name(m_->name_actuatoradr[a], "actuator", a);
    act.ctrl_limited = m_->actuator_ctrllimited[a];
    act.ctrl_min = m_->actuator_ctrlrange[2 * a];
    act.ctrl_max = m_->actuator_ctrlrange[2 * a + 1];
    if (problem || at(m_->jnt_bodyid[j]).is_static) {
      // kept with no effect, so that the controls keep MuJoCo's order
      act.gain = 0;
      out_->actuators.push_back(act);
      if (problem && !disabled(mjDSBL_ACTUATION)) {
        ++dropped_->actuators;
        unmodelled(label, std::string(problem) + " is not modelled");
      }
      return;
    }
    act.gear = m_->actuator_gear[6 * a];
    act.gain = m_->actuator_gainprm[mjNGAIN * a];
    if (m_->actuator_biastype[a] == mjBIAS_AFFINE)
      for (int k = 0; k < 3; ++k) act.bias[k] = m_->actuator_biasprm[mjNBIAS * a + k];
    act.force_limited = m_->actuator_forcelimited[a];
    act.force_min = m_->actuator_forcerange[2 * a];
    act.force_max = m_->actuator_forcerange[2 * a + 1];
    act.dof = add_dof(j, 0, DofDynamics{});
    out_->actuators.push_back(act);
  }

  // The rows the dofs' dynamics need, after the actuators are known: a dof_drive where armature,
  // damping or a velocity servo of unlimited force softens the dof, a dof_motor for its friction
  // loss and for each force-limited velocity servo.
  void dynamics_rows(int j) {
    const int dofs = joint_dofs(j);
    for (int k = 0; k < dofs; ++k) {
      const int d = dof_index_[m_->jnt_dofadr[j] + k];
      if (d < 0) continue;
      DofDynamics& dof = out_->dofs[d];
      bool soft = dof.armature > 0 || dof.damping > 0;
      for (Actuator& a : out_->actuators) {
        if (a.dof != d || !(a.bias[2] < 0) || a.gear == 0) continue;
        if (a.force_limited) a.motor = add(make_dof_row(ConstraintType::dof_motor, dof.coordinate, dof.coordinate.joint));
        else soft = true;
      }
      if (soft) dof.drive = add(dof.coordinate);
      if (dof.frictionloss > 0) dof.friction = add(make_dof_row(ConstraintType::dof_motor, dof.coordinate, dof.coordinate.joint));
    }
  }

  void equality(int e) {
    std::string label = "equality \"";
    label += name(m_->name_eqadr[e], "equality", e);
    label += "\" (";
    label += equality_type_name(m_->eq_type[e]);
    label += ")";
    if (!m_->eq_active[e] || !equalities()) {
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
  std::vector<std::optional<Constraint>> chains_ = std::vector<std::optional<Constraint>>(m_->nbody);  // each body's joints
  std::vector<int> dof_index_ = std::vector<int>(m_->nv, -1);  // MuJoCo's dof -> Mechanism::dofs
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

Mechanism load_mjcf(const std::string& path, MjcfDropped* dropped, bool allow_dropped) {
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
  MjcfDropped& out = dropped ? *dropped : ignored;
  Converter(path, model.get(), data.get(), &m, &out).run();
  if (!allow_dropped && !out.unmodelled.empty())
    throw InputError(printable(path) + ": " + out.unmodelled.front() + " (allow_dropped, --allow-dropped, steps without it)");
  check_ranges(m, path);
  return m;
}

#endif

}  // namespace ldlpgs
