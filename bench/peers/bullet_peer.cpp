// Bullet 3.24 in double precision (Debian's bullet-float64: BT_USE_DOUBLE_PRECISION) as a peer:
// a btDiscreteDynamicsWorld with the sequential impulse solver, every body a btRigidBody
// (static ones of mass 0) with an empty shape in collision group 0 and mask 0 (no collisions)
// and deactivation off; constraints btPoint2PointConstraint (ball), btHingeConstraint,
// btSliderConstraint (prismatic: its angular limits 0 by default; cylindrical: freed) and
// btFixedConstraint (weld), their frames in the body frames (ours: the centre of mass and
// principal axes, as Bullet's). One stepSimulation(dt, 0) is one step of dt (no substeps).
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <limits>
#include <memory>

#include "bench/peers/engines.h"

namespace ldlpgs::peers {

namespace {

btVector3 bt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

// A constraint frame in a body's frame: origin the anchor, rotation whose column `axis_column`
// is our axis n (frame column 2; hinge: z, slider: x), right-handed.
btTransform frame(const Eigen::Vector3d& anchor, const Eigen::Matrix3d& f, int axis_column) {
  Eigen::Matrix3d r;
  const Eigen::Vector3d n = f.col(2), u = f.col(0);
  r.col(axis_column) = n;
  r.col((axis_column + 1) % 3) = u;
  r.col((axis_column + 2) % 3) = n.cross(u);
  btMatrix3x3 basis(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(basis, bt(anchor));
}

}  // namespace

PeerResult run_bullet(const Mechanism& m, double seconds, int iterations) {
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                              ConstraintType::cylindrical, ConstraintType::weld}, "Bullet");
  if (!r.ran()) return r;
  // Declared before the world, so they outlive it (its destructor walks its objects).
  btEmptyShape shape;
  std::vector<std::unique_ptr<btRigidBody>> body;
  std::vector<std::unique_ptr<btTypedConstraint>> joint;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(bt(m.gravity));
  world.getSolverInfo().m_numIterations = iterations;

  for (const RigidBody& b : m.bodies) {
    btRigidBody::btRigidBodyConstructionInfo info(b.is_static ? 0.0 : b.mass, nullptr, &shape,
                                                  b.is_static ? btVector3(0, 0, 0) : bt(b.inertia));
    info.m_startWorldTransform =
        btTransform(btQuaternion(b.orientation.x(), b.orientation.y(), b.orientation.z(), b.orientation.w()),
                    bt(b.position));
    body.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* rb = body.back().get();
    if (!b.is_static) {
      rb->setLinearVelocity(bt(b.linear_velocity));
      rb->setAngularVelocity(bt(b.angular_velocity));
      rb->setActivationState(DISABLE_DEACTIVATION);
    }
    world.addRigidBody(rb, 0, 0);
  }
  for (const Constraint& c : m.constraints) {
    btRigidBody& a = *body[c.body_a];
    btRigidBody& b = *body[c.body_b];
    switch (c.type) {
      case ConstraintType::ball:
        joint.push_back(std::make_unique<btPoint2PointConstraint>(a, b, bt(c.anchor_a), bt(c.anchor_b)));
        break;
      case ConstraintType::hinge:
        joint.push_back(std::make_unique<btHingeConstraint>(a, b, frame(c.anchor_a, c.frame_a, 2),
                                                            frame(c.anchor_b, c.frame_b, 2)));
        break;
      case ConstraintType::prismatic:
      case ConstraintType::cylindrical: {
        auto slider = std::make_unique<btSliderConstraint>(a, b, frame(c.anchor_a, c.frame_a, 0),
                                                           frame(c.anchor_b, c.frame_b, 0), true);
        if (c.type == ConstraintType::cylindrical) {  // lower > upper frees the rotation
          slider->setLowerAngLimit(1);
          slider->setUpperAngLimit(-1);
        }
        joint.push_back(std::move(slider));
        break;
      }
      default:  // weld
        joint.push_back(std::make_unique<btFixedConstraint>(a, b, frame(c.anchor_a, c.frame_a, 2),
                                                            frame(c.anchor_b, c.frame_b, 2)));
        break;
    }
    world.addConstraint(joint.back().get(), true);
  }

  Mechanism state = m;
  auto read_back = [&] {
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      const btTransform& t = body[i]->getCenterOfMassTransform();
      const btQuaternion q = t.getRotation();
      state.bodies[i].position = eig(t.getOrigin());
      state.bodies[i].orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
      r.positions.push_back(state.bodies[i].position);
    }
  };
  timed_steps(m, seconds, [&] { world.stepSimulation(m.timestep, 0); }, read_back, &r);

  // Bullet's own pivots and frames, each carried by its body's transform; the slider's frames
  // slide along the axis, so across it (ours, on Bullet's poses).
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const Constraint& c = m.constraints[i];
    const btTransform& ta = body[c.body_a]->getCenterOfMassTransform();
    const btTransform& tb = body[c.body_b]->getCenterOfMassTransform();
    btVector3 pa, pb;
    switch (c.type) {
      case ConstraintType::ball: {
        const auto& p2p = static_cast<const btPoint2PointConstraint&>(*joint[i]);
        pa = ta * p2p.getPivotInA();
        pb = tb * p2p.getPivotInB();
        break;
      }
      case ConstraintType::hinge: {
        auto& h = static_cast<btHingeConstraint&>(*joint[i]);
        pa = ta * h.getAFrame().getOrigin();
        pb = tb * h.getBFrame().getOrigin();
        break;
      }
      case ConstraintType::weld: {
        auto& f = static_cast<btFixedConstraint&>(*joint[i]);
        pa = ta * f.getFrameOffsetA().getOrigin();
        pb = tb * f.getFrameOffsetB().getOrigin();
        break;
      }
      default:
        r.separation = std::max(r.separation, joint_separation(c, state.bodies[c.body_a], state.bodies[c.body_b]));
        continue;
    }
    r.separation = std::max(r.separation, static_cast<double>((pa - pb).length()));
  }
  for (const RigidBody& b : state.bodies) r.finite = r.finite && b.position.allFinite();
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  for (auto& j : joint) world.removeConstraint(j.get());
  for (auto& b : body) world.removeRigidBody(b.get());
  return r;
}

}  // namespace ldlpgs::peers
