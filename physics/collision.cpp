// Collision detection with ODE: one geom per shape, placed without an ODE body at its body's pose
// before each pass; dSpaceCollide finds the candidate pairs, dCollide their points.
#include "ldlpgs/physics/collision.h"

#include <algorithm>
#include <array>
#include <limits>
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

constexpr double kMaxMargin = 100;  // m

struct GeomOwner {
  int body = -1, shape = -1;
};

// The farthest point of a shape from its body's centre of mass (m; a plane: 0, it is static).
double reach(const Shape& s) {
  switch (s.type) {
    case ShapeType::plane: return 0;
    case ShapeType::sphere: return s.position.norm() + s.radius;
    case ShapeType::capsule: return s.position.norm() + s.half_length + s.radius;
    case ShapeType::box: return s.position.norm() + s.half_extents.norm();
  }
  return 0;
}

}  // namespace

struct CollisionWorld::Geometry {
  std::vector<dGeomID> geoms;       // (size shapes; in no ODE space)
  std::vector<GeomOwner> owners;    // the body and shape of each geom (size shapes)
  std::vector<char> enabled;        // its body is within the mechanism's ranges this pass (size shapes)
  std::vector<int> planes;          // the geoms that are planes (unbounded: no sweep)
  std::vector<int> swept;           // the others, in the order of their boxes' lower x (size shapes - planes)
  std::vector<std::array<double, 6>> box;  // each geom's bounding box this pass, ODE's order (size shapes)
  std::vector<std::pair<int, int>> excluded;  // body pairs (low, high) that may not touch, sorted
  std::vector<double> reach;        // each body's farthest shape point from its centre (size bodies)
  std::vector<double> margin;       // this pass's inflation of each body's shapes (size bodies)
  const Mechanism* mechanism = nullptr;  // during detect()
  std::vector<ContactPoint>* out = nullptr;

  ~Geometry() {
    for (dGeomID geom : geoms) dGeomDestroy(geom);
  }
  void sweep_and_prune();
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

// The geom at its body's current pose, inflated by `margin`: world pose = body pose * shape pose;
// a plane as n . x = n . p + margin in the world (ODE's planes are not placeable).
void place(dGeomID g, const Shape& s, const RigidBody& body, double margin) {
  switch (s.type) {
    case ShapeType::plane: break;
    case ShapeType::sphere: dGeomSphereSetRadius(g, s.radius + margin); break;
    case ShapeType::capsule: dGeomCapsuleSetParams(g, s.radius + margin, 2 * s.half_length); break;
    case ShapeType::box: {
      const Eigen::Vector3d l = 2 * (s.half_extents.array() + margin).matrix();
      dGeomBoxSetLengths(g, l.x(), l.y(), l.z());
      break;
    }
  }
  if (s.type == ShapeType::plane) {
    const Eigen::Vector3d n = (body.orientation * s.normal).normalized();
    dGeomPlaneSetParams(g, n.x(), n.y(), n.z(), n.dot(body.to_world(s.position)) + margin);
    return;
  }
  const Eigen::Vector3d p = body.to_world(s.position);
  const Eigen::Quaterniond q = body.orientation * s.orientation;
  dGeomSetPosition(g, p.x(), p.y(), p.z());
  const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(g, dq);
}

// A box shape's frame in the world (rotation, centre) and half extents, for near_callback.
struct InflatedBox {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d centre, half_extents;
  // The point moved into the box across the contact plane only: the part of what the clamp
  // removes that lies along the normal n is kept.
  Eigen::Vector3d clamp(const Eigen::Vector3d& point, const Eigen::Vector3d& n) const {
    const Eigen::Vector3d local = rotation.transpose() * (point - centre), n_local = rotation.transpose() * n;
    const Eigen::Vector3d within = local.cwiseMax(-half_extents).cwiseMin(half_extents);
    return centre + rotation * (within + (local - within).dot(n_local) * n_local);
  }
};

// The broad phase's candidate pair (their bounding boxes overlap) to dCollide, unless
// the rules of shape.h keep it apart. ODE's normal points into the first geom (moving o1 along it
// separates them). Body a is the pair's lower index whatever order the sweep passes them in (its
// order follows the bodies' coordinates), so that a pair's points keep their identity from step
// to step (contact.h's matching).
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
  const double ma = g.margin[a.body], mb = g.margin[b.body];
  // An inflated box's corners stand out by its margin sideways too: its points are brought back
  // within the real box (a sphere or capsule grows along its own normals, which needs none).
  InflatedBox boxes[2];
  int clamped = 0;
  for (const GeomOwner* o : {&a, &b}) {
    const RigidBody& body = m.bodies[o->body];
    const Shape& s = body.shapes[o->shape];
    if (s.type == ShapeType::box && g.margin[o->body] != 0)
      boxes[clamped++] = {(body.orientation * s.orientation).toRotationMatrix(), body.to_world(s.position), s.half_extents};
  }
  for (int i = 0; i < n; ++i) {
    const dContactGeom& c = points[i];
    ContactPoint p;
    p.body_a = a.body;
    p.shape_a = a.shape;
    p.body_b = b.body;
    p.shape_b = b.shape;
    p.normal = Eigen::Vector3d(c.normal[0], c.normal[1], c.normal[2]);
    if (flip) p.normal = -p.normal;
    // The inflated surfaces overlap by c.depth about c.pos; the real ones lie ma and mb behind
    // them: their depth is c.depth - ma - mb, about the point midway between them.
    p.depth = c.depth - ma - mb;
    p.position = Eigen::Vector3d(c.pos[0], c.pos[1], c.pos[2]) + 0.5 * (mb - ma) * p.normal;
    for (int k = 0; k < clamped; ++k) p.position = boxes[k].clamp(p.position, p.normal);
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
  for (int b = 0; b < static_cast<int>(m.bodies.size()); ++b)
    for (int s = 0; s < static_cast<int>(m.bodies[b].shapes.size()); ++s) {
      const dGeomID geom = make_geom(nullptr, m.bodies[b].shapes[s]);
      const int index = static_cast<int>(g.geoms.size());
      dGeomSetData(geom, reinterpret_cast<void*>(static_cast<size_t>(index)));
      (m.bodies[b].shapes[s].type == ShapeType::plane ? g.planes : g.swept).push_back(index);
      g.geoms.push_back(geom);
      g.owners.push_back({b, s});
    }
  g.enabled.assign(g.geoms.size(), 1);
  g.box.resize(g.geoms.size());
  g.reach.assign(m.bodies.size(), 0.0);
  g.margin.assign(m.bodies.size(), 0.0);
  for (size_t b = 0; b < m.bodies.size(); ++b)
    for (const Shape& s : m.bodies[b].shapes) g.reach[b] = std::max(g.reach[b], reach(s));
  for (const Constraint& c : m.constraints)
    if (!c.collide) g.excluded.emplace_back(std::min(c.body_a, c.body_b), std::max(c.body_a, c.body_b));
  std::sort(g.excluded.begin(), g.excluded.end());
}

CollisionWorld::~CollisionWorld() = default;
CollisionWorld::CollisionWorld(CollisionWorld&&) noexcept = default;
CollisionWorld& CollisionWorld::operator=(CollisionWorld&&) noexcept = default;

bool CollisionWorld::empty() const { return geometry_->geoms.empty(); }

void CollisionWorld::detect(const Mechanism& m, double margin, double horizon, std::vector<ContactPoint>* out) {
  init_ode();
  Geometry& g = *geometry_;
  out->clear();
  if (g.geoms.empty()) return;
  // A dynamic body's shapes grow by what its points travel in the horizon at its velocities
  // (|v| + |w| reach) and a static body's by what gravity's pull adds to that (|g| horizon^2):
  // every dynamic body falls alike, so gravity closes no gap between two of them. At most 100 m:
  // a body that fast is found by its motion's next steps anyway, and a geom inflated beyond its
  // world would only gather every pair (NaN: the most).
  const auto capped = [](double inflation) { return inflation < kMaxMargin ? inflation : kMaxMargin; };
  const double fall = m.gravity.norm() * horizon * horizon;
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const RigidBody& body = m.bodies[b];
    const double speed = body.linear_velocity.norm() + body.angular_velocity.norm() * g.reach[b];
    g.margin[b] = capped(body.is_static ? fall : margin + speed * horizon);
  }
  for (size_t i = 0; i < g.geoms.size(); ++i) {
    const RigidBody& body = m.bodies[g.owners[i].body];
    // A body outside the mechanism's ranges (a run that came apart) touches nothing (ODE's hash
    // space stopped the process on bounds beyond its integer grid).
    const bool within = body.position.allFinite() && body.position.cwiseAbs().maxCoeff() <= MechanismRanges::coordinate_max &&
                        body.orientation.coeffs().allFinite();
    g.enabled[i] = within;
    if (!within) continue;
    place(g.geoms[i], body.shapes[g.owners[i].shape], body, g.margin[g.owners[i].body]);
    dGeomGetAABB(g.geoms[i], g.box[i].data());
  }
  g.mechanism = &m;
  g.out = out;
  g.sweep_and_prune();
  g.mechanism = nullptr;
  g.out = nullptr;
}

// The broad phase: every plane against every other geom (dCollide tests the plane), and the
// bounded geoms swept along x, their order kept from the last pass and restored by insertion
// sort (nearly sorted from one step to the next: linear). ODE's own spaces allocate on every
// pass (papers/physics.md, "Collision detection").
void CollisionWorld::Geometry::sweep_and_prune() {
  for (int p : planes)
    for (int i = 0; i < static_cast<int>(geoms.size()); ++i)
      if (i != p && enabled[i] && enabled[p]) near_callback(this, geoms[p], geoms[i]);
  const auto lower_x = [&](int i) { return enabled[i] ? box[i][0] : std::numeric_limits<double>::infinity(); };  // (disabled last)
  for (size_t k = 1; k < swept.size(); ++k)
    for (size_t j = k; j > 0 && lower_x(swept[j - 1]) > lower_x(swept[j]); --j) std::swap(swept[j - 1], swept[j]);
  for (size_t k = 0; k < swept.size() && enabled[swept[k]]; ++k) {
    const std::array<double, 6>& a = box[swept[k]];
    for (size_t l = k + 1; l < swept.size() && enabled[swept[l]]; ++l) {
      const std::array<double, 6>& b = box[swept[l]];
      if (b[0] > a[1]) break;  // (sorted by lower x: no later box reaches back to this one)
      if (b[2] > a[3] || a[2] > b[3] || b[4] > a[5] || a[4] > b[5]) continue;
      near_callback(this, geoms[swept[k]], geoms[swept[l]]);
    }
  }
}

}  // namespace ldlpgs
