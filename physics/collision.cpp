// Collision detection with ODE: one geom per shape, placed without an ODE body at its body's pose
// before each pass; dSpaceCollide finds the candidate pairs, dCollide their points.
#include "ldlpgs/physics/collision.h"

#include <algorithm>
#include <mutex>

#include <ode/ode.h>

namespace ldlpgs {

namespace {

// ODE's global data, once per process, and its per-thread collision data, once per thread.
void init_ode() {
  static std::once_flag once;
  std::call_once(once, [] { dInitODE2(0); });
  thread_local bool thread_ready = false;
  if (!thread_ready) {
    dAllocateODEDataForThread(dAllocateMaskAll);
    thread_ready = true;
  }
}

struct GeomOwner {
  int body = -1, shape = -1;
};

}  // namespace

struct CollisionWorld::Geometry {
  dSpaceID space = nullptr;
  std::vector<dGeomID> geoms;       // (size shapes)
  std::vector<GeomOwner> owners;    // the body and shape of each geom (size shapes)
  std::vector<std::pair<int, int>> excluded;  // body pairs (low, high) that may not touch, sorted
  const Mechanism* mechanism = nullptr;  // during detect()
  std::vector<ContactPoint>* out = nullptr;

  ~Geometry() {
    if (space) dSpaceDestroy(space);  // destroys its geoms (cleanup mode on)
  }
  bool excluded_pair(int a, int b) const {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    return std::binary_search(excluded.begin(), excluded.end(), key);
  }
};

namespace {

dGeomID make_geom(dSpaceID space, const Shape& s) {
  switch (s.type) {
    case ShapeType::plane: return dCreatePlane(space, 0, 0, 1, 0);  // parameters set by place()
    case ShapeType::sphere: return dCreateSphere(space, s.radius);
    case ShapeType::capsule: return dCreateCapsule(space, s.radius, 2 * s.half_length);  // ODE: the segment's length
    case ShapeType::box: return dCreateBox(space, 2 * s.half_extents.x(), 2 * s.half_extents.y(), 2 * s.half_extents.z());
  }
  return nullptr;
}

// The geom at its body's current pose: world pose = body pose * shape pose; a plane as
// n . x = n . p in the world (ODE's planes are not placeable).
void place(dGeomID g, const Shape& s, const RigidBody& body) {
  if (s.type == ShapeType::plane) {
    const Eigen::Vector3d n = (body.orientation * s.normal).normalized();
    dGeomPlaneSetParams(g, n.x(), n.y(), n.z(), n.dot(body.to_world(s.position)));
    return;
  }
  const Eigen::Vector3d p = body.to_world(s.position);
  const Eigen::Quaterniond q = body.orientation * s.orientation;
  dGeomSetPosition(g, p.x(), p.y(), p.z());
  const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(g, dq);
}

// dSpaceCollide's callback: a candidate pair (their bounding boxes overlap) to dCollide, unless
// the rules of shape.h keep it apart. ODE's normal points into the first geom (moving o1 along it
// separates them). Body a is the pair's lower index whatever order the space passes them in
// (sweep and prune's order follows the bodies' coordinates), so that a pair's points keep their
// identity from step to step (contact.h's matching).
void near_callback(void* data, dGeomID o1, dGeomID o2) {
  auto& g = *static_cast<CollisionWorld::Geometry*>(data);
  const GeomOwner& x = g.owners[reinterpret_cast<size_t>(dGeomGetData(o1))];
  const GeomOwner& y = g.owners[reinterpret_cast<size_t>(dGeomGetData(o2))];
  const Mechanism& m = *g.mechanism;
  const RigidBody &bx = m.bodies[x.body], &by = m.bodies[y.body];
  if (x.body == y.body || (bx.is_static && by.is_static)) return;
  if (!may_collide(bx.shapes[x.shape], by.shapes[y.shape]) || g.excluded_pair(x.body, y.body)) return;
  dContactGeom points[kMaxPointsPerPair];
  const int n = dCollide(o1, o2, kMaxPointsPerPair, points, sizeof(dContactGeom));
  const bool flip = x.body < y.body;  // then a = o1's body and the normal is ODE's reversed
  const GeomOwner &a = flip ? x : y, &b = flip ? y : x;
  for (int i = 0; i < n; ++i) {
    const dContactGeom& c = points[i];
    ContactPoint p;
    p.body_a = a.body;
    p.shape_a = a.shape;
    p.body_b = b.body;
    p.shape_b = b.shape;
    p.position = Eigen::Vector3d(c.pos[0], c.pos[1], c.pos[2]);
    p.normal = Eigen::Vector3d(c.normal[0], c.normal[1], c.normal[2]);
    if (flip) p.normal = -p.normal;
    p.depth = c.depth;
    g.out->push_back(p);
  }
}

}  // namespace

bool has_shapes(const Mechanism& m) {
  return std::any_of(m.bodies.begin(), m.bodies.end(), [](const RigidBody& b) { return !b.shapes.empty(); });
}

CollisionWorld::CollisionWorld(const Mechanism& m) : geometry_(std::make_unique<Geometry>()) {
  init_ode();
  Geometry& g = *geometry_;
  g.space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XZY);  // (measured fastest; the hash space allocates per pass)
  dSpaceSetCleanup(g.space, 1);
  for (int b = 0; b < static_cast<int>(m.bodies.size()); ++b)
    for (int s = 0; s < static_cast<int>(m.bodies[b].shapes.size()); ++s) {
      const dGeomID geom = make_geom(g.space, m.bodies[b].shapes[s]);
      dGeomSetData(geom, reinterpret_cast<void*>(g.geoms.size()));
      g.geoms.push_back(geom);
      g.owners.push_back({b, s});
    }
  for (const Constraint& c : m.constraints)
    if (!c.collide) g.excluded.emplace_back(std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b));
  std::sort(g.excluded.begin(), g.excluded.end());
}

CollisionWorld::~CollisionWorld() = default;
CollisionWorld::CollisionWorld(CollisionWorld&&) noexcept = default;
CollisionWorld& CollisionWorld::operator=(CollisionWorld&&) noexcept = default;

bool CollisionWorld::empty() const { return geometry_->geoms.empty(); }

void CollisionWorld::detect(const Mechanism& m, std::vector<ContactPoint>* out) {
  init_ode();
  Geometry& g = *geometry_;
  out->clear();
  if (g.geoms.empty()) return;
  for (size_t i = 0; i < g.geoms.size(); ++i) {
    const RigidBody& body = m.bodies[g.owners[i].body];
    // A body outside the mechanism's ranges (a run that came apart) touches nothing: ODE's hash
    // space stops the process on bounds beyond its integer grid.
    const bool within = body.position.allFinite() && body.position.cwiseAbs().maxCoeff() <= MechanismRanges::coordinate_max &&
                        body.orientation.coeffs().allFinite();
    if (!within) {
      dGeomDisable(g.geoms[i]);
      continue;
    }
    dGeomEnable(g.geoms[i]);
    place(g.geoms[i], body.shapes[g.owners[i].shape], body);
  }
  g.mechanism = &m;
  g.out = out;
  dSpaceCollide(g.space, &g, &near_callback);
  g.mechanism = nullptr;
  g.out = nullptr;
}

}  // namespace ldlpgs
