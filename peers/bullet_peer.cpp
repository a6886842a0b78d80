// Bullet 3.24 in double precision (Debian's bullet-float64: BT_USE_DOUBLE_PRECISION) as a peer:
// a btDiscreteDynamicsWorld with the sequential impulse solver, every body a btRigidBody
// (static ones of mass 0) with deactivation off; constraints btPoint2PointConstraint (ball), btHingeConstraint,
// btSliderConstraint (prismatic: its angular limits 0 by default; cylindrical: freed) and
// btFixedConstraint (weld), their frames in the body frames (ours: the centre of mass and
// principal axes, as Bullet's). One stepSimulation(dt, 0) is one step of dt (no substeps).
//
// Contacts: a body's shapes as Bullet shapes (btStaticPlaneShape, btSphereShape,
// btCapsuleShapeZ: ours lie along z, Bullet's default btCapsuleShape along y; btBoxShape), in a
// btCompoundShape at their poses in the body frame unless the body has one shape at its centre;
// a body without shapes keeps an empty shape in collision group 0 and mask 0 (no collisions).
// Pair rules: Bullet multiplies the two bodies' frictions and restitutions by default; the
// combine callbacks (btManifoldResult.h) are set to ours for the run, sqrt(mu_a mu_b) and
// max(e_a, e_b), on each body's friction and restitution: Bullet keeps one per body, the largest
// of its shapes' (exact where a body's shapes agree, as in every built-in scene). The filter of
// physics/shape.h replaces Bullet's group and mask test (an overlap filter callback), per body
// too: two bodies may touch if any of their shapes may; bodies joined without `collide` are
// ignored pairs (addConstraint's disableCollisionsBetweenLinkedBodies). Bullet's defaults
// otherwise: collision margins 0.04 m (inside boxes, the radius of spheres and capsules), split
// impulse on, contact ERP 0.2.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "peers/engines.h"

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

// A shape in its own frame.
std::unique_ptr<btCollisionShape> bullet_shape(const Shape& s) {
  switch (s.type) {
    case ShapeType::plane: {
      const Eigen::Vector3d n = s.normal.normalized();
      return std::make_unique<btStaticPlaneShape>(bt(n), n.dot(s.position));
    }
    case ShapeType::sphere: return std::make_unique<btSphereShape>(s.radius);
    case ShapeType::capsule: return std::make_unique<btCapsuleShapeZ>(s.radius, 2 * s.half_length);
    case ShapeType::box: return std::make_unique<btBoxShape>(bt(s.half_extents));
    case ShapeType::cylinder: return std::make_unique<btCylinderShapeZ>(btVector3(s.radius, s.radius, s.half_length));
    case ShapeType::ellipsoid:
    case ShapeType::convex:
    case ShapeType::heightfield: break;  // (run_bullet skips mechanisms with these)
  }
  return nullptr;
}

btScalar sqrt_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}
btScalar max_restitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::max(a->getRestitution(), b->getRestitution());
}

// The pair filter of physics/shape.h on two collision objects (their user index: our body).
struct Filter : btOverlapFilterCallback {
  const Mechanism* m = nullptr;
  bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
    const RigidBody& a = m->bodies[static_cast<btCollisionObject*>(p0->m_clientObject)->getUserIndex()];
    const RigidBody& b = m->bodies[static_cast<btCollisionObject*>(p1->m_clientObject)->getUserIndex()];
    if (a.is_static && b.is_static) return false;
    for (const Shape& x : a.shapes)
      for (const Shape& y : b.shapes)
        if (may_collide(x, y)) return true;
    return false;
  }
};

// Our combine rules while alive, Bullet's back after.
struct PairRules {
  CalculateCombinedCallback friction = gCalculateCombinedFrictionCallback;
  CalculateCombinedCallback restitution = gCalculateCombinedRestitutionCallback;
  PairRules() {
    gCalculateCombinedFrictionCallback = &sqrt_friction;
    gCalculateCombinedRestitutionCallback = &max_restitution;
  }
  ~PairRules() {
    gCalculateCombinedFrictionCallback = friction;
    gCalculateCombinedRestitutionCallback = restitution;
  }
};

}  // namespace

PeerResult run_bullet(const Mechanism& m, double seconds, int iterations, bool two_friction) {
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                              ConstraintType::cylindrical, ConstraintType::weld}, "Bullet");
  if (r.ran())
    r.skipped = unsupported(m, {ShapeType::plane, ShapeType::sphere, ShapeType::capsule, ShapeType::box, ShapeType::cylinder},
                            "Bullet");
  if (!r.ran()) return r;
  // Declared before the world, so they outlive it (its destructor walks its objects).
  btEmptyShape empty;
  Filter filter;
  filter.m = &m;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;  // children first, then compounds
  std::vector<std::unique_ptr<btRigidBody>> body;
  std::vector<std::unique_ptr<btTypedConstraint>> joint;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(bt(m.gravity));
  world.getSolverInfo().m_numIterations = iterations;
  if (two_friction) world.getSolverInfo().m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
  world.getPairCache()->setOverlapFilterCallback(&filter);
  const PairRules rules;

  for (const RigidBody& b : m.bodies) {
    btCollisionShape* shape = &empty;
    double friction = 0, restitution = 0;
    for (const Shape& s : b.shapes) {
      friction = std::max(friction, s.friction);
      restitution = std::max(restitution, s.restitution);
      shapes.push_back(bullet_shape(s));
    }
    if (b.shapes.size() == 1 && (b.shapes[0].type == ShapeType::plane ||
                                 (b.shapes[0].position.isZero() && b.shapes[0].orientation.coeffs() == Eigen::Quaterniond::Identity().coeffs()))) {
      shape = shapes.back().get();
    } else if (!b.shapes.empty()) {
      auto compound = std::make_unique<btCompoundShape>();
      for (size_t k = 0; k < b.shapes.size(); ++k) {
        const Shape& s = b.shapes[k];
        const Eigen::Quaterniond& q = s.orientation;
        compound->addChildShape(btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(s.position)),
                                shapes[shapes.size() - b.shapes.size() + k].get());
      }
      shapes.push_back(std::move(compound));
      shape = shapes.back().get();
    }
    btRigidBody::btRigidBodyConstructionInfo info(b.is_static ? 0.0 : b.mass, nullptr, shape,
                                                  b.is_static ? btVector3(0, 0, 0) : bt(b.inertia));
    info.m_startWorldTransform =
        btTransform(btQuaternion(b.orientation.x(), b.orientation.y(), b.orientation.z(), b.orientation.w()),
                    bt(b.position));
    info.m_friction = friction;
    info.m_restitution = restitution;
    body.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* rb = body.back().get();
    rb->setUserIndex(static_cast<int>(body.size()) - 1);
    if (!b.is_static) {
      rb->setLinearVelocity(bt(b.linear_velocity));
      rb->setAngularVelocity(bt(b.angular_velocity));
      rb->setActivationState(DISABLE_DEACTIVATION);
    }
    if (b.shapes.empty())
      world.addRigidBody(rb, 0, 0);
    else
      world.addRigidBody(rb);  // the filter decides
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
    world.addConstraint(joint.back().get(), !c.collide);
  }

  Mechanism state = m;
  auto read_back = [&] {
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      const btTransform& t = body[i]->getCenterOfMassTransform();
      const btQuaternion q = t.getRotation();
      state.bodies[i].position = eig(t.getOrigin());
      state.bodies[i].orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
    }
    record_poses(state, &r);
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
