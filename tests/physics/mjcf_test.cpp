// MJCF models as mechanisms (physics/io/mjcf.h), checked against MuJoCo itself: for every shipped
// model we can represent, the counts and masses MuJoCo reports, the centres of mass of its
// kinematics, and, at random configurations MuJoCo computes, that every joint row holds (c = 0)
// and annihilates every motion MuJoCo's coordinates allow (J V = 0 for the Jacobian of each dof)
// while the rows number exactly 6 n - nv: the rows remove exactly the degrees of freedom the
// joints do not allow. Then the humanoid in free fall, and one named test per bad input.
#include "ldlpgs/physics/io/mjcf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "tests/support/temp_files.h"

#ifdef LDLPGS_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace ldlpgs {
namespace {

using Eigen::Vector3d;
using testing::temp_file;

// The message of the InputError that loading `path` throws ("" if it loads).
std::string load_error(const std::string& path) {
  try {
    load_mjcf(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

#ifndef LDLPGS_HAVE_MUJOCO

TEST(Mjcf, WithoutMuJoCoEveryModelIsRefused) {
  const std::string message = load_error("model.xml");
  EXPECT_NE(message.find("model.xml: MJCF models need MuJoCo"), std::string::npos) << message;
}

#else

const std::string kModels = "/usr/share/mujoco/model";

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

ModelPtr mujoco_model(const std::string& path) {
  char error[1024] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
  EXPECT_TRUE(m) << path << ": " << error;
  return m;
}

const std::string kGymnasium = std::string(LDLPGS_TESTDATA) + "/mjcf/gymnasium";

std::vector<std::string> models_in(const std::string& dir) {
  std::vector<std::string> paths;
  std::error_code ec;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir, ec))
    if (entry.path().extension() == ".xml") paths.push_back(entry.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}
std::vector<std::string> shipped_models() { return models_in(kModels); }
std::vector<std::string> gymnasium_models() { return models_in(kGymnasium); }

// Equalities the converter turns into constraints (mjcf.h: after all the joints' constraints).
int converted_equalities(const mjModel* m) {
  int n = 0;
  for (int e = 0; e < m->neq; ++e) {
    const bool body_type = m->eq_type[e] == mjEQ_CONNECT || m->eq_type[e] == mjEQ_WELD;
    const bool both_static = m->body_weldid[m->eq_obj1id[e]] == 0 && m->body_weldid[m->eq_obj2id[e]] == 0;
    n += m->eq_active[e] && body_type && !both_static ? 1 : 0;
  }
  return n;
}

// Poses (xipos, ximat, ...), subtree centres of mass and the dof axes the Jacobians use; no
// collision detection (MuJoCo would warn of full contact buffers on the piled-up composites).
void kinematics(const mjModel* m, mjData* d) {
  mj_kinematics(m, d);
  mj_comPos(m, d);
}

// A random configuration: every coordinate moved from qpos0 (hinges, slides by up to 0.5;
// quaternions turned by up to ~0.5 rad; free positions shifted).
void random_configuration(const mjModel* m, mjData* d, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  mju_copy(d->qpos, m->qpos0, m->nq);
  for (int j = 0; j < m->njnt; ++j) {
    mjtNum* q = d->qpos + m->jnt_qposadr[j];
    switch (m->jnt_type[j]) {
      case mjJNT_FREE:
        for (int k = 0; k < 3; ++k) q[k] += u(*rng);
        q += 3;
        [[fallthrough]];
      case mjJNT_BALL: {
        const Eigen::Quaterniond turn(Eigen::AngleAxisd(u(*rng), Vector3d(u(*rng), u(*rng), 1).normalized()));
        const Eigen::Quaterniond q1 = Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * turn;
        q[0] = q1.w(), q[1] = q1.x(), q[2] = q1.y(), q[3] = q1.z();
        break;
      }
      default: q[0] += u(*rng);
    }
  }
  mju_zero(d->qvel, m->nv);
  kinematics(m, d);
}

// Our bodies put at MuJoCo's current pose (centre of mass xipos, principal frame ximat).
void set_poses(const mjData* d, Mechanism* mech) {
  for (size_t b = 0; b < mech->bodies.size(); ++b) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> r(d->ximat + 9 * b);
    mech->bodies[b].position = Vector3d(d->xipos + 3 * b);
    mech->bodies[b].orientation = Eigen::Quaterniond(Eigen::Matrix3d(r)).normalized();
  }
}

// MuJoCo's configuration in d reached from `from` in small steps, our bodies following and every
// constraint evaluated on the way, as a simulation moves them: a joint set's fit starts where the
// last one ended (joint_set.h), and a set with several solutions keeps the one it is on.
void walk_to(const mjModel* m, mjData* d, const std::vector<mjtNum>& from, Mechanism* mech) {
  const std::vector<mjtNum> target(d->qpos, d->qpos + m->nq);
  std::vector<mjtNum> qvel(m->nv);  // from -> target in unit time
  mj_differentiatePos(m, qvel.data(), 1.0, from.data(), target.data());
  constexpr int kSteps = 8;
  for (int s = 1; s <= kSteps; ++s) {
    mju_copy(d->qpos, from.data(), m->nq);
    mj_integratePos(m, d->qpos, qvel.data(), static_cast<double>(s) / kSteps);
    if (s == kSteps) mju_copy(d->qpos, target.data(), m->nq);
    kinematics(m, d);
    set_poses(d, mech);
    for (const Constraint& c : mech->constraints) evaluate(c, mech->bodies[c.body_a], mech->bodies[c.body_b]);
  }
}

// Body velocities (v at the centre of mass, w; world) of MuJoCo's unit motion qvel = e_k, for
// every dof k: jac[b] is 6 x nv (mj_jacBodyCom).
std::vector<Eigen::MatrixXd> body_jacobians(const mjModel* m, const mjData* d) {
  std::vector<Eigen::MatrixXd> jac(m->nbody, Eigen::MatrixXd::Zero(6, m->nv));  // (size nbody)
  std::vector<mjtNum> jacp(3 * m->nv), jacr(3 * m->nv);                            // row-major 3 x nv
  for (int b = 1; b < m->nbody; ++b) {
    mj_jacBodyCom(m, d, jacp.data(), jacr.data(), b);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < m->nv; ++k) {
        jac[b](r, k) = jacp[r * m->nv + k];
        jac[b](3 + r, k) = jacr[r * m->nv + k];
      }
  }
  return jac;
}

// J V for all dofs: rows x nv.
Eigen::MatrixXd rows_times_motions(const ConstraintRows& rows, const Constraint& c,
                                   const std::vector<Eigen::MatrixXd>& jac) {
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 12, Eigen::RowMajor>> j(rows.jacobian.data(), rows.rows, 12);
  return j.leftCols(6) * jac[c.body_a] + j.rightCols(6) * jac[c.body_b];
}

// Rounding in MuJoCo's kinematics and ours at positions of O(10 m) and lever arms of O(1 m):
// a wrong anchor, axis or frame gives errors of the size of the configuration change (0.1-1).
constexpr double kRounding = 1e-10;

// Our shapes against MuJoCo's geoms at the pose of d (mj_kinematics at qpos0, the pose of
// load_mjcf's bodies): for every geom of a type shape.h has, in MuJoCo's order on its body, the
// type, the sizes, the sliding friction and the filter bits as mjModel has them, and the world
// pose: to_world(position) = geom_xpos, the body's orientation times the shape's = geom_xmat, a
// plane's normal = geom_xmat's z (on a static body). MuJoCo's kinematics compose the poses
// through the body frames (xpos, xquat); the converter through the inertial frame (ipos, iquat).
struct ShapeCounts {
  std::array<int, 8> of_type{};  // by ShapeType
  int dropped = 0;               // geoms of the other types
};

// Geoms of the kinematics at O(10 m) (the 22 humanoids): rounding is ~1e-14.
constexpr double kGeomPose = 1e-9;

// Mesh geoms without a compiled hull (contype = conaffinity = 0: MuJoCo makes none), which touch
// nothing and become no shape.
int collisionless_meshes(const mjModel* m) {
  int n = 0;
  for (int g = 0; g < m->ngeom; ++g) n += m->geom_type[g] == mjGEOM_MESH && m->mesh_graphadr[m->geom_dataid[g]] < 0;
  return n;
}

ShapeCounts expect_shapes_match(const mjModel* m, const mjData* d, const Mechanism& mech) {
  ShapeCounts counts;
  for (int b = 0; b < m->nbody; ++b) {
    const RigidBody& body = mech.bodies[b];
    size_t k = 0;  // the next shape of the body
    for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
      SCOPED_TRACE("geom " + std::to_string(g) + " on body " + body.name);
      ShapeType type;
      switch (m->geom_type[g]) {
        case mjGEOM_PLANE: type = ShapeType::plane; break;
        case mjGEOM_SPHERE: type = ShapeType::sphere; break;
        case mjGEOM_CAPSULE: type = ShapeType::capsule; break;
        case mjGEOM_BOX: type = ShapeType::box; break;
        case mjGEOM_CYLINDER: type = ShapeType::cylinder; break;
        case mjGEOM_ELLIPSOID: type = ShapeType::ellipsoid; break;
        case mjGEOM_MESH: type = ShapeType::convex; break;
        case mjGEOM_HFIELD: type = ShapeType::heightfield; break;
        default: ++counts.dropped; continue;
      }
      if (type == ShapeType::convex && m->mesh_graphadr[m->geom_dataid[g]] < 0) continue;  // touches nothing: no shape
      if (k == body.shapes.size()) {
        ADD_FAILURE() << "no shape for the geom";
        break;
      }
      const Shape& s = body.shapes[k++];
      ++counts.of_type[static_cast<int>(type)];
      EXPECT_EQ(s.type, type);
      const mjtNum* size = m->geom_size + 3 * g;
      switch (type) {
        case ShapeType::plane: break;  // its size only draws it
        case ShapeType::capsule:
        case ShapeType::cylinder: EXPECT_EQ(s.half_length, size[1]); [[fallthrough]];
        case ShapeType::sphere: EXPECT_EQ(s.radius, size[0]); break;
        case ShapeType::box:
        case ShapeType::ellipsoid: EXPECT_EQ(s.half_extents, Vector3d(size)); break;
        case ShapeType::convex:
        case ShapeType::heightfield: break;  // their data: the tests at the end of the file
      }
      EXPECT_EQ(s.friction, m->geom_friction[3 * g]);
      // (0 where a <flag> disables contacts: the shape is kept but touches nothing)
      const bool touching = (m->opt.disableflags & (mjDSBL_CONTACT | mjDSBL_CONSTRAINT)) == 0;
      EXPECT_EQ(s.contype, touching ? static_cast<uint32_t>(m->geom_contype[g]) : 0u);
      EXPECT_EQ(s.conaffinity, touching ? static_cast<uint32_t>(m->geom_conaffinity[g]) : 0u);
      EXPECT_LE((body.to_world(s.position) - Vector3d(d->geom_xpos + 3 * g)).norm(), kGeomPose);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> xmat(d->geom_xmat + 9 * g);
      if (type == ShapeType::plane) {
        EXPECT_TRUE(body.is_static);
        EXPECT_LE((body.orientation * s.normal - xmat.col(2)).norm(), kGeomPose);
      } else {
        EXPECT_LE(((body.orientation * s.orientation).toRotationMatrix() - xmat).norm(), kGeomPose);
      }
    }
    EXPECT_EQ(k, body.shapes.size()) << "shapes without a geom on body " << body.name;
  }
  return counts;
}

// A ball's cone limit (max side, negated: c = max - angle): the angle is that of MuJoCo's
// quaternion for the ball, and J V moves only the ball's three dofs, by -(the axis of that
// rotation) (d angle/dt = axis . w for the ball's local w).
void expect_ball_cone(const mjModel* m, const mjData* d, const Constraint& c, const Mechanism& mech,
                      const Eigen::MatrixXd& jv) {
  const int body = c.body_b;
  int joint = m->body_jntadr[body];
  for (int k = 0; k < c.joint; ++k) ++joint;
  ASSERT_EQ(m->jnt_type[joint], mjJNT_BALL);
  const mjtNum* q = d->qpos + m->jnt_qposadr[joint];
  const Eigen::Quaterniond turn(q[0], q[1], q[2], q[3]);
  const Eigen::AngleAxisd angle_axis(turn.normalized());
  const double angle = angle_axis.angle();
  EXPECT_NEAR(limit_value(c, mech.bodies[c.body_a], mech.bodies[body]), angle, kRounding) << "the cone's angle";
  const int dof = m->jnt_dofadr[joint];
  for (int k = 0; k < m->nv; ++k) {
    const double expected = k >= dof && k < dof + 3 ? -angle_axis.axis()[k - dof] : 0.0;
    EXPECT_NEAR(jv(0, k), expected, kRounding) << "dof " << k;
  }
}

// Its row measures one of MuJoCo's dofs at unit rate (J V_k = 1 on that dof, 0 on the rest).
void expect_dof_rate(const mjModel* m, const mjData* d, const Constraint& c, const Eigen::MatrixXd& jv) {
  (void)d;
  Eigen::Index k = 0;
  jv.row(0).cwiseAbs().maxCoeff(&k);
  EXPECT_NEAR(jv(0, k), 1.0, kRounding) << to_string(c.type) << " on MuJoCo's dof " << k;
  EXPECT_LE(jv.row(0).cwiseAbs().sum() - std::abs(jv(0, k)), kRounding) << "one dof only";
  EXPECT_LT(k, m->nv);
}

// The joints' rows against MuJoCo's kinematics of model m (d: at qpos0 on entry): they remove
// exactly 6 n - nv degrees of freedom, hold at qpos0, and at random configurations of MuJoCo's
// coordinates still hold and annihilate every dof's motion; each limit measures its coordinate.
void expect_joints_match(const mjModel* m, mjData* d, Mechanism* mechanism, std::mt19937* rng_state) {
  Mechanism& mech = *mechanism;
  std::mt19937& rng = *rng_state;
  // Degrees of freedom: the joints' equality rows remove exactly 6 n - nv of the 6 n.
  const int equalities = converted_equalities(m);
  const size_t joint_constraints = mech.constraints.size() - equalities;
  int joint_rows = 0;
  for (size_t c = 0; c < joint_constraints; ++c)
    if (is_equality(mech.constraints[c].type) && !acts_on_a_dof(mech.constraints[c].type)) joint_rows += num_rows(mech.constraints[c]);
  EXPECT_EQ(6 * mech.num_dynamic_bodies() - joint_rows, m->nv) << "degrees of freedom";

  // At qpos0 every row holds, equalities included.
  for (const Constraint& c : mech.constraints) {
    const ConstraintRows rows = evaluate(c, mech.bodies[c.body_a], mech.bodies[c.body_b]);
    if (is_equality(c.type)) {
      for (int r = 0; r < rows.rows; ++r) EXPECT_LE(std::abs(rows.c[r]), kRounding) << to_string(c.type);
    } else if (c.type == ConstraintType::angular_limit || c.type == ConstraintType::positional_limit ||
               c.type == ConstraintType::coordinate_limit) {
      EXPECT_LE(std::abs(limit_value(c, mech.bodies[c.body_a], mech.bodies[c.body_b])), kRounding);
    }
  }

  // At random configurations of MuJoCo's coordinates: the joints' rows still hold and their
  // Jacobian annihilates every dof's motion; each limit moves with exactly one coordinate, at
  // unit rate, and measures it (q - qpos0).
  // The dense check costs O(nbody nv) memory and O(rows nv) time per trial: the many-humanoid
  // models (nv in the hundreds and thousands) are copies of humanoid.xml's joints, checked there.
  if (m->nv > 100) {
    std::printf("nv = %d, random configurations checked on the smaller models only\n", m->nv);
    return;
  }
  std::vector<mjtNum> previous(m->qpos0, m->qpos0 + m->nq);
  for (int trial = 0; trial < 3; ++trial) {
    random_configuration(m, d, &rng);
    walk_to(m, d, previous, &mech);
    previous.assign(d->qpos, d->qpos + m->nq);
    const std::vector<Eigen::MatrixXd> jac = body_jacobians(m, d);
    double worst_c = 0, worst_jv = 0;
    for (size_t ci = 0; ci < joint_constraints; ++ci) {
      const Constraint& c = mech.constraints[ci];
      const ConstraintRows rows = evaluate(c, mech.bodies[c.body_a], mech.bodies[c.body_b]);
      const Eigen::MatrixXd jv = rows_times_motions(rows, c, jac);
      if (acts_on_a_dof(c.type)) {
        expect_dof_rate(m, d, c, jv);
        continue;
      }
      if (is_equality(c.type)) {
        for (int r = 0; r < rows.rows; ++r) worst_c = std::max(worst_c, std::abs(rows.c[r]));
        worst_jv = std::max(worst_jv, jv.cwiseAbs().maxCoeff());
        continue;
      }
      if (c.type == ConstraintType::coordinate_limit && c.chain->joints[c.joint].type == ChainJointType::ball) {
        expect_ball_cone(m, d, c, mech, jv);
        continue;
      }
      // A limit: one coordinate k with |J V_k| = 1, all others 0.
      Eigen::Index k = 0;
      jv.row(0).cwiseAbs().maxCoeff(&k);
      EXPECT_NEAR(std::abs(jv(0, k)), 1.0, kRounding) << to_string(c.type) << " " << ci;
      EXPECT_LE(jv.row(0).cwiseAbs().sum() - std::abs(jv(0, k)), kRounding) << "one coordinate only";
      int joint = 0;
      while (joint + 1 < m->njnt && m->jnt_dofadr[joint + 1] <= k) ++joint;
      const double q = d->qpos[m->jnt_qposadr[joint]] - m->qpos0[m->jnt_qposadr[joint]];
      // The row is the nearer side of the limit: the max side is negated (constraint.h).
      const double value = limit_value(c, mech.bodies[c.body_a], mech.bodies[c.body_b]);
      const bool max_side = value - c.min > c.max - value;
      EXPECT_NEAR(value, (jv(0, k) > 0) != max_side ? q : -q, kRounding) << "limit " << ci << " on joint " << joint;
    }
    EXPECT_LE(worst_c, kRounding) << "joint rows at a MuJoCo configuration";
    EXPECT_LE(worst_jv, kRounding) << "J V of MuJoCo's motions";
  }
}

TEST(Mjcf, ShippedAndGymnasiumModelsMatchMuJoCo) {
  std::mt19937 rng(6);
  int loaded = 0;
  std::vector<std::string> paths = shipped_models();
  const std::vector<std::string> gymnasium = gymnasium_models();
  EXPECT_GE(gymnasium.size(), 14u) << kGymnasium;
  paths.insert(paths.end(), gymnasium.begin(), gymnasium.end());
  for (const std::string& path : paths) {
    MjcfDropped dropped;
    Mechanism mech;
    try {
      mech = load_mjcf(path, &dropped);
    } catch (const InputError& e) {
      const std::string error = e.what();
      std::printf("skipped %s: %s\n", path.c_str(), error.c_str());
      EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << "the message names the file: " << error;
      EXPECT_EQ(path.rfind(kGymnasium, 0), std::string::npos) << "every Gymnasium model loads: " << error;
      continue;
    }
    ++loaded;
    SCOPED_TRACE(path);
    const ModelPtr model = mujoco_model(path);
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    const DataPtr data(mj_makeData(m));
    mjData* d = data.get();
    kinematics(m, d);

    // Counts, masses, gravity, timestep.
    ASSERT_EQ(static_cast<int>(mech.bodies.size()), m->nbody);
    const ShapeCounts shapes = expect_shapes_match(m, d, mech);
    EXPECT_EQ(dropped.geoms, shapes.dropped);
    int shape_count = 0;
    for (int n : shapes.of_type) shape_count += n;
    EXPECT_EQ(shape_count + shapes.dropped, m->ngeom - collisionless_meshes(m));
    double mass = 0;
    Vector3d moment = Vector3d::Zero();
    for (const RigidBody& b : mech.bodies) {
      mass += b.mass;
      moment += b.mass * b.position;
    }
    EXPECT_NEAR(mass, mj_getTotalmass(m), 1e-12 * mass);
    EXPECT_LE((moment / mass - Vector3d(d->subtree_com)).norm(), kRounding) << "whole-model centre of mass";
    for (int b = 0; b < m->nbody; ++b)
      EXPECT_LE((mech.bodies[b].position - Vector3d(d->xipos + 3 * b)).norm(), kRounding) << "body " << b;
    EXPECT_EQ(mech.gravity, Vector3d(m->opt.gravity));
    EXPECT_EQ(mech.timestep, m->opt.timestep);

    expect_joints_match(m, d, &mech, &rng);
  }
  std::printf("%d shipped models loaded\n", loaded);
  EXPECT_GE(loaded, 8 + 14) << "humanoids, rope, loop, slider crank, arm, mug, scene; Gymnasium's 14";
}

// A body with a random set of joints (joint_set.h) on a parent that turns, as MJCF: slides and
// at most three rotational dofs (hinges, or a ball followed by slides only, as MuJoCo requires),
// so that the set's dofs are independent and MuJoCo's nv is what the rows leave; random axes,
// anchors and ranges, and an off-centre box so that the inertial frame is not the body's. (More
// rotational dofs than 3 are redundant but for the translations their lever arms bring: legal,
// stepped, but their coordinates are ill-conditioned, so the limits' exact values are not
// compared there.)
std::string random_joint_set_model(std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> kind(0, 2), count(2, 4);
  auto triple = [&](double scale) {
    char text[96];
    std::snprintf(text, sizeof text, "%.6f %.6f %.6f", scale * u(*rng), scale * u(*rng), scale * u(*rng));
    return std::string(text);
  };
  std::string joints;
  int dofs = 0, rotations = 0;
  bool ball = false;
  for (int k = 0, n = count(*rng); k < n; ++k) {
    int type = kind(*rng);
    if (type == 2 && rotations > 0) type = 0;
    if (type == 0 && rotations == 3) type = 1;
    if (ball) type = 1;  // MuJoCo: a ball may be followed by slides only
    rotations += type == 0 ? 1 : type == 2 ? 3 : 0;
    const bool limited = u(*rng) > 0;
    joints += "<joint name=\"j" + std::to_string(k) + "\" pos=\"" + triple(0.3) + "\"";
    if (type == 2) {
      ball = true;
      dofs += 3;
      joints += " type=\"ball\"";
      if (limited) joints += " limited=\"true\" range=\"0 0.7\"";
    } else {
      dofs += 1;
      joints += type == 0 ? " type=\"hinge\"" : " type=\"slide\"";
      joints += " axis=\"" + triple(1) + "\"";
      if (limited) joints += " limited=\"true\" range=\"-0.4 0.6\"";
    }
    joints += "/>";
  }
  return "<mujoco><compiler angle=\"radian\"/><worldbody><body name=\"parent\" pos=\"0 0 1\">"
         "<joint name=\"turn\" axis=\"0.3 1 0.2\"/><geom type=\"capsule\" size=\".05\" fromto=\"0 0 0 .3 0 0\"/>"
         "<body name=\"child\" pos=\"" + triple(0.5) + "\" euler=\"" + triple(1) + "\">" + joints +
         "<geom type=\"box\" size=\".1 .2 .3\" pos=\"" + triple(0.2) + "\" euler=\"" + triple(1) +
         "\"/></body></body></worldbody></mujoco>";
}

TEST(Mjcf, JointSetsMatchMuJoCo) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 60; ++trial) {
    const std::string text = random_joint_set_model(&rng);
    SCOPED_TRACE(text);
    const std::string path = temp_file("joint_set.xml", text);
    Mechanism mech = load_mjcf(path);
    const ModelPtr model = mujoco_model(path);
    ASSERT_TRUE(model);
    const DataPtr data(mj_makeData(model.get()));
    kinematics(model.get(), data.get());
    expect_joints_match(model.get(), data.get(), &mech, &rng);
  }
}

// Body velocities of MuJoCo's motion qvel (v at the centre of mass, w; world).
void set_velocities(const mjModel* m, const mjData* d, Mechanism* mech) {
  const std::vector<Eigen::MatrixXd> jac = body_jacobians(m, d);
  const Eigen::Map<const Eigen::VectorXd> qvel(d->qvel, m->nv);
  for (int b = 1; b < m->nbody; ++b) {
    const Eigen::Matrix<double, 6, 1> v = jac[b] * qvel;
    mech->bodies[b].linear_velocity = v.head<3>();
    mech->bodies[b].angular_velocity = v.tail<3>();
  }
}

struct Fall {
  double separation = 0;  // largest |anchor_a - anchor_b| of the ball-based rows over the run (m)
  ConstraintError error;  // largest over the run
  double com_error = 0;   // largest |com - (p0 + v0 t + g t (t + dt) / 2)| (m)
};

Fall fall(Mechanism mech, double seconds) {
  double mass = 0;
  Vector3d p0 = Vector3d::Zero(), v0 = Vector3d::Zero();
  for (const RigidBody& b : mech.bodies)
    if (!b.is_static) {
      mass += b.mass;
      p0 += b.mass * b.position;
      v0 += b.mass * b.linear_velocity;
    }
  p0 /= mass;
  v0 /= mass;
  const Vector3d g = mech.gravity;
  const double dt = mech.timestep;
  StepOptions options;
  options.solver.kind = SolverKind::ldl_pgs;  // the humanoid's joint ranges are inequalities
  options.diagnostics = true;
  Simulation sim(std::move(mech), options);
  Fall out;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int s = 1; s <= steps; ++s) {
    const StepReport r = sim.step();
    EXPECT_TRUE(r.result.ok()) << "step " << s;
    const Mechanism& now = sim.mechanism();
    for (const Constraint& c : now.constraints) {
      if (c.type != ConstraintType::ball && c.type != ConstraintType::hinge && c.type != ConstraintType::weld) continue;
      const Vector3d a = now.bodies[c.body_a].to_world(c.anchor_a), b = now.bodies[c.body_b].to_world(c.anchor_b);
      out.separation = std::max(out.separation, (a - b).norm());
    }
    out.error.position_max = std::max(out.error.position_max, r.error.position_max);
    out.error.angular_max = std::max(out.error.angular_max, r.error.angular_max);
    // Semi-implicit Euler: v_n = v0 + n g dt (the constraint impulses J^T lambda have no net
    // linear part), x_n = x0 + dt sum_{k=1..n} v_k = x0 + v0 t + g t (t + dt) / 2 with t = n dt:
    // the continuous p0 + v0 t + g t^2 / 2 plus g t dt / 2, the timestep's first-order error.
    const double t = s * dt;
    Vector3d com = Vector3d::Zero();
    for (const RigidBody& b : now.bodies)
      if (!b.is_static) com += b.mass * b.position;
    com /= mass;
    out.com_error = std::max(out.com_error, (com - (p0 + v0 * t + g * (t * (t + dt) / 2))).norm());
  }
  return out;
}

// The free fall of 2 s moves the centre of mass 20 m; 400 steps of rounding at that size are
// ~1e-12 m. The discrete formula is exact up to that; against the continuous one the gap is
// g t dt / 2 = 0.049 m at t = 2 s, dt = 5 ms.
constexpr double kComRounding = 1e-10;

// The humanoid without its shapes: a free fall, away from its floor.
Mechanism without_shapes(Mechanism m) {
  for (RigidBody& b : m.bodies) b.shapes.clear();
  return m;
}

TEST(Mjcf, HumanoidFallingAtRestStaysTogether) {
  const Fall f = fall(without_shapes(load_mjcf(kModels + "/humanoid/humanoid.xml")), 2.0);
  std::printf("humanoid at rest, 2 s: separation %.3g m, rows %.3g m / %.3g rad, centre of mass %.3g m\n",
              f.separation, f.error.position_max, f.error.angular_max, f.com_error);
  EXPECT_LT(f.separation, 1e-6);
  EXPECT_LT(f.error.position_max, 1e-6);
  EXPECT_LT(f.com_error, kComRounding);
}

// The same fall with every joint moving (a random qvel of MuJoCo's, so the velocities respect the
// joints): the centre of mass still follows the formula; the separation is reported (velocity
// steps drift by ~|w|^2 r dt^2 per step, which Baumgarte corrects).
TEST(Mjcf, HumanoidFallingWhileMovingFollowsFreeFall) {
  const std::string path = kModels + "/humanoid/humanoid.xml";
  Mechanism mech = without_shapes(load_mjcf(path));
  const ModelPtr model = mujoco_model(path);
  ASSERT_TRUE(model);
  const DataPtr data(mj_makeData(model.get()));
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);  // rad/s, m/s
  for (int k = 0; k < model->nv; ++k) data->qvel[k] = u(rng);
  kinematics(model.get(), data.get());
  set_velocities(model.get(), data.get(), &mech);
  const Fall f = fall(std::move(mech), 2.0);
  std::printf("humanoid moving (qvel in [-1, 1]), 2 s: separation %.3g m, rows %.3g m / %.3g rad, centre of mass %.3g m\n",
              f.separation, f.error.position_max, f.error.angular_max, f.com_error);
  EXPECT_LT(f.com_error, kComRounding);
}

TEST(Mjcf, DroppedIsCountedAndDescribed) {
  // MuJoCo's humanoid and every Gymnasium model: nothing that changes the dynamics is dropped
  std::vector<std::string> paths = gymnasium_models();
  paths.push_back(kModels + "/humanoid/humanoid.xml");
  for (const std::string& path : paths) {
    MjcfDropped dropped;
    load_mjcf(path, &dropped);
    EXPECT_TRUE(dropped.unmodelled.empty()) << path << ": " << dropped.unmodelled.front();
    EXPECT_EQ(dropped.geoms + dropped.contact_pairs + dropped.tendons + dropped.actuators + dropped.joint_dynamics +
                  dropped.ranges + dropped.fluid,
              0)
        << path << ": " << describe(dropped);
  }
  const Mechanism swimmer = load_mjcf(kGymnasium + "/swimmer.xml");
  EXPECT_TRUE(swimmer.fluid.active()) << "its option viscosity and density";

  // Each kind of unmodelled element refused by default, naming it; with allow_dropped, counted
  // and described on one line.
  struct Case {
    const char* xml;  // inside <mujoco>
    const char* named;
  };
  const std::string bodies =
      "<worldbody><body name=\"a\"><joint type=\"free\" name=\"root\"/><geom type=\"cylinder\" size=\".1 .2\"/>"
      "<geom type=\"ellipsoid\" size=\".1 .2 .3\"/><body name=\"c\" pos=\"0 0 .5\"><joint name=\"elbow\" "
      "axis=\"0 1 0\"/><geom type=\"sphere\" size=\".1\"/></body></body>"
      "<body name=\"b\" pos=\"1 0 0\"><freejoint/><geom type=\"box\" size=\".1 .1 .1\"/></body></worldbody>";
  const Case cases[] = {
      {"<contact><exclude body1=\"a\" body2=\"b\"/></contact>", "contact exclude 0"},
      {"<tendon><fixed name=\"t\" limited=\"true\" range=\"-1 1\"><joint joint=\"elbow\" coef=\"1\"/></fixed>"
       "</tendon>",
       "tendon \"t\""},
      {"<actuator><general name=\"slow\" joint=\"elbow\" dyntype=\"filter\" dynprm=\"1\"/></actuator>",
       "actuator \"slow\""},
      {"<default><joint damping=\"1\"/></default>", "joint \"root\""},
  };
  for (const Case& c : cases) {
    const std::string path = temp_file("dropped.xml", std::string("<mujoco>") + c.xml + bodies + "</mujoco>");
    try {
      load_mjcf(path);
      ADD_FAILURE() << c.xml << ": not refused";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(c.named), std::string::npos) << what;
      EXPECT_NE(what.find("--allow-dropped"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
    }
    MjcfDropped dropped;
    const Mechanism m = load_mjcf(path, &dropped, /*allow_dropped=*/true);
    ASSERT_EQ(dropped.unmodelled.size(), 1u) << c.xml;
    EXPECT_EQ(dropped.geoms, 0) << "cylinders and ellipsoids are shapes";
    EXPECT_EQ(m.bodies[1].shapes.size(), 2u);
    const std::string line = describe(dropped);
    EXPECT_EQ(line.rfind("dropped: 1 ", 0), 0u) << line;
    EXPECT_EQ(line.find('\n'), std::string::npos) << "one line";
  }
}

// The humanoid's geoms: the floor a plane on the static world, 16 capsules and 3 spheres on the
// 16 moving bodies, each as MuJoCo compiled it (expect_shapes_match).
TEST(Mjcf, HumanoidShapesMatchMuJoCo) {
  const std::string path = kModels + "/humanoid/humanoid.xml";
  const Mechanism mech = load_mjcf(path);
  const ModelPtr model = mujoco_model(path);
  ASSERT_TRUE(model);
  const DataPtr data(mj_makeData(model.get()));
  kinematics(model.get(), data.get());
  const ShapeCounts counts = expect_shapes_match(model.get(), data.get(), mech);
  EXPECT_EQ(counts.of_type[static_cast<int>(ShapeType::plane)], 1);
  EXPECT_EQ(counts.of_type[static_cast<int>(ShapeType::capsule)], 16);
  EXPECT_EQ(counts.of_type[static_cast<int>(ShapeType::sphere)], 3);
  EXPECT_EQ(counts.of_type[static_cast<int>(ShapeType::box)], 0);
  EXPECT_EQ(counts.dropped, 0);
  ASSERT_EQ(mech.bodies[0].shapes.size(), 1u);
  EXPECT_TRUE(mech.bodies[0].is_static);
  EXPECT_EQ(mech.bodies[0].shapes[0].type, ShapeType::plane) << "the floor";
  EXPECT_EQ(mech.bodies[0].shapes[0].normal, Vector3d(0, 0, 1));
  // the torso is free: every joint joins two moving bodies, a parent and its child, which
  // MuJoCo's filterparent keeps apart
  for (const Constraint& c : mech.constraints) EXPECT_FALSE(c.collide);
}

// Every Gymnasium model steps 10 s of its own timestep with the ldl-pgs solver, passive and under
// a seeded random control (each actuator's uniform in its ctrlrange, [-1, 1] if unlimited, drawn
// anew every step): every step sound (run_failure), its joints and ranges held within 1e-6 (m,
// rad) at the end of every step, and its contacts within the slop plus 1 mm. A model that starts
// outside a range (the ant's ankles, 30 degrees out at qpos0) is held from the step its ranges
// are first met, within 10 steps; under random controls with 100 projection iterations (30 by
// default). The limits' LCP is solved by the schur schedule: the default
// talk schedule leaves inverted_pendulum's pole 1e-4 m off where it strikes its range
// (papers/physics.md, "MJCF models: Gymnasium's").
void step_ten_seconds(const std::string& path, bool random_controls) {
  SCOPED_TRACE(path);
  Mechanism m = load_mjcf(path);
  StepOptions options;
  options.solver.kind = SolverKind::ldl_pgs;
  options.solver.schedule = HybridSchedule::schur;
  options.diagnostics = true;
  // Under random controls the walkers thrash on their floor: with the default 30 projection
  // iterations one step of walker2d's ends 1.3e-6 m off (papers/physics.md, "MJCF models").
  if (random_controls) options.post_stabilize = 100;
  const double size = mechanism_size(m);
  const int steps = static_cast<int>(std::lround(10.0 / m.timestep));
  const ConstraintError initial = constraint_error(m);
  bool held = initial.position_max <= 1e-6 && initial.angular_max <= 1e-6;
  int settled_at = 0;
  const std::vector<Actuator> actuators = m.actuators;
  Simulation sim(std::move(m), options);
  std::mt19937 rng(51);
  std::vector<double> u(actuators.size(), 0.0);
  ConstraintError worst;
  double penetration = 0;
  for (int s = 1; s <= steps; ++s) {
    for (size_t i = 0; i < u.size() && random_controls; ++i) {
      const Actuator& a = actuators[i];
      u[i] = std::uniform_real_distribution<double>(a.ctrl_limited ? a.ctrl_min : -1, a.ctrl_limited ? a.ctrl_max : 1)(rng);
    }
    sim.set_controls(u);
    const StepReport r = sim.step();
    const std::string failure = run_failure(r, size);
    ASSERT_TRUE(failure.empty()) << "step " << s << ": " << failure;
    penetration = std::max(penetration, r.penetration_max_m);
    if (!held) {
      held = r.error.position_max <= 1e-6 && r.error.angular_max <= 1e-6;
      settled_at = s;
      continue;
    }
    worst.position_max = std::max(worst.position_max, r.error.position_max);
    worst.angular_max = std::max(worst.angular_max, r.error.angular_max);
  }
  std::printf("%s, %s: %d steps, ranges met at step %d, then joints %.3g m / %.3g rad; penetration %.3g m\n",
              std::filesystem::path(path).filename().c_str(), random_controls ? "random controls" : "passive", steps,
              settled_at, worst.position_max, worst.angular_max, penetration);
  EXPECT_LE(settled_at, 10);
  EXPECT_LE(worst.position_max, 1e-6);
  EXPECT_LE(worst.angular_max, 1e-6);
  EXPECT_LE(penetration, options.contacts.slop + 1e-3);
}

TEST(Mjcf, GymnasiumModelsStepTenSeconds) {
  for (const std::string& path : gymnasium_models()) step_ten_seconds(path, /*random_controls=*/false);
}

TEST(Mjcf, GymnasiumModelsStepTenSecondsUnderRandomControls) {
  for (const std::string& path : gymnasium_models()) step_ten_seconds(path, /*random_controls=*/true);
}

// The Gymnasium models without contacts, and the planar walkers with contacts off (in free fall:
// their roots are joint sets), against MuJoCo itself: every dof started at 0.5 (rad or m)/s, the
// bodies' centres after 1 s of our steps at the model's timestep against MuJoCo's RK4 at 1e-4 s,
// beside MuJoCo's own semi-implicit Euler at the model's timestep (ours is one too). With every
// joint's armature, damping, spring and friction loss and the actuators, passive (controls 0)
// and under a fixed sinusoidal control inside each ctrlrange. Ours must be within twice MuJoCo's
// Euler error, or 1e-3 m: this checks the inertia frames, the joints' rows, the limits, armature,
// damping, springs and gear.
struct Fidelity {
  double ours = 0, euler = 0;  // largest |x_b - x_b(RK4)| over the bodies at 1 s (m)
};

ModelPtr reference_model(const std::string& path, int integrator, double timestep) {
  ModelPtr m = mujoco_model(path);
  m->opt.disableflags |= mjDSBL_CONTACT;
  m->opt.integrator = integrator;
  m->opt.timestep = timestep;
  return m;
}

// Actuator i's control at time t: a sine of its own frequency, a tenth of its ctrlrange wide
// about its middle (0.1 about 0 where unlimited): mild enough that the pendulums and the reacher
// stay off their ranges for the second, where MuJoCo's soft limits and our hard ones part.
double sine_control(const mjModel* m, int i, double t) {
  const double wave = std::sin(2 * M_PI * (1 + 0.37 * i) * t + i);
  if (!m->actuator_ctrllimited[i]) return 0.1 * wave;
  const double lo = m->actuator_ctrlrange[2 * i], hi = m->actuator_ctrlrange[2 * i + 1];
  return 0.5 * (lo + hi) + 0.05 * (hi - lo) * wave;
}

// MuJoCo's centres of mass (xipos) after `seconds` from qpos0 at qvel = 0.5.
std::vector<Vector3d> mujoco_run(const mjModel* m, double seconds, bool controlled) {
  const DataPtr data(mj_makeData(m));
  mjData* d = data.get();
  for (int k = 0; k < m->nv; ++k) d->qvel[k] = 0.5;
  const int steps = static_cast<int>(std::lround(seconds / m->opt.timestep));
  for (int s = 0; s < steps; ++s) {
    for (int i = 0; i < m->nu; ++i) d->ctrl[i] = controlled ? sine_control(m, i, s * m->opt.timestep) : 0;
    mj_step(m, d);
  }
  std::vector<Vector3d> x;
  for (int b = 0; b < m->nbody; ++b) x.emplace_back(d->xipos + 3 * b);
  return x;
}

Fidelity fidelity(const std::string& path, bool controlled) {
  constexpr double kSeconds = 1;
  Mechanism mech = load_mjcf(path);
  for (RigidBody& b : mech.bodies) b.shapes.clear();  // contacts off, as in MuJoCo's runs
  const ModelPtr reference = reference_model(path, mjINT_RK4, 1e-4);
  const ModelPtr euler = reference_model(path, mjINT_EULER, mech.timestep);
  {
    const DataPtr data(mj_makeData(euler.get()));
    for (int k = 0; k < euler->nv; ++k) data->qvel[k] = 0.5;
    kinematics(euler.get(), data.get());
    set_velocities(euler.get(), data.get(), &mech);
  }
  const double dt = mech.timestep;
  const int steps = static_cast<int>(std::lround(kSeconds / dt));
  Simulation sim(std::move(mech), StepOptions{});
  std::vector<double> u(euler->nu, 0.0);
  for (int s = 0; s < steps; ++s) {
    for (int i = 0; i < euler->nu; ++i) u[i] = controlled ? sine_control(euler.get(), i, s * dt) : 0;
    sim.set_controls(u);
    sim.step();
  }
  const std::vector<Vector3d> exact = mujoco_run(reference.get(), kSeconds, controlled);
  const std::vector<Vector3d> theirs = mujoco_run(euler.get(), kSeconds, controlled);
  Fidelity f;
  for (size_t b = 0; b < exact.size(); ++b) {
    f.ours = std::max(f.ours, (sim.mechanism().bodies[b].position - exact[b]).norm());
    f.euler = std::max(f.euler, (theirs[b] - exact[b]).norm());
  }
  return f;
}

TEST(Mjcf, GymnasiumModelsMoveAsMuJoCoMovesThem) {
  for (const char* name : {"inverted_pendulum", "inverted_double_pendulum", "reacher", "swimmer", "hopper",
                           "walker2d", "walker2d_v5", "half_cheetah"}) {
    for (const bool controlled : {false, true}) {
      const Fidelity f = fidelity(kGymnasium + "/" + name + ".xml", controlled);
      std::printf("%s, %s: 1 s, against MuJoCo's RK4 at 1e-4 s: ours %.3g m, MuJoCo's Euler %.3g m\n", name,
                  controlled ? "sine controls" : "passive", f.ours, f.euler);
      EXPECT_LE(f.ours, std::max(2 * f.euler, 1e-3)) << name << (controlled ? ", sine controls" : ", passive");
    }
  }
}

// Every kind of joint dynamics and actuator the conversion takes, on one arm against MuJoCo's RK4
// as fidelity() measures it: a hinge with a spring (springref), damping and a position servo; a
// slide with armature and a velocity servo; a hinge with a force-limited velocity servo and
// friction loss; a ball with armature, damping and a spring; a motor with a gear and forcerange.
// This arm is hard on a maximal-coordinates Euler step (ours is 2.7 times MuJoCo's own error on it
// with no dynamics at all), so the claim is convergence: at a quarter of the timestep our error
// falls to at most 0.4 of it (first order: 0.25), where a dynamics converted wrong would keep a
// model error (an armature measured without the slide's centrifugal change kept 0.35 m at any
// timestep), and it ends within 1 cm.
TEST(Mjcf, JointDynamicsAndServosMatchMuJoCo) {
  const std::string model = R"(<mujoco><compiler angle="radian"/>
    <option timestep="TIMESTEP"/>
    <worldbody>
      <body name="upper" pos="0 0 1">
        <joint name="shoulder" type="hinge" axis="0 1 0" stiffness="20" springref="0.3" damping="0.5"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
        <body name="sleeve" pos="0.3 0 0">
          <joint name="extend" type="slide" axis="1 0 0" armature="0.2"/>
          <geom type="box" size="0.1 0.03 0.03"/>
          <body name="lower" pos="0.1 0 0">
            <joint name="elbow" type="hinge" axis="0 0 1" frictionloss="0.05" armature="0.01"/>
            <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.03"/>
            <body name="hand" pos="0.25 0 0">
              <joint name="wrist" type="ball" armature="0.005" damping="0.02" stiffness="0.5"/>
              <geom type="box" size="0.05 0.04 0.02" pos="0.05 0 0"/>
            </body>
          </body>
        </body>
      </body>
    </worldbody>
    <actuator>
      <position joint="shoulder" kp="30" ctrlrange="-1 1" ctrllimited="true"/>
      <velocity joint="extend" kv="5"/>
      <velocity joint="elbow" kv="2" forcerange="-0.3 0.3" forcelimited="true"/>
      <motor joint="shoulder" gear="3" forcerange="-2 2" forcelimited="true"/>
    </actuator></mujoco>)";
  const auto at = [&](const char* timestep) {
    std::string text = model;
    text.replace(text.find("TIMESTEP"), 8, timestep);
    return temp_file(std::string("dynamics_") + timestep + ".xml", text);
  };
  MjcfDropped dropped;
  const Mechanism m = load_mjcf(at("0.004"), &dropped);
  EXPECT_TRUE(dropped.unmodelled.empty());
  EXPECT_EQ(m.actuators.size(), 4u);
  EXPECT_EQ(m.dofs.size(), 6u) << "shoulder, extend, elbow, the wrist's three";
  for (const bool controlled : {false, true}) {
    const Fidelity coarse = fidelity(at("0.004"), controlled), fine = fidelity(at("0.001"), controlled);
    std::printf("arm, %s: 1 s, against MuJoCo's RK4 at 1e-4 s: ours %.3g m at 4 ms, %.3g m at 1 ms; MuJoCo's "
                "Euler %.3g m, %.3g m\n",
                controlled ? "sine controls" : "passive", coarse.ours, fine.ours, coarse.euler, fine.euler);
    EXPECT_LE(fine.ours, 0.4 * coarse.ours) << (controlled ? "sine controls" : "passive");
    EXPECT_LE(fine.ours, 1e-2);
  }
}

// MuJoCo's <flag> switches: each one off removes what it names, and nothing else.
TEST(Mjcf, FlagsAreHonoured) {
  // a cart on a rail (slide, limited), a pole (hinge, limited, damped), a ball held to the pole by
  // a connect, a motor, all above a floor
  const std::string body =
      "<worldbody><geom name=\"floor\" type=\"plane\" size=\"5 5 .1\"/>"
      "<body name=\"cart\" pos=\"0 0 .2\"><joint name=\"rail\" type=\"slide\" axis=\"1 0 0\" limited=\"true\" "
      "range=\"-1 1\"/><geom type=\"box\" size=\".2 .1 .1\"/>"
      "<body name=\"pole\"><joint name=\"hinge\" axis=\"0 1 0\" limited=\"true\" range=\"-1 1\" damping=\"1\"/>"
      "<geom type=\"capsule\" fromto=\"0 0 0 0 0 .6\" size=\".05\"/></body></body>"
      "<body name=\"ball\" pos=\"0 0 .9\"><freejoint/><geom size=\".05\"/></body></worldbody>"
      "<equality><connect body1=\"pole\" body2=\"ball\" anchor=\"0 0 .6\"/></equality>"
      "<actuator><motor joint=\"rail\"/></actuator>";
  struct Counts {
    Vector3d gravity;
    int limits = 0, equalities = 0, touching_shapes = 0, damped_dofs = 0;
    bool actuation = true;
    MjcfDropped dropped;
  };
  auto load = [&](const std::string& flag) {
    const std::string path = temp_file("flags.xml", "<mujoco><compiler angle=\"radian\"/><option><flag " + flag +
                                                        "/></option>" + body + "</mujoco>");
    Counts c;
    const Mechanism m = load_mjcf(path, &c.dropped);
    c.gravity = m.gravity;
    c.actuation = m.actuation;
    for (const DofDynamics& d : m.dofs) c.damped_dofs += d.damping > 0 ? 1 : 0;
    for (const Constraint& k : m.constraints) {
      c.limits += k.type == ConstraintType::positional_limit || k.type == ConstraintType::angular_limit ? 1 : 0;
      c.equalities += k.type == ConstraintType::ball ? 1 : 0;
    }
    for (const RigidBody& b : m.bodies)
      for (const Shape& s : b.shapes) c.touching_shapes += s.contype != 0 || s.conaffinity != 0 ? 1 : 0;
    return c;
  };
  const Counts all = load("");
  EXPECT_EQ(all.gravity, Vector3d(0, 0, -9.81));
  EXPECT_EQ(all.limits, 2);
  EXPECT_EQ(all.equalities, 1);
  EXPECT_EQ(all.touching_shapes, 4);
  EXPECT_TRUE(all.dropped.unmodelled.empty());
  EXPECT_TRUE(all.actuation);
  EXPECT_EQ(all.damped_dofs, 1);
  const Counts gravity = load("gravity=\"disable\"");
  EXPECT_EQ(gravity.gravity, Vector3d::Zero());
  EXPECT_EQ(gravity.limits, 2);
  const Counts contact = load("contact=\"disable\"");
  EXPECT_EQ(contact.touching_shapes, 0);
  EXPECT_EQ(contact.limits, 2);
  EXPECT_EQ(contact.equalities, 1);
  const Counts limit = load("limit=\"disable\"");
  EXPECT_EQ(limit.limits, 0);
  EXPECT_EQ(limit.touching_shapes, 4);
  const Counts equality = load("equality=\"disable\"");
  EXPECT_EQ(equality.equalities, 0);
  EXPECT_EQ(equality.limits, 2);
  const Counts constraint = load("constraint=\"disable\"");
  EXPECT_EQ(constraint.limits + constraint.equalities + constraint.touching_shapes, 0);
  EXPECT_FALSE(load("actuation=\"disable\"").actuation);
  EXPECT_EQ(load("passive=\"disable\"").damped_dofs, 0);

  // stepped: with contacts disabled, the ball and the cart pass through the floor
  const std::string path = temp_file("flags.xml", "<mujoco><option><flag contact=\"disable\"/></option>" + body +
                                                      "</mujoco>");
  Simulation sim(load_mjcf(path), StepOptions{});
  for (int s = 0; s < 100; ++s) EXPECT_EQ(sim.step().contacts, 0);
}

// Constraint::collide as MuJoCo's body-pair filter: a body collides with the world it is
// hinged to, not with a moving parent unless filterparent is disabled; bodies welded together
// (no joint) never; an equality between unrelated bodies does not keep them apart.
TEST(Mjcf, CollideFollowsMuJoCosFilter) {
  const std::string bodies =
      "<worldbody><body name=\"a\"><joint axis=\"1 0 0\"/><geom size=\".1\"/>"
      "<body name=\"b\" pos=\"0 0 1\"><joint axis=\"1 0 0\"/><geom size=\".1\"/>"
      "<body name=\"c\" pos=\"0 0 1\"><geom size=\".1\"/></body></body></body>"
      "<body name=\"d\" pos=\"2 0 0\"><freejoint/><geom size=\".1\"/></body></worldbody>"
      "<equality><connect body1=\"a\" body2=\"d\" anchor=\"1 0 0\"/></equality></mujoco>";
  for (const bool filterparent : {true, false}) {
    const Mechanism m = load_mjcf(temp_file("collide.xml", std::string("<mujoco>") +
                                                                (filterparent ? "" : "<option><flag filterparent=\"disable\"/></option>") +
                                                                bodies));
    SCOPED_TRACE(filterparent ? "filterparent" : "filterparent disabled");
    ASSERT_EQ(m.constraints.size(), 4u);
    const auto joins = [&](size_t i, const char* x, const char* y) {
      return m.bodies[m.constraints[i].body_a].name == x && m.bodies[m.constraints[i].body_b].name == y;
    };
    ASSERT_TRUE(joins(0, "world", "a") && joins(1, "a", "b") && joins(2, "b", "c") && joins(3, "a", "d"));
    EXPECT_TRUE(m.constraints[0].collide) << "the world hinge: MuJoCo collides bodies with the world";
    EXPECT_EQ(m.constraints[1].collide, !filterparent) << "parent and child";
    EXPECT_FALSE(m.constraints[2].collide) << "one weld group";
    EXPECT_TRUE(m.constraints[3].collide) << "an equality between unrelated bodies";
  }
}

// Bad input: the message names the file and the construct.
void expect_refused(const std::string& path, std::initializer_list<std::string> fragments) {
  const std::string message = load_error(path);
  ASSERT_FALSE(message.empty()) << path << " loaded";
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  for (const std::string& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
}

const std::string kBody = R"(<geom type="sphere" size=".1"/>)";

TEST(MjcfBadInput, UnparsableFile) {
  expect_refused(temp_file("broken.xml", "<mujoco><worldbody><body></worldbody>"), {"MuJoCo cannot load it"});
}

TEST(MjcfBadInput, MissingFile) { expect_refused("/nonexistent/model.xml", {"MuJoCo cannot load it"}); }

// Read whole, a directory named *.xml threw ios_base::failure: exit 3, "internal error".
TEST(MjcfBadInput, DirectoryNamedXml) {
  const std::string dir = testing::temp_path("model-dir.xml");
  std::filesystem::create_directories(dir);
  expect_refused(dir, {"it is a directory"});
}

// Not XML: refused at its first chunk (a 2 GB file of NUL bytes had been read whole, /dev/zero forever).
TEST(MjcfBadInput, NotXml) {
  expect_refused(temp_file("nul.xml", std::string(100000, '\0')), {"not an MJCF (XML) file"});
  expect_refused(temp_file("text.xml", "  mujoco"), {"does not start with '<'"});
}

// MuJoCo accepts a sphere of 2e9 m and a negative friction; shape_problem does not (MuJoCo
// itself refuses a plane on a moving body).
TEST(MjcfBadInput, GeomOutsideTheShapeRanges) {
  const std::string start = "<mujoco><worldbody><body name=\"arm\"><joint axis=\"1 0 0\"/>";
  expect_refused(temp_file("big.xml", start + "<geom name=\"ball\" size=\"2e9\"/></body></worldbody></mujoco>"),
                 {"geom \"ball\" on body \"arm\": radius 2e+09 is not in (0, 1e9] m"});
  expect_refused(temp_file("friction.xml", start + "<geom name=\"ball\" size=\".1\" friction=\"-1 0 0\"/></body>"
                                                   "</worldbody></mujoco>"),
                 {"geom \"ball\" on body \"arm\": friction -1 is not finite and >= 0"});
  expect_refused(temp_file("plane.xml", start + "<geom name=\"floor\" type=\"plane\" size=\"1 1 1\"/></body>"
                                                "</worldbody></mujoco>"),
                 {"MuJoCo cannot load it", "plane"});
}

TEST(MjcfBadInput, JointEquality) {
  expect_refused(temp_file("coupled.xml", "<mujoco><worldbody><body><joint name=\"a\"/>" + kBody +
                                          "</body><body><joint name=\"b\"/>" + kBody + "</body></worldbody>"
                                          "<equality><joint name=\"gear\" joint1=\"a\" joint2=\"b\"/></equality></mujoco>"),
                 {"equality \"gear\" (joint)"});
}

TEST(MjcfBadInput, WeldAwayFromItsRelpose) {
  expect_refused(temp_file("weld.xml", "<mujoco><worldbody><body name=\"a\"><freejoint/>" + kBody +
                                       "</body><body name=\"b\" pos=\"1 0 0\"><freejoint/>" + kBody + "</body></worldbody>"
                                       "<equality><weld name=\"w\" body1=\"a\" body2=\"b\" relpose=\"2 0 0 1 0 0 0\"/>"
                                       "</equality></mujoco>"),
                 {"equality \"w\" (weld)", "relpose"});
}

// ---- what a file can hand MuJoCo ----

// A hinge axis "nan 0 0" on a model with a muscle (whose length range MuJoCo computes by stepping
// the model) never returned from mj_loadXML; now every non-finite or unparsable number in a
// numeric attribute is refused before MuJoCo reads the file, naming file, line, element,
// attribute and value.
TEST(LdlpgsRobust, MjcfNanAxisIsRefusedNotHung) {
  struct Case {
    std::string element, attribute, value, problem;
  };
  const Case cases[] = {{"joint", "axis", "nan 0 0", "not a finite number"},
                        {"joint", "axis", "1 -inf 0", "not a finite number"},
                        {"joint", "axis", "NaN 0 0", "not a finite number"},
                        {"joint", "pos", "0 0 1e400", "not a finite number"},
                        {"joint", "axis", "1 0 zero", "not a number"},
                        {"body", "pos", "0 +inf 0", "not a finite number"},
                        {"geom", "fromto", "0 0 0 0 0 -nan", "not a finite number"},
                        {"option", "timestep", "inf", "not a finite number"},
                        {"option", "gravity", "0 0 -1e999", "not a finite number"}};
  for (const Case& c : cases) {
    std::string joint = "<joint name=\"a\" axis=\"1 0 0\"/>", body = "<body name=\"arm\">",
                geom = "<geom type=\"capsule\" size=\".05\" fromto=\"0 0 0 0 0 -1\"/>", option;
    const std::string attribute = c.attribute + "=\"" + c.value + "\"";
    if (c.element == "joint") {
      joint = "<joint name=\"a\" ";
      joint += attribute;
      joint += c.attribute == "axis" ? "/>" : " axis=\"1 0 0\"/>";
    }
    if (c.element == "body") body = "<body name=\"arm\" " + attribute + ">";
    if (c.element == "geom") geom = "<geom type=\"capsule\" size=\".05\" " + attribute + "/>";
    if (c.element == "option") option = "<option " + attribute + "/>";
    const std::string path = temp_file("bad_number.xml", "<mujoco>" + option + "\n<worldbody>\n" + body + joint + geom +
                                                             "</body></worldbody>\n<actuator><muscle joint=\"a\"/>"
                                                             "</actuator></mujoco>");
    SCOPED_TRACE(attribute);
    std::string where = path;  // file:line: <element> attribute="value"
    where += c.element == "option" ? ":1: <" : ":3: <";
    where += c.element;
    where += "> ";
    where += attribute;
    const std::string message = load_error(path);
    EXPECT_EQ(message.rfind(where, 0), 0u) << message;
    EXPECT_NE(message.find(c.problem), std::string::npos) << message;
  }
}

// MuJoCo stepped a negative or zero timestep without complaint ("5 steps of -0.01 s", exit 0).
TEST(LdlpgsRobust, MjcfCompiledTimestepMustBePositive) {
  for (const char* timestep : {"-0.01", "0"}) {
    const std::string path = temp_file("timestep.xml", std::string("<mujoco><option timestep=\"") + timestep +
                                                           "\"/><worldbody><body><joint axis=\"1 0 0\"/>" + kBody +
                                                           "</body></worldbody></mujoco>");
    expect_refused(path, {"option timestep", "finite and > 0"});
  }
}

// Two or three hinges whose axes are independent only to rounding: axes 1e-8 apart passed the
// fixed 1e-9 test and gave an H of NaN (1 - k^2 rounded to 0). Now such a model is refused, and
// every model that loads has finite J, W and H, whatever the angle and the anchors' scale.
// Nearly parallel (or coplanar) hinge axes: a joint_set whose rank test treats them as dependent
// or not, but never rows that are not finite.
TEST(LdlpgsRobust, MjcfNearParallelHingesStayFinite) {
  for (double scale : {1.0, 1e3}) {
    for (double d : {1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2}) {
      for (int hinges : {2, 3}) {
        char text[1024];
        const char* third = hinges == 3 ? "<joint name=\"c\" axis=\"0 1 0\"/>" : "";
        // two hinges: axes d apart, anchors apart (the four-rod universal joint); three: n3 = y,
        // n2 tilted d out of the xy plane from x... nearly coplanar with n1 = x and n3.
        if (hinges == 2)
          std::snprintf(text, sizeof text,
                        "<mujoco><worldbody><body name=\"arm\" pos=\"%g 0 0\"><joint name=\"a\" axis=\"1 0 0\"/>"
                        "<joint name=\"b\" axis=\"1 %.17g 0\" pos=\"0 %g 0\"/>%s</body></worldbody></mujoco>",
                        scale, d, 0.1 * scale, kBody.c_str());
        else
          std::snprintf(text, sizeof text,
                        "<mujoco><worldbody><body name=\"arm\" pos=\"%g 0 0\"><joint name=\"a\" axis=\"1 0 0\"/>"
                        "<joint name=\"b\" axis=\"1 1 %.17g\"/>%s%s</body></worldbody></mujoco>",
                        scale, d, third, kBody.c_str());
        SCOPED_TRACE(text);
        const std::string path = temp_file("parallel.xml", text);
        const Mechanism m = load_mjcf(path);
        const System s = build_system(m, StepOptions{});
        std::vector<int> sizes;
        const SymmetricCsc h = equality_matrix(s, &sizes);
        EXPECT_TRUE(std::all_of(h.values.begin(), h.values.end(), [](double x) { return std::isfinite(x); }));
        Simulation sim(m, StepOptions{});
        for (int step = 0; step < 20; ++step) sim.step();
        EXPECT_TRUE(std::isfinite(constraint_error(sim.mechanism()).position_max));
      }
    }
  }
}

// Names, paths and MuJoCo's own messages come from the file: quoted escaped and bounded.
TEST(LdlpgsRobust, MjcfMessagesAreOneBoundedPrintableLine) {
  const std::string long_name(5000, 'x');
  std::string thirteen;  // more dofs on one body than a joint set holds
  for (int j = 0; j < 13; ++j) thirteen += "<joint type=\"slide\" axis=\"1 0 0\"/>";
  const std::string slides = temp_file("slides.xml", "<mujoco><worldbody><body name=\"" + long_name + "&#10;&#7;\">" +
                                                         thirteen + kBody + "</body></worldbody></mujoco>");
  const std::string broken = temp_file("broken.xml", "<mujoco><worldbody><body name=\"" + long_name + "\x01\">" + long_name);
  std::string joints;  // 200 slides of long names: the refusal names the body
  for (int j = 0; j < 200; ++j) joints += "<joint name=\"" + long_name.substr(0, 70) + std::to_string(j) + "\" type=\"slide\"/>";
  const std::string many = temp_file("many.xml", "<mujoco><worldbody><body>" + joints + kBody + "</body></worldbody></mujoco>");
  for (const std::string& path : {slides, broken, many}) {
    const std::string message = load_error(path);
    ASSERT_FALSE(message.empty());
    EXPECT_LT(message.size(), 1000u) << message.size();
    EXPECT_TRUE(std::none_of(message.begin(), message.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
        << message;
  }
}

// ---- geoms of every type: converted, and colliding as MuJoCo's do ----

// Every shipped and Gymnasium model that loads converts every geom: nothing dropped, each
// cylinder, ellipsoid, mesh and hfield a shape of its kind (a mesh no geom can collide with
// excepted: MuJoCo compiles no hull for it and it touches nothing).
TEST(Mjcf, EveryGeomTypeConvertsWithNothingDropped) {
  std::vector<std::string> paths = shipped_models();
  const std::vector<std::string> gymnasium = gymnasium_models();
  paths.insert(paths.end(), gymnasium.begin(), gymnasium.end());
  std::array<int, 8> converted{}, in_models{};  // by ShapeType
  for (const std::string& path : paths) {
    MjcfDropped dropped;
    Mechanism mech;
    try {
      mech = load_mjcf(path, &dropped);
    } catch (const InputError&) {
      continue;  // (refused for its joints or equalities: Mjcf.ShippedAndGymnasiumModelsMatchMuJoCo)
    }
    SCOPED_TRACE(path);
    EXPECT_EQ(dropped.geoms, 0);
    const ModelPtr model = mujoco_model(path);
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    std::array<int, 8> expected{}, ours{};
    for (int g = 0; g < m->ngeom; ++g) {
      const int t = m->geom_type[g];
      if (t == mjGEOM_MESH && m->mesh_graphadr[m->geom_dataid[g]] < 0) continue;
      const ShapeType type = t == mjGEOM_CYLINDER    ? ShapeType::cylinder
                             : t == mjGEOM_ELLIPSOID ? ShapeType::ellipsoid
                             : t == mjGEOM_MESH      ? ShapeType::convex
                             : t == mjGEOM_HFIELD    ? ShapeType::heightfield
                                                     : ShapeType::plane;  // (the old four: not counted here)
      if (type != ShapeType::plane) ++expected[static_cast<int>(type)];
    }
    for (const RigidBody& b : mech.bodies)
      for (const Shape& s : b.shapes)
        if (static_cast<int>(s.type) > static_cast<int>(ShapeType::box)) ++ours[static_cast<int>(s.type)];
    EXPECT_EQ(ours, expected);
    for (int k = 0; k < 8; ++k) {
      converted[k] += ours[k];
      in_models[k] += expected[k];
    }
  }
  std::printf("converted: %d cylinders, %d ellipsoids, %d meshes, %d hfields\n", converted[4], converted[5], converted[6],
              converted[7]);
  EXPECT_GT(converted[static_cast<int>(ShapeType::cylinder)], 0);
  EXPECT_GT(converted[static_cast<int>(ShapeType::ellipsoid)], 0);
}

// The height of body "b"'s free joint at which its geom just touches the world's (MuJoCo's
// contacts, bisected to 1e-10 m between `low`, touching, and `high`, apart).
double touching_height(const std::string& path, double low, double high) {
  const ModelPtr model = mujoco_model(path);
  if (!model) return 0;
  const DataPtr data(mj_makeData(model.get()));
  mjData* d = data.get();
  while (high - low > 1e-10) {
    const double z = 0.5 * (low + high);
    mju_copy(d->qpos, model->qpos0, model->nq);
    d->qpos[2] = z;
    mj_forward(model.get(), d);
    (d->ncon > 0 ? low : high) = z;
  }
  return 0.5 * (low + high);
}

// The deepest contact point: depth and normal (from the world into the body).
struct Deepest {
  double depth = -1;
  Vector3d normal = Vector3d::Zero();
};

Deepest mujoco_deepest(const std::string& path) {
  Deepest r;
  const ModelPtr model = mujoco_model(path);
  if (!model) return r;
  const DataPtr data(mj_makeData(model.get()));
  mj_forward(model.get(), data.get());
  for (int i = 0; i < data->ncon; ++i) {
    const mjContact& c = data->contact[i];
    if (-c.dist <= r.depth) continue;
    r.depth = -c.dist;
    const bool world_first = model->body_weldid[model->geom_bodyid[c.geom1]] == 0;  // frame: geom1 -> geom2
    r.normal = (world_first ? 1.0 : -1.0) * Vector3d(c.frame);
  }
  return r;
}

Deepest our_deepest(const Mechanism& mech) {
  Deepest r;
  CollisionWorld world(mech);
  std::vector<ContactPoint> points;
  world.detect(mech, 0, 0, &points);
  for (const ContactPoint& p : points)
    if (p.depth > r.depth) {
      r.depth = p.depth;
      r.normal = p.normal;  // (body a is the world, body 0)
    }
  return r;
}

// A free body "b" with one geom of each new type, turned and offset in its body, 1 cm into the
// world's floor (a plane, or an hfield read from a file of MuJoCo's own format) at the height
// MuJoCo finds it touching: our deepest contact is MuJoCo's (mj_collision's), depth and normal.
// MuJoCo's cylinder, mesh and ellipsoid against a plane are exact (its support points), its
// hfield prisms are MPR's (tolerance 1e-6); ours are ODE's geometry and libccd's MPR.
TEST(Mjcf, NewGeomTypesCollideAsMuJoCosDo) {
  // a 5 x 6 grid of uneven heights (MuJoCo normalizes them to 0..1 of the elevation 0.3 m)
  const int rows = 5, cols = 6;
  const int32_t dims[2] = {rows, cols};
  std::string grid(reinterpret_cast<const char*>(dims), 8);
  for (int k = 0; k < rows * cols; ++k) {
    const float h = static_cast<float>(0.5 + 0.5 * std::sin(1.7 * k) * std::cos(0.9 * (k % cols)));
    grid.append(reinterpret_cast<const char*>(&h), 4);
  }
  const std::string grid_path = temp_file("grid.bin", grid);
  const std::string plane = "<geom type=\"plane\" size=\"5 5 .1\"/>";
  const std::string field = "<geom type=\"hfield\" hfield=\"h\" pos=\".1 -.2 0\" euler=\"0 0 20\"/>";
  struct Case {
    const char* name;
    std::string floor, body, geom;  // body: its attributes but pos
    double tolerance;
  };
  const std::string mesh = "<mesh name=\"m\" vertex=\"0 0 0  .3 0 .05  0 .25 0  .05 0 .2  .25 .2 .15  .1 .3 .25  .3 .1 .3\"/>";
  const Case cases[] = {
      {"cylinder", plane, "euler=\"20 10 0\"", "<geom type=\"cylinder\" size=\".1 .3\" pos=\".02 0 .01\" euler=\"0 70 0\"/>", 1e-9},
      {"ellipsoid", plane, "euler=\"30 -20 10\"", "<geom type=\"ellipsoid\" size=\".1 .3 .2\" pos=\"0 .03 0\" euler=\"10 0 40\"/>", 1e-9},
      {"mesh", plane, "euler=\"15 25 5\"", "<geom type=\"mesh\" mesh=\"m\" pos=\".05 0 .02\" euler=\"0 30 10\"/>", 1e-9},
      {"sphere on hfield", field, "", "<geom type=\"sphere\" size=\".15\"/>", 1e-5},
      {"mesh on hfield", field, "euler=\"15 25 5\"", "<geom type=\"mesh\" mesh=\"m\" pos=\".05 0 .02\"/>", 1e-5},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto model = [&](const char* z) {
      return "<mujoco><option gravity=\"0 0 0\"/><asset><hfield name=\"h\" file=\"" + grid_path +
             "\" size=\"1.2 1 .3 .1\"/>" + mesh + "</asset><worldbody>" + c.floor + "<body name=\"b\" pos=\".23 .31 " + z +
             "\" " + c.body + "><freejoint/>" + c.geom + "</body></worldbody></mujoco>";
    };
    const double touching = touching_height(temp_file("probe.xml", model("1")), -0.5, 1.5);
    char z[64];
    std::snprintf(z, sizeof z, "%.17g", touching - 0.01);
    const std::string path = temp_file("touching.xml", model(z));
    const Deepest theirs = mujoco_deepest(path), ours = our_deepest(load_mjcf(path));
    std::printf("%s: MuJoCo's deepest %.9f m, ours %.9f m, normals %.2g apart\n", c.name, theirs.depth, ours.depth,
                (theirs.normal - ours.normal).norm());
    EXPECT_GT(theirs.depth, 0.001);
    EXPECT_NEAR(ours.depth, theirs.depth, c.tolerance);
    EXPECT_LE((ours.normal - theirs.normal).norm(), c.tolerance > 1e-9 ? 1e-3 : 1e-9);
  }
}

// An hfield on a moving body (MuJoCo refuses it itself), and a mesh that could collide but has
// no compiled hull (faces given, compiler convexhull="false"), are refused naming the geom.
TEST(MjcfBadInput, MovingHfieldAndMeshWithoutAHull) {
  const std::string grid_path = temp_file("grid.bin", std::string("\2\0\0\0\2\0\0\0", 8) + std::string(16, '\0'));
  const std::string moving = temp_file(
      "moving.xml", "<mujoco><asset><hfield name=\"h\" file=\"" + grid_path +
                        "\" size=\"1 1 .1 .1\"/></asset><worldbody><body><freejoint/><geom name=\"ground\" type=\"hfield\" "
                        "hfield=\"h\"/><geom type=\"sphere\" size=\".1\"/></body></worldbody></mujoco>");
  const std::string error = load_error(moving);
  EXPECT_NE(error.find("'ground'"), std::string::npos) << error;
  EXPECT_NE(error.find("hfield only allowed in static bodies"), std::string::npos) << error;
  const std::string no_hull = temp_file(
      "no_hull.xml", "<mujoco><compiler convexhull=\"false\"/><asset><mesh name=\"m\" vertex=\"0 0 0  1 0 0  0 1 0  0 0 1\" "
                     "face=\"0 2 1  0 1 3  0 3 2  1 2 3\"/>"
                     "</asset><worldbody><body><freejoint/><geom name=\"rock\" type=\"mesh\" mesh=\"m\"/></body></worldbody></mujoco>");
  const std::string hull_error = load_error(no_hull);
  EXPECT_NE(hull_error.find("geom \"rock\""), std::string::npos) << hull_error;
  EXPECT_NE(hull_error.find("no convex hull"), std::string::npos) << hull_error;
}

#endif

}  // namespace
}  // namespace ldlpgs
