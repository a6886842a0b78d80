// MuJoCo 2.2.2 as a peer in maximal coordinates: every dynamic body a free body (<freejoint/>,
// its mass and principal inertia at its origin), every static body a body without joints, and
// the joints as equality constraints: ball = <connect>, weld = <weld>, hinge = two <connect>s
// on the axis (at the anchor and 0.1 m along it; the pair removes the 5 degrees of freedom a
// hinge does, with one redundant row along the axis, which MuJoCo's soft constraints absorb).
// MuJoCo has no prismatic equality. The model is an MJCF string loaded through a temporary
// file (mj_loadXML), at MuJoCo's hardest settings: Newton solver, 100 iterations, tolerance 0,
// semi-implicit Euler (as ours), every equality solref = (2 timestep, 1) (the
// stiffest MuJoCo accepts without refsafe off) and solimp (0.9999, 0.9999, 0.001, 0.5, 2).
//
// Contacts where the mechanism has shapes (off otherwise): each shape a geom of its body at its
// pose in the body frame (plane, sphere, capsule along z and box are MuJoCo's types; a plane's z
// is our normal), condim 3 with friction (our mu, 0, 0), our contype and conaffinity, and an
// <exclude> for each pair of bodies joined without `collide` (reduced coordinates also leave
// parent and child apart themselves). MuJoCo's defaults otherwise: soft contacts (solref 0.02 1,
// solimp 0.9 0.95 0.001), the pyramidal cone, margin 0. Its pair rule for friction is the larger
// of the two geoms' (ours: sqrt(mu_a mu_b); the same where they agree, as in every built-in
// scene); it has no restitution (every built-in scene's is 0).
//
// And, where the body graph is a forest, in MuJoCo's own reduced coordinates (run_mujoco_tree):
// bodies nested from the static ones (the world) or from a free root, each joint a MuJoCo joint
// of the child (ball, hinge, slide = our prismatic; a weld nests the body with no joint), so the
// joints cannot separate; the same options, no equality constraints. With rk4, MuJoCo's RK4
// (mjINT_RK4) at timestep / 16: the second reference trajectory, for trees (peer.h).
//
// And, for a scene read from an MJCF file, that file itself (run_mujoco_mjcf): MuJoCo's own
// model in its reduced coordinates, as the file has it (joint dynamics, actuators at zero
// controls, fluid forces: what physics/io/mjcf.h converts), but contacts off where the conversion kept
// no shape (with shapes, MuJoCo collides its own geoms, the floor included). Its bodies are ours
// with the same index (physics/io/mjcf.h), our centres of mass its xipos.
#include <mujoco/mujoco.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "peers/engines.h"
#include "ldlpgs/physics/collision.h"

namespace ldlpgs::peers {

namespace {

// The shapes MuJoCo's geoms express here (convex hulls and heightfields would need assets).
const std::initializer_list<ShapeType> kMujocoShapes = {ShapeType::plane, ShapeType::sphere,   ShapeType::capsule,
                                                        ShapeType::box,   ShapeType::cylinder, ShapeType::ellipsoid};

constexpr double kHingeArm = 0.1;  // m: the second connect's offset along a hinge's axis

struct Connect {
  int a, b;  // body ids in MuJoCo (world = 0; ours + 1)
  Eigen::Vector3d on_a, on_b;  // anchors in each body's frame
};

std::string v3(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(17);
  s << v.x() << ' ' << v.y() << ' ' << v.z();
  return s.str();
}

std::string wxyz(const Eigen::Quaterniond& q) {
  std::ostringstream s;
  s.precision(17);
  s << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z();
  return s.str();
}

std::string options(const Mechanism& m, const char* integrator = "Euler") {
  std::ostringstream x;
  x.precision(17);
  x << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "<option timestep=\"" << m.timestep << "\" gravity=\"" << v3(m.gravity)
    << "\" integrator=\"" << integrator << "\" solver=\"Newton\" iterations=\"100\" tolerance=\"0\">\n";
  if (!has_shapes(m)) x << "<flag contact=\"disable\"/>\n";
  x << "</option>\n";
  return x.str();
}

// A body's shapes as geoms in its frame (the body frame is ours in the models built here).
std::string geoms(const RigidBody& b) {
  std::ostringstream x;
  x.precision(17);
  for (const Shape& s : b.shapes) {
    x << "<geom type=\"" << to_string(s.type) << "\" size=\"";
    switch (s.type) {
      case ShapeType::plane: x << "0 0 1"; break;
      case ShapeType::sphere: x << s.radius; break;
      case ShapeType::capsule: x << s.radius << ' ' << s.half_length; break;
      case ShapeType::box:
      case ShapeType::ellipsoid: x << v3(s.half_extents); break;
      case ShapeType::cylinder: x << s.radius << ' ' << s.half_length; break;
      case ShapeType::convex:
      case ShapeType::heightfield: break;  // (the MuJoCo peers skip mechanisms with these)
    }
    const Eigen::Quaterniond q = s.type == ShapeType::plane
                                     ? Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), s.normal)
                                     : s.orientation;
    x << "\" pos=\"" << v3(s.position) << "\" quat=\"" << wxyz(q) << "\" condim=\"3\" friction=\"" << s.friction
      << " 0 0\" contype=\"" << s.contype << "\" conaffinity=\"" << s.conaffinity << "\"/>";
  }
  return x.str();
}

// <size> for `rows` constraint rows and, with shapes, up to 16 contacts per geom, then <contact>
// excluding the bodies joined without `collide`.
std::string size_and_contacts(const Mechanism& m, int rows) {
  std::ostringstream x;
  if (!has_shapes(m)) {
    x << "<size njmax=\"" << rows + 16 << "\" nconmax=\"1\"/>\n";
    return x.str();
  }
  std::set<std::pair<int, int>> excluded;
  for (const Constraint& c : m.constraints)
    if (!c.collide) excluded.emplace(std::minmax(c.body_a, c.body_b));
  x << "<contact>";
  for (const auto& [a, b] : excluded) x << "<exclude body1=\"b" << a << "\" body2=\"b" << b << "\"/>";
  int shapes = 0;
  for (const RigidBody& b : m.bodies) shapes += static_cast<int>(b.shapes.size());
  const int contacts = 16 * shapes + 16;  // a box on two boxes: 8 points on each
  x << "</contact>\n<size njmax=\"" << rows + 16 + 4 * contacts << "\" nconmax=\"" << contacts << "\"/>\n";  // 4 rows: the pyramid
  return x.str();
}

std::string mjcf(const Mechanism& m, const std::vector<Connect>& connects, int rows) {
  std::ostringstream x;
  x.precision(17);
  std::ostringstream soft;
  soft.precision(17);
  soft << "solref=\"" << 2 * m.timestep << " 1\" solimp=\"0.9999 0.9999 0.001 0.5 2\"";
  const std::string solref = soft.str();
  x << "<mujoco model=\"peers\">\n" << options(m) << size_and_contacts(m, rows) << "<worldbody>\n";
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const RigidBody& b = m.bodies[i];
    const Eigen::Quaterniond& q = b.orientation;
    x << "<body name=\"b" << i << "\" pos=\"" << v3(b.position) << "\" quat=\"" << q.w() << ' ' << q.x() << ' '
      << q.y() << ' ' << q.z() << "\">";
    if (!b.is_static)
      x << "<freejoint/><inertial pos=\"0 0 0\" mass=\"" << b.mass << "\" diaginertia=\"" << v3(b.inertia) << "\"/>";
    x << geoms(b) << "</body>\n";
  }
  x << "</worldbody>\n<equality>\n";
  for (const Connect& c : connects)
    x << "<connect body1=\"b" << c.a - 1 << "\" body2=\"b" << c.b - 1 << "\" anchor=\"" << v3(c.on_a) << "\" "
      << solref << "/>\n";
  for (const Constraint& c : m.constraints)
    if (c.type == ConstraintType::weld)
      x << "<weld body1=\"b" << c.body_a << "\" body2=\"b" << c.body_b << "\" " << solref << "/>\n";
  x << "</equality>\n</mujoco>\n";
  return x.str();
}

void set_free_velocity(const mjModel* model, mjData* data, int body, const RigidBody& b) {
  const int dof = model->jnt_dofadr[model->body_jntadr[body]];
  const Eigen::Vector3d w = b.orientation.conjugate() * b.angular_velocity;
  for (int k = 0; k < 3; ++k) {
    data->qvel[dof + k] = b.linear_velocity[k];
    data->qvel[dof + 3 + k] = w[k];
  }
}

// The MJCF through a temporary file (mj_loadXML reads files); nullptr and *error if refused.
mjModel* load(const std::string& xml, std::string* error) {
  static std::atomic<int> counter{0};
  std::string file = "ldlpgs-peers-";
  file += std::to_string(getpid());
  file += '-';
  file += std::to_string(counter++);
  file += ".xml";
  const std::filesystem::path path = std::filesystem::temp_directory_path() / file;
  std::ofstream(path) << xml;
  char message[1000] = "";
  mjModel* model = mj_loadXML(path.c_str(), nullptr, message, sizeof message);
  std::filesystem::remove(path);
  if (!model) {
    *error = "MuJoCo refused the model: ";
    for (const char* c = message; *c; ++c) *error += *c == '\n' ? ' ' : *c;  // one line
    while (!error->empty() && error->back() == ' ') error->pop_back();
  }
  return model;
}

// Steps round(seconds / timestep) times, recording every body's pose (MuJoCo body id[i] for
// ours i: its inertial frame, xipos and ximat, which is the body frame in the models built here)
// in *state and r (record_poses); r->step_us the median of mj_step alone.
void step_and_record(const mjModel* model, mjData* data, const Mechanism& m, double seconds,
                     const std::vector<int>& id, Mechanism* state, PeerResult* r) {
  mj_forward(model, data);
  auto read_back = [&] {
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      // static bodies stay at our pose: MuJoCo puts the inertial frame of a massless body (the
      // pivot of ball-chain-20-1000, 2 m up) at the origin
      if (m.bodies[i].is_static) continue;
      const mjtNum* p = data->xipos + 3 * id[i];
      mjtNum q[4];
      mju_mat2Quat(q, data->ximat + 9 * id[i]);
      state->bodies[i].position = Eigen::Vector3d(p[0], p[1], p[2]);
      state->bodies[i].orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    }
    record_poses(*state, r);
  };
  // mj_kinematics: xipos, ximat of the new qpos (mj_step leaves them one step behind); untimed
  timed_steps(m, seconds, [&] { mj_step(model, data); }, [&] {
    mj_kinematics(model, data);
    read_back();
  }, r);
  for (const RigidBody& b : state->bodies) r->finite = r->finite && b.position.allFinite();
}

}  // namespace

PeerResult run_mujoco(const Mechanism& m, double seconds) {
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::weld}, "MuJoCo");
  if (r.ran()) r.skipped = unsupported(m, kMujocoShapes, "MuJoCo");
  if (!r.ran()) return r;
  std::vector<Connect> connects;
  int rows = 0;
  for (const Constraint& c : m.constraints) {
    if (c.type == ConstraintType::weld) {
      rows += 6;
      continue;
    }
    connects.push_back({c.body_a + 1, c.body_b + 1, c.anchor_a, c.anchor_b});
    rows += 3;
    if (c.type == ConstraintType::hinge) {
      connects.push_back({c.body_a + 1, c.body_b + 1, c.anchor_a + kHingeArm * c.frame_a.col(2),
                          c.anchor_b + kHingeArm * c.frame_b.col(2)});
      rows += 3;
    }
  }
  std::string error;
  mjModel* model = load(mjcf(m, connects, rows), &error);
  if (!model) {
    r.skipped = error;
    return r;
  }
  // connect's anchor on body 2 is MuJoCo's eq_data[3..5]; ours, exactly (the compiler derives it
  // from the initial pose, the same point up to rounding).
  for (size_t e = 0; e < connects.size(); ++e)
    for (int k = 0; k < 3; ++k) model->eq_data[e * mjNEQDATA + 3 + k] = connects[e].on_b[k];
  mjData* data = mj_makeData(model);
  // initial velocities: a free joint's qvel is the linear velocity (world) then the angular
  // velocity in the body's own frame
  for (size_t i = 0; i < m.bodies.size(); ++i)
    if (!m.bodies[i].is_static) set_free_velocity(model, data, i + 1, m.bodies[i]);
  std::vector<int> id(m.bodies.size());
  for (size_t i = 0; i < id.size(); ++i) id[i] = i + 1;
  Mechanism state = m;
  step_and_record(model, data, m, seconds, id, &state, &r);

  // MuJoCo's own connect points (its eq_data carried by its xpos, xmat); welds ours, on its poses
  for (size_t e = 0; e < connects.size(); ++e) {
    Eigen::Vector3d p[2];
    for (int j = 0; j < 2; ++j) {
      const int body = j == 0 ? connects[e].a : connects[e].b;
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(data->xmat + 9 * body);
      p[j] = Eigen::Map<const Eigen::Vector3d>(data->xpos + 3 * body) +
             rot * Eigen::Map<const Eigen::Vector3d>(model->eq_data + e * mjNEQDATA + 3 * j);
    }
    r.separation = std::max(r.separation, (p[0] - p[1]).norm());
  }
  for (const Constraint& c : m.constraints)
    if (c.type == ConstraintType::weld)
      r.separation = std::max(r.separation, joint_separation(c, state.bodies[c.body_a], state.bodies[c.body_b]));
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  mj_deleteData(data);
  mj_deleteModel(model);
  return r;
}

namespace {

// The forest of the body graph: parent[i] = the body i hangs from (-1: a root; static bodies
// are roots, and so is one body of each tree that touches none), joint[i] its constraint;
// children in the order found (breadth first). "" or why the graph is not a forest.
struct Forest {
  std::vector<int> parent, joint;
  std::vector<std::vector<int>> children;
};
std::string forest(const Mechanism& m, Forest* f) {
  const int n = static_cast<int>(m.bodies.size());
  f->parent.assign(n, -1);
  f->joint.assign(n, -1);
  f->children.assign(n, {});
  std::vector<std::vector<int>> touching(n);  // constraints at each body
  for (size_t c = 0; c < m.constraints.size(); ++c) {
    touching[m.constraints[c].body_a].push_back(c);
    touching[m.constraints[c].body_b].push_back(c);
  }
  std::vector<bool> seen(n, false), used(m.constraints.size(), false);
  std::vector<int> queue;
  auto grow = [&](int root) {
    seen[root] = true;
    queue.assign(1, root);
    for (size_t q = 0; q < queue.size(); ++q)
      for (int c : touching[queue[q]]) {
        if (used[c]) continue;
        used[c] = true;
        const Constraint& k = m.constraints[c];
        const int other = k.body_a == queue[q] ? k.body_b : k.body_a;
        if (seen[other] || m.bodies[other].is_static) {
          std::string why = "not a tree: constraint ";
          why += std::to_string(c);
          why += " closes a loop";
          return why;
        }
        seen[other] = true;
        f->parent[other] = queue[q];
        f->joint[other] = c;
        f->children[queue[q]].push_back(other);
        queue.push_back(other);
      }
    return std::string();
  };
  for (int pass = 0; pass < 2; ++pass)  // static roots first, then free roots
    for (int i = 0; i < n; ++i)
      if (!seen[i] && m.bodies[i].is_static == (pass == 0)) {
        const std::string why = grow(i);
        if (!why.empty()) return why;
      }
  return "";
}

// One body of the nested MJCF, its children inside it; poses relative to the parent (the world
// for static bodies and their children, whose static parents are the world too).
void nest(const Mechanism& m, const Forest& f, int i, std::ostringstream& x) {
  const RigidBody& b = m.bodies[i];
  const int p = f.parent[i];
  const bool in_world = p < 0 || m.bodies[p].is_static;
  const Eigen::Quaterniond q = in_world ? b.orientation : m.bodies[p].orientation.conjugate() * b.orientation;
  const Eigen::Vector3d pos =
      in_world ? b.position : Eigen::Vector3d(m.bodies[p].orientation.conjugate() * (b.position - m.bodies[p].position));
  x << "<body name=\"b" << i << "\" pos=\"" << v3(pos) << "\" quat=\"" << wxyz(q) << "\">";
  if (!b.is_static) {
    if (p < 0) {
      x << "<freejoint/>";
    } else {
      const Constraint& c = m.constraints[f.joint[i]];
      const bool a_is_child = c.body_a == i;
      const Eigen::Vector3d anchor = a_is_child ? c.anchor_a : c.anchor_b;
      const Eigen::Vector3d axis = (a_is_child ? c.frame_a : c.frame_b).col(2);
      switch (c.type) {
        case ConstraintType::ball: x << "<joint type=\"ball\" pos=\"" << v3(anchor) << "\"/>"; break;
        case ConstraintType::hinge:
          x << "<joint type=\"hinge\" pos=\"" << v3(anchor) << "\" axis=\"" << v3(axis) << "\"/>";
          break;
        case ConstraintType::prismatic:
          x << "<joint type=\"slide\" pos=\"" << v3(anchor) << "\" axis=\"" << v3(axis) << "\"/>";
          break;
        default: break;  // weld: nested without a joint
      }
    }
    x << "<inertial pos=\"0 0 0\" mass=\"" << b.mass << "\" diaginertia=\"" << v3(b.inertia) << "\"/>";
  }
  x << geoms(b) << "\n";
  if (b.is_static) x << "</body>\n";  // a static body's children sit in the world
  for (int child : f.children[i]) nest(m, f, child, x);
  if (!b.is_static) x << "</body>\n";
}

}  // namespace

PeerResult run_mujoco_tree(const Mechanism& scene, double seconds, bool rk4) {
  Mechanism m = scene;
  if (rk4) m.timestep /= 16;
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                              ConstraintType::weld}, "MuJoCo (reduced coordinates)");
  if (r.ran()) r.skipped = unsupported(m, kMujocoShapes, "MuJoCo (reduced coordinates)");
  Forest f;
  if (r.ran()) r.skipped = forest(m, &f);
  if (!r.ran()) return r;
  std::ostringstream x;
  x.precision(17);
  x << "<mujoco model=\"peers-tree\">\n" << options(m, rk4 ? "RK4" : "Euler") << size_and_contacts(m, 0)
    << "<worldbody>\n";
  for (size_t i = 0; i < m.bodies.size(); ++i)
    if (f.parent[i] < 0) nest(m, f, i, x);
  x << "</worldbody>\n</mujoco>\n";
  std::string error;
  mjModel* model = load(x.str(), &error);
  if (!model) {
    r.skipped = error;
    return r;
  }
  mjData* data = mj_makeData(model);
  std::vector<int> id(m.bodies.size());
  for (size_t i = 0; i < id.size(); ++i) {
    std::string name = "b";
    name += std::to_string(i);
    id[i] = mj_name2id(model, mjOBJ_BODY, name.c_str());
  }
  // initial velocities: free roots as in maximal coordinates; a joint's qvel is the child's
  // angular velocity relative to its parent (ball: in the child's frame; hinge: about the axis)
  // or its velocity along the slide
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const RigidBody& b = m.bodies[i];
    if (b.is_static) continue;
    if (f.parent[i] < 0) {
      set_free_velocity(model, data, id[i], b);
      continue;
    }
    const RigidBody& p = m.bodies[f.parent[i]];
    const Constraint& c = m.constraints[f.joint[i]];
    if (c.type == ConstraintType::weld) continue;
    const int dof = model->jnt_dofadr[model->body_jntadr[id[i]]];
    const Eigen::Vector3d w = b.angular_velocity - p.angular_velocity;
    const Eigen::Vector3d axis = b.orientation * (c.body_a == static_cast<int>(i) ? c.frame_a : c.frame_b).col(2);
    if (c.type == ConstraintType::ball) {
      const Eigen::Vector3d local = b.orientation.conjugate() * w;
      for (int k = 0; k < 3; ++k) data->qvel[dof + k] = local[k];
    } else if (c.type == ConstraintType::hinge) {
      data->qvel[dof] = w.dot(axis);
    } else {  // slide: the child's velocity relative to the parent's point under its anchor, along the axis
      const Eigen::Vector3d at = b.position;
      data->qvel[dof] = (b.linear_velocity - p.linear_velocity - p.angular_velocity.cross(at - p.position)).dot(axis);
    }
  }
  Mechanism state = m;
  step_and_record(model, data, m, seconds, id, &state, &r);
  r.separation = joint_separation(state);  // 0 up to rounding: the joints are the coordinates
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  mj_deleteData(data);
  mj_deleteModel(model);
  return r;
}

PeerResult run_mujoco_mjcf(const std::string& path, const Mechanism& scene, double seconds, bool rk4) {
  PeerResult r;
  char message[1000] = "";
  mjModel* model = mj_loadXML(path.c_str(), nullptr, message, sizeof message);
  if (!model) {
    r.skipped = "MuJoCo refused ";
    r.skipped += path;
    return r;
  }
  if (model->nbody != static_cast<int>(scene.bodies.size())) {
    r.skipped = path;
    r.skipped += " is not this scene (its body count differs)";
    mj_deleteModel(model);
    return r;
  }
  if (!has_shapes(scene)) model->opt.disableflags |= mjDSBL_CONTACT;
  Mechanism m = scene;
  if (rk4) {
    m.timestep /= 16;
    model->opt.integrator = mjINT_RK4;
  }
  model->opt.timestep = m.timestep;
  for (int k = 0; k < 3; ++k) model->opt.gravity[k] = m.gravity[k];  // 0 if the file disabled it
  mjData* data = mj_makeData(model);
  std::vector<int> id(m.bodies.size());
  for (size_t i = 0; i < id.size(); ++i) id[i] = i;
  Mechanism state = m;
  step_and_record(model, data, m, seconds, id, &state, &r);
  // our anchors on MuJoCo's poses: its joints are its coordinates, so this reads back rounding
  // (and, with limits or equalities, how far its soft constraints let them give)
  r.separation = joint_separation(state);
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  mj_deleteData(data);
  mj_deleteModel(model);
  return r;
}

}  // namespace ldlpgs::peers
