// ODE 0.16 (Debian's libode-dev, built with dDOUBLE) as a peer: every dynamic body a dBody with
// its mass and principal inertia, every static body the world (body 0), joints ball, hinge,
// slider (our prismatic), piston (our cylindrical) and fixed (our weld), set at the initial pose; no geoms, so no
// collisions. ERP is our Baumgarte factor 0.2 (also ODE's default), CFM ODE's default.
// dWorldStep solves the LCP with a dense factorization (O(rows^3)); dWorldQuickStep runs SOR
// iterations (ODE's default 20).
#include <ode/ode.h>

#include <algorithm>
#include <limits>
#include <mutex>

#include "bench/peers/engines.h"

namespace ldlpgs::peers {

namespace {

static_assert(sizeof(dReal) == sizeof(double), "the peers compare double precision engines");

struct World {
  dWorldID id = dWorldCreate();
  ~World() { dWorldDestroy(id); }  // destroys its bodies and joints
};

Eigen::Vector3d vec(const dReal* p) { return {p[0], p[1], p[2]}; }

}  // namespace

PeerResult run_ode(const Mechanism& m, double seconds, int quickstep_iterations) {
  static std::once_flag init;
  std::call_once(init, [] { dInitODE2(0); });
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                              ConstraintType::cylindrical, ConstraintType::weld}, "ODE");
  if (!r.ran()) return r;
  World world;
  dWorldSetGravity(world.id, m.gravity.x(), m.gravity.y(), m.gravity.z());
  dWorldSetERP(world.id, 0.2);
  if (quickstep_iterations) dWorldSetQuickStepNumIterations(world.id, quickstep_iterations);

  std::vector<dBodyID> body(m.bodies.size(), nullptr);  // nullptr: static, the world
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const RigidBody& b = m.bodies[i];
    if (b.is_static) continue;
    body[i] = dBodyCreate(world.id);
    dMass mass;
    dMassSetParameters(&mass, b.mass, 0, 0, 0, b.inertia.x(), b.inertia.y(), b.inertia.z(), 0, 0, 0);
    dBodySetMass(body[i], &mass);
    dBodySetPosition(body[i], b.position.x(), b.position.y(), b.position.z());
    const dQuaternion q = {b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()};
    dBodySetQuaternion(body[i], q);
    dBodySetLinearVel(body[i], b.linear_velocity.x(), b.linear_velocity.y(), b.linear_velocity.z());
    dBodySetAngularVel(body[i], b.angular_velocity.x(), b.angular_velocity.y(), b.angular_velocity.z());
  }
  std::vector<dJointID> joint(m.constraints.size());
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const Constraint& c = m.constraints[i];
    const RigidBody& a = m.bodies[c.body_a];
    const Eigen::Vector3d p = a.to_world(c.anchor_a), n = a.orientation * c.frame_a.col(2);
    switch (c.type) {
      case ConstraintType::ball: joint[i] = dJointCreateBall(world.id, 0); break;
      case ConstraintType::hinge: joint[i] = dJointCreateHinge(world.id, 0); break;
      case ConstraintType::prismatic: joint[i] = dJointCreateSlider(world.id, 0); break;
      case ConstraintType::cylindrical: joint[i] = dJointCreatePiston(world.id, 0); break;
      default: joint[i] = dJointCreateFixed(world.id, 0); break;  // weld (unsupported() let nothing else through)
    }
    dJointAttach(joint[i], body[c.body_a], body[c.body_b]);
    switch (c.type) {
      case ConstraintType::ball: dJointSetBallAnchor(joint[i], p.x(), p.y(), p.z()); break;
      case ConstraintType::hinge:
        dJointSetHingeAnchor(joint[i], p.x(), p.y(), p.z());
        dJointSetHingeAxis(joint[i], n.x(), n.y(), n.z());
        break;
      case ConstraintType::prismatic: dJointSetSliderAxis(joint[i], n.x(), n.y(), n.z()); break;
      case ConstraintType::cylindrical:
        dJointSetPistonAnchor(joint[i], p.x(), p.y(), p.z());
        dJointSetPistonAxis(joint[i], n.x(), n.y(), n.z());
        break;
      default: dJointSetFixed(joint[i]); break;
    }
  }

  Mechanism state = m;  // the poses ODE reports
  auto read_back = [&] {
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      if (body[i]) {
        state.bodies[i].position = vec(dBodyGetPosition(body[i]));
        const dReal* q = dBodyGetQuaternion(body[i]);
        state.bodies[i].orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
      }
      r.positions.push_back(state.bodies[i].position);
    }
  };
  timed_steps(
      m, seconds,
      [&] {
        if (quickstep_iterations)
          dWorldQuickStep(world.id, m.timestep);
        else
          dWorldStep(world.id, m.timestep);
      },
      read_back, &r);

  // ODE's own anchors where it reports them (ball, hinge: the anchor as body 1 and as body 2 see
  // it); slider and fixed report none and the piston's anchors slide, so ours, on ODE's poses.
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const Constraint& c = m.constraints[i];
    dVector3 p1, p2;
    double sep;
    if (c.type == ConstraintType::ball || c.type == ConstraintType::hinge) {
      if (c.type == ConstraintType::ball) {
        dJointGetBallAnchor(joint[i], p1);
        dJointGetBallAnchor2(joint[i], p2);
      } else {
        dJointGetHingeAnchor(joint[i], p1);
        dJointGetHingeAnchor2(joint[i], p2);
      }
      sep = (vec(p1) - vec(p2)).norm();
    } else {
      sep = joint_separation(c, state.bodies[c.body_a], state.bodies[c.body_b]);
    }
    r.separation = std::max(r.separation, sep);
  }
  for (const RigidBody& b : state.bodies) r.finite = r.finite && b.position.allFinite();
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  return r;
}

}  // namespace ldlpgs::peers
