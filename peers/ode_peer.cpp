// ODE 0.16 (Debian's libode-dev, built with dDOUBLE) as a peer: every dynamic body a dBody with
// its mass and principal inertia, every static body the world (body 0), joints ball, hinge,
// slider (our prismatic), piston (our cylindrical) and fixed (our weld), set at the initial pose.
// ERP is our Baumgarte factor 0.2 (also ODE's default), CFM ODE's default.
// dWorldStep solves the LCP with a dense factorization (O(rows^3)); dWorldQuickStep runs SOR
// iterations (ODE's default 20).
//
// Contacts, as ODE's demos make them: one geom per shape, on its dBody at the shape's pose in the
// body frame (dGeomSetOffsetPosition/Quaternion; ODE's body frame is ours, the centre of mass and
// principal axes), a static body's geoms without a body at their world pose (a plane as
// n . x = d); a sweep-and-prune space as our detector's. Each step, before the solve,
// dSpaceCollide, the rules of physics/shape.h on each candidate pair, dCollide for up to 4
// points, each a dContactJoint (in a joint group emptied after the step) with mu = our pair's
// friction as a Coulomb coefficient (dContactApprox1: the friction pyramid's bound is mu times
// the normal impulse, not a constant force) and bounce = our restitution. No soft-contact
// settings: the contacts take the world's ERP 0.2 and CFM, as the joints do.
#include <ode/ode.h>

#include <algorithm>
#include <limits>
#include <mutex>

#include "peers/engines.h"
#include "ldlpgs/physics/collision.h"

namespace ldlpgs::peers {

namespace {

static_assert(sizeof(dReal) == sizeof(double), "the peers compare double precision engines");

struct World {
  dWorldID id = dWorldCreate();
  dSpaceID space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XZY);
  dJointGroupID contacts = dJointGroupCreate(0);
  World() { dSpaceSetCleanup(space, 1); }
  ~World() {
    dJointGroupDestroy(contacts);
    dSpaceDestroy(space);  // destroys its geoms
    dWorldDestroy(id);     // destroys its bodies and joints
  }
};

struct Owner {
  int body, shape;
};

// What dSpaceCollide's callback needs: the mechanism, each geom's owner (its data is the index),
// the body pairs our rules keep apart, the bodies' dBodyIDs.
struct Collide {
  const Mechanism* m;
  World* world;
  const std::vector<dBodyID>* body;
  std::vector<Owner> owner;
  std::vector<std::pair<int, int>> excluded;  // (low, high), sorted
};

// A candidate pair from the space, kept apart by the rules of physics/shape.h (one body, two
// static bodies, the pair filter, bodies joined without `collide`), else up to 4 contact joints.
void near_callback(void* data, dGeomID g1, dGeomID g2) {
  const Collide& c = *static_cast<const Collide*>(data);
  const Owner& x = c.owner[reinterpret_cast<size_t>(dGeomGetData(g1))];
  const Owner& y = c.owner[reinterpret_cast<size_t>(dGeomGetData(g2))];
  const RigidBody &bx = c.m->bodies[x.body], &by = c.m->bodies[y.body];
  if (x.body == y.body || (bx.is_static && by.is_static)) return;
  const Shape &sx = bx.shapes[x.shape], &sy = by.shapes[y.shape];
  if (!may_collide(sx, sy) ||
      std::binary_search(c.excluded.begin(), c.excluded.end(), std::pair<int, int>(std::minmax(x.body, y.body))))
    return;
  dContact contact[kMaxPointsPerPair];
  const int n = dCollide(g1, g2, kMaxPointsPerPair, &contact[0].geom, sizeof(dContact));
  for (int i = 0; i < n; ++i) {
    dSurfaceParameters& s = contact[i].surface;
    s = {};
    s.mode = dContactApprox1;
    s.mu = combined_friction(sx, sy);
    s.bounce = combined_restitution(sx, sy);
    if (s.bounce > 0) s.mode |= dContactBounce;
    const dJointID j = dJointCreateContact(c.world->id, c.world->contacts, &contact[i]);
    dJointAttach(j, (*c.body)[x.body], (*c.body)[y.body]);
  }
}

// The geoms of `m`'s shapes in world.space, on their bodies.
void make_geoms(const Mechanism& m, const std::vector<dBodyID>& body, World* world, Collide* c) {
  for (int b = 0; b < static_cast<int>(m.bodies.size()); ++b) {
    const RigidBody& rb = m.bodies[b];
    for (int k = 0; k < static_cast<int>(rb.shapes.size()); ++k) {
      const Shape& s = rb.shapes[k];
      dGeomID g = nullptr;
      switch (s.type) {
        case ShapeType::plane: {
          const Eigen::Vector3d n = (rb.orientation * s.normal).normalized();
          g = dCreatePlane(world->space, n.x(), n.y(), n.z(), n.dot(rb.to_world(s.position)));
          break;
        }
        case ShapeType::sphere: g = dCreateSphere(world->space, s.radius); break;
        case ShapeType::capsule: g = dCreateCapsule(world->space, s.radius, 2 * s.half_length); break;
        case ShapeType::box:
          g = dCreateBox(world->space, 2 * s.half_extents.x(), 2 * s.half_extents.y(), 2 * s.half_extents.z());
          break;
        case ShapeType::cylinder: g = dCreateCylinder(world->space, s.radius, 2 * s.half_length); break;
        case ShapeType::ellipsoid:
        case ShapeType::convex:
        case ShapeType::heightfield: break;  // (run_ode skips mechanisms with these)
      }
      dGeomSetData(g, reinterpret_cast<void*>(c->owner.size()));
      c->owner.push_back({b, k});
      if (s.type == ShapeType::plane) continue;
      const Eigen::Quaterniond q = body[b] ? s.orientation : rb.orientation * s.orientation;
      const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
      if (body[b]) {
        dGeomSetBody(g, body[b]);
        dGeomSetOffsetPosition(g, s.position.x(), s.position.y(), s.position.z());
        dGeomSetOffsetQuaternion(g, dq);
      } else {
        const Eigen::Vector3d p = rb.to_world(s.position);
        dGeomSetPosition(g, p.x(), p.y(), p.z());
        dGeomSetQuaternion(g, dq);
      }
    }
  }
  for (const Constraint& k : m.constraints)
    if (!k.collide) c->excluded.emplace_back(std::minmax(k.body_a, k.body_b));
  std::sort(c->excluded.begin(), c->excluded.end());
}

Eigen::Vector3d vec(const dReal* p) { return {p[0], p[1], p[2]}; }

}  // namespace

PeerResult run_ode(const Mechanism& m, double seconds, int quickstep_iterations) {
  static std::once_flag init;
  std::call_once(init, [] { dInitODE2(0); });
  thread_local bool thread_ready = false;  // ODE's per-thread collision data
  if (!thread_ready) thread_ready = dAllocateODEDataForThread(dAllocateMaskAll);
  PeerResult r;
  r.skipped = unsupported(m, {ConstraintType::ball, ConstraintType::hinge, ConstraintType::prismatic,
                              ConstraintType::cylindrical, ConstraintType::weld}, "ODE");
  if (r.ran())
    r.skipped = unsupported(m, {ShapeType::plane, ShapeType::sphere, ShapeType::capsule, ShapeType::box, ShapeType::cylinder},
                            "ODE");
  if (!r.ran()) return r;
  World world;
  dRandSetSeed(0);  // QuickStep shuffles its rows with ODE's global generator: the same run each time
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

  Collide collide{&m, &world, &body, {}, {}};
  make_geoms(m, body, &world, &collide);

  Mechanism state = m;  // the poses ODE reports
  auto read_back = [&] {
    for (size_t i = 0; i < m.bodies.size(); ++i) {
      if (body[i]) {
        state.bodies[i].position = vec(dBodyGetPosition(body[i]));
        const dReal* q = dBodyGetQuaternion(body[i]);
        state.bodies[i].orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
      }
    }
    record_poses(state, &r);
  };
  timed_steps(
      m, seconds,
      [&] {
        dSpaceCollide(world.space, &collide, &near_callback);
        if (quickstep_iterations)
          dWorldQuickStep(world.id, m.timestep);
        else
          dWorldStep(world.id, m.timestep);
        dJointGroupEmpty(world.contacts);
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
