// Which collision detector the physics layer should use for contacts, chosen by measurement: ODE's
// collision (dCollide in a hash or sweep-and-prune space, geoms without bodies), Bullet's
// btCollisionWorld (btDbvtBroadphase, persistent manifolds of up to 4 points) and libccd (MPR or
// GJK+EPA, one point per pair, as MuJoCo uses it; our sweep-and-prune along x as broad phase).
// Geometry only: every pass places the shapes (the exact poses, then poses perturbed by up to
// 1e-3 m and 1e-3 rad, as resting contact jitters) and runs broad and narrow phase over the scene.
// Prints Markdown (papers/ quotes it), from the repository root:
//   build/bin/collision_bench > /tmp/collision_bench.md
//
// Every detector's contacts are turned into one convention, checked against an analytic
// reference on the exact poses: a contact of shapes a < b has its normal pointing from a into b
// (moving b by depth along the normal separates them) and depth > 0 when they overlap. Each
// adapter names its library's own convention where it converts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "peers/median.h"

#ifdef LDLPGS_HAVE_ODE
#include <ode/ode.h>
#endif
#ifdef LDLPGS_HAVE_BULLET
#include <btBulletCollisionCommon.h>
#endif
#ifdef LDLPGS_HAVE_CCD
#include <ccd/ccd.h>
#endif

using Eigen::Quaterniond;
using Eigen::Vector3d;

namespace {

constexpr double kPenetration = 1e-3;  // every resting contact of the scenes overlaps by 1 mm
constexpr double kJitter = 1e-3;       // perturbation of the poses after the first pass (m, rad)
constexpr int kPoseSets = 64;          // pose sets cycled through: set 0 exact, the rest perturbed
constexpr int kMaxPointsPerPair = 4;   // what ODE is asked for; Bullet's manifold holds 4

// The shapes of physics/shape.h: a capsule's segment lies on its local z, half_length excluding the
// caps; the plane is z = 0 with normal +z, always geometry 0 of a scene.
enum class Kind { plane, box, sphere, capsule };

struct Geom {
  Kind kind = Kind::box;
  Vector3d position = Vector3d::Zero();
  Quaterniond orientation = Quaterniond::Identity();
  Vector3d half_extents = Vector3d::Constant(0.5);
  double radius = 0, half_length = 0;
  int link = -1;  // index in a chain: neighbours are jointed and never collide (-1: not in one)
};

struct Pose {
  Vector3d position;
  Quaterniond orientation;
};

struct Scene {
  std::string name;
  std::vector<Geom> geoms;  // [0] the plane
  bool excluded(int a, int b) const {
    return geoms[a].link >= 0 && geoms[b].link >= 0 && std::abs(geoms[a].link - geoms[b].link) == 1;
  }
};

// A contact point between shapes a < b: the normal points from a into b, depth > 0 overlapping.
// age: passes this point has survived matched to an earlier one (Bullet's lifetime; 0 elsewhere).
struct Contact {
  int a = 0, b = 0;
  Vector3d position, normal;
  double depth = 0;
  int age = 0;
};

Contact oriented(int a, int b, const Vector3d& position, const Vector3d& normal_into_b, double depth, int age = 0) {
  if (a < b) return {a, b, position, normal_into_b, depth, age};
  return {b, a, position, -normal_into_b, depth, age};
}

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::plane: return "plane";
    case Kind::box: return "box";
    case Kind::sphere: return "sphere";
    case Kind::capsule: return "capsule";
  }
  return "?";
}

// Lowest z of a shape: its depth below the plane is minus this.
double lowest_z(const Geom& g, const Pose& p) {
  const Eigen::Matrix3d r = p.orientation.toRotationMatrix();
  switch (g.kind) {
    case Kind::box: return p.position.z() - r.row(2).cwiseAbs().dot(g.half_extents);
    case Kind::sphere: return p.position.z() - g.radius;
    case Kind::capsule: return p.position.z() - std::abs(r(2, 2)) * g.half_length - g.radius;
    case Kind::plane: break;
  }
  return 0;
}

// ---- Scenes -------------------------------------------------------------------------------------

Geom box_at(double x, double z, const Quaterniond& q = Quaterniond::Identity()) {
  Geom g;
  g.position = {x, 0, z};
  g.orientation = q;
  return g;
}

// The 1:1000 stack's geometry: two boxes on the plane, each 1 mm into what it rests on.
Scene stack() {
  Scene s{"two boxes stacked (the 1:1000 stack)", {Geom{Kind::plane}}};
  s.geoms.push_back(box_at(0, 0.5 - kPenetration));
  s.geoms.push_back(box_at(0, 1.5 - 2 * kPenetration));
  return s;
}

// A box tilted by `angle` about `axis`, its lowest vertex 1 mm into the plane.
Scene box_on_plane(const char* name, double angle, const Vector3d& axis) {
  Scene s{name, {Geom{Kind::plane}}};
  Geom g = box_at(0, 0, Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())));
  g.position.z() = -kPenetration - lowest_z(g, {Vector3d::Zero(), g.orientation});
  s.geoms.push_back(g);
  return s;
}

// Layer i of `layers` holds layers - i boxes 1 m apart along x, on the layer below, shifted by half
// a box; every box 1 mm into what it rests on. Side neighbours touch with no gap and no overlap.
Scene pyramid(const char* name, int layers) {
  Scene s{name, {Geom{Kind::plane}}};
  for (int i = 0; i < layers; ++i)
    for (int j = 0; j < layers - i; ++j) s.geoms.push_back(box_at(0.5 * i + j, 0.5 - kPenetration + i * (1 - kPenetration)));
  return s;
}

// 20 capsules along x, cap to cap, 1 mm into the plane (neighbours jointed: no contact), and a
// sphere of radius 0.3 beyond the last, 1 mm into the plane and 1 mm into that capsule's cap.
Scene chain() {
  Scene s{"chain of 20 capsules + sphere", {Geom{Kind::plane}}};
  const double radius = 0.05, half_length = 0.2, pitch = 2 * (half_length + radius);
  const Quaterniond z_to_x(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()));
  for (int i = 0; i < 20; ++i) {
    Geom g{Kind::capsule, {i * pitch, 0, radius - kPenetration}, z_to_x};
    g.radius = radius;
    g.half_length = half_length;
    g.link = i;
    s.geoms.push_back(g);
  }
  const double r = 0.3, end = 19 * pitch + half_length;  // the last segment's end point, x
  const double dz = r - radius, reach = r + radius - kPenetration;
  Geom ball{Kind::sphere, {end + std::sqrt(reach * reach - dz * dz), 0, r - kPenetration}};
  ball.radius = r;
  s.geoms.push_back(ball);
  return s;
}

std::vector<Scene> scenes() {
  return {box_on_plane("box on plane, level", 0, Vector3d::UnitX()),
          box_on_plane("box on plane, tilted 0.01 rad about x", 0.01, Vector3d::UnitX()),
          box_on_plane("box on plane, tilted 0.1 rad about (1,1,0)", 0.1, Vector3d(1, 1, 0)),
          stack(),
          pyramid("pyramid of 55 boxes, 10 layers", 10), chain()};
}

// Pose set 0 is exact; the others move every shape but the plane by up to kJitter per coordinate
// and turn it by a rotation vector of up to kJitter per component. Fixed seed: every library sees
// the same poses.
std::vector<std::vector<Pose>> pose_sets(const Scene& s) {
  std::mt19937_64 rng(20240607);
  std::uniform_real_distribution<double> u(-kJitter, kJitter);
  std::vector<std::vector<Pose>> sets(kPoseSets);  // [kPoseSets][geoms]
  for (int k = 0; k < kPoseSets; ++k)
    for (const Geom& g : s.geoms) {
      Pose p{g.position, g.orientation};
      if (k > 0 && g.kind != Kind::plane) {
        const Vector3d w(u(rng), u(rng), u(rng));
        p.position += Vector3d(u(rng), u(rng), u(rng));
        p.orientation = (Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized())) * g.orientation).normalized();
      }
      sets[k].push_back(p);
    }
  return sets;
}

// ---- The analytic reference on the exact poses ---------------------------------------------------

struct Expected {
  int a, b;
  Vector3d normal;  // from a into b
  double depth;
  std::string pair_class;
};

// Every pair that overlaps or touches (depth >= 0) on the exact poses. Box pairs are axis aligned
// in these scenes, so their normal is the axis of least overlap.
std::vector<Expected> reference(const Scene& s) {
  std::vector<Expected> out;
  const int n = static_cast<int>(s.geoms.size());
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (s.excluded(a, b)) continue;
      const Geom &ga = s.geoms[a], &gb = s.geoms[b];
      if (ga.kind == Kind::plane) {
        const double depth = -lowest_z(gb, {gb.position, gb.orientation});
        if (depth >= -1e-12) out.push_back({a, b, Vector3d::UnitZ(), depth, std::string(kind_name(gb.kind)) + "-plane"});
      } else if (ga.kind == Kind::box && gb.kind == Kind::box) {
        const Vector3d d = gb.position - ga.position;
        const Vector3d overlap = ga.half_extents + gb.half_extents - d.cwiseAbs();
        int axis;
        const double depth = overlap.minCoeff(&axis);
        if (depth < -1e-12) continue;
        const Vector3d normal = Vector3d::Unit(axis) * (d[axis] >= 0 ? 1 : -1);
        out.push_back({a, b, normal, depth, axis == 2 ? "box-box stacked" : "box-box side (gap 0)"});
      } else if (ga.kind == Kind::capsule && gb.kind == Kind::sphere) {
        const Vector3d axis = ga.orientation * Vector3d::UnitZ();
        const double t = std::clamp((gb.position - ga.position).dot(axis), -ga.half_length, ga.half_length);
        const Vector3d d = gb.position - (ga.position + t * axis);
        const double depth = ga.radius + gb.radius - d.norm();
        if (depth >= -1e-12) out.push_back({a, b, d.normalized(), depth, "sphere-capsule"});
      }
      // capsule-capsule: only neighbours are near, and they are excluded
    }
  return out;
}

// ---- The detectors ------------------------------------------------------------------------------

class Detector {
 public:
  virtual ~Detector() = default;
  // One pass: place every shape at `poses`, then broad and narrow phase; contacts replaced.
  // `native`, when given, receives the library's own contact data of this pass, one per line.
  virtual void detect(const std::vector<Pose>& poses, std::vector<Contact>& contacts, std::string* native) = 0;
};

// printf into a string (GCC 12 warns falsely on "literal" + std::string: DEVELOPERS.md).
template <class... Args>
std::string format(const char* f, Args... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, f, args...);
  return buf;
}
std::string vec(const Vector3d& v) { return format("(%.6f, %.6f, %.6f)", v.x(), v.y(), v.z()); }

#ifdef LDLPGS_HAVE_ODE
// ODE: every shape a geom without a body in one space, placed by dGeomSetPosition and
// dGeomSetQuaternion; dSpaceCollide reports AABB-overlapping pairs, dCollide makes up to
// kMaxPointsPerPair points. ODE's convention (dContactGeom): for dCollide(g1, g2) the normal
// points into g1, i.e. from g2 to g1, and moving g1 by depth along it separates them; depth > 0.
class OdeDetector final : public Detector {
 public:
  enum class Space { hash, sweep_and_prune };
  OdeDetector(const Scene& scene, Space space) : scene_(scene) {
    space_ = space == Space::hash ? dHashSpaceCreate(nullptr) : dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    for (size_t i = 0; i < scene.geoms.size(); ++i) {
      const Geom& g = scene.geoms[i];
      dGeomID id = nullptr;
      switch (g.kind) {
        case Kind::plane: id = dCreatePlane(space_, 0, 0, 1, 0); break;
        case Kind::box: id = dCreateBox(space_, 2 * g.half_extents.x(), 2 * g.half_extents.y(), 2 * g.half_extents.z()); break;
        case Kind::sphere: id = dCreateSphere(space_, g.radius); break;
        case Kind::capsule: id = dCreateCapsule(space_, g.radius, 2 * g.half_length); break;  // along local z
      }
      dGeomSetData(id, reinterpret_cast<void*>(static_cast<intptr_t>(i)));
      geom_.push_back(id);
    }
  }
  ~OdeDetector() override { dSpaceDestroy(space_); }  // destroys its geoms (cleanup mode on)

  void detect(const std::vector<Pose>& poses, std::vector<Contact>& contacts, std::string* native) override {
    for (size_t i = 1; i < geom_.size(); ++i) {
      const Pose& p = poses[i];
      dGeomSetPosition(geom_[i], p.position.x(), p.position.y(), p.position.z());
      const dQuaternion q = {p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()};
      dGeomSetQuaternion(geom_[i], q);
    }
    contacts.clear();
    out_ = &contacts;
    native_ = native;
    dSpaceCollide(space_, this, &OdeDetector::near);
  }

 private:
  static int index(dGeomID g) { return static_cast<int>(reinterpret_cast<intptr_t>(dGeomGetData(g))); }
  static void near(void* data, dGeomID g1, dGeomID g2) {
    auto& self = *static_cast<OdeDetector*>(data);
    const int i1 = index(g1), i2 = index(g2);
    if (self.scene_.excluded(i1, i2)) return;
    dContactGeom c[kMaxPointsPerPair];
    const int n = dCollide(g1, g2, kMaxPointsPerPair, c, sizeof(dContactGeom));
    for (int k = 0; k < n; ++k) {
      const Vector3d pos(c[k].pos[0], c[k].pos[1], c[k].pos[2]), normal(c[k].normal[0], c[k].normal[1], c[k].normal[2]);
      self.out_->push_back(oriented(i2, i1, pos, normal, c[k].depth));  // into g1: from g2 into g1
      if (self.native_)
        *self.native_ += format("dCollide(g%d %s, g%d %s): pos %s normal %s depth %.6f\n", i1,
                                kind_name(self.scene_.geoms[i1].kind), i2, kind_name(self.scene_.geoms[i2].kind),
                                vec(pos).c_str(), vec(normal).c_str(), c[k].depth);
    }
  }

  const Scene& scene_;
  dSpaceID space_;
  std::vector<dGeomID> geom_;  // [geoms]
  std::vector<Contact>* out_ = nullptr;
  std::string* native_ = nullptr;
};
#endif

#ifdef LDLPGS_HAVE_BULLET
// Bullet: every shape a btCollisionObject (flags 0, so that box-box pairs are not filtered out as
// static-static) in a btCollisionWorld with btDbvtBroadphase; performDiscreteCollisionDetection
// updates the AABBs, the pairs and each pair's btPersistentManifold (up to 4 points, kept across
// passes and matched to the new ones by distance). Bullet's convention (btManifoldPoint):
// m_normalWorldOnB points from body B (getBody1) into body A (getBody0), getDistance() < 0 when
// they overlap, getPositionWorldOnA = getPositionWorldOnB + normal * distance.
class BulletDetector final : public Detector {
 public:
  BulletDetector(const Scene& scene, bool multipoint) : scene_(scene), filter_(scene) {
    // Multipoint: the convex-plane algorithm also collides a few rotated copies of the shape, so
    // that a box gets its 4 points in one pass rather than over several.
    if (multipoint) configuration_.setPlaneConvexMultipointIterations();
    world_.getPairCache()->setOverlapFilterCallback(&filter_);
    for (size_t i = 0; i < scene.geoms.size(); ++i) {
      const Geom& g = scene.geoms[i];
      switch (g.kind) {
        case Kind::plane: shape_.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0)); break;
        case Kind::box: shape_.push_back(std::make_unique<btBoxShape>(bt(g.half_extents))); break;
        case Kind::sphere: shape_.push_back(std::make_unique<btSphereShape>(g.radius)); break;
        case Kind::capsule: shape_.push_back(std::make_unique<btCapsuleShapeZ>(g.radius, 2 * g.half_length)); break;
      }
      object_.push_back(std::make_unique<btCollisionObject>());
      btCollisionObject& o = *object_.back();
      o.setCollisionShape(shape_.back().get());
      o.setUserIndex(static_cast<int>(i));
      o.setWorldTransform(transform({g.position, g.orientation}));
      if (g.kind != Kind::plane) o.setCollisionFlags(0);  // movable: collides with the others
      world_.addCollisionObject(&o);
    }
  }
  ~BulletDetector() override {
    for (auto& o : object_) world_.removeCollisionObject(o.get());
  }

  void detect(const std::vector<Pose>& poses, std::vector<Contact>& contacts, std::string* native) override {
    for (size_t i = 1; i < object_.size(); ++i) object_[i]->setWorldTransform(transform(poses[i]));
    world_.performDiscreteCollisionDetection();
    contacts.clear();
    for (int m = 0; m < dispatcher_.getNumManifolds(); ++m) {
      const btPersistentManifold& manifold = *dispatcher_.getManifoldByIndexInternal(m);
      const int a = manifold.getBody0()->getUserIndex(), b = manifold.getBody1()->getUserIndex();
      for (int k = 0; k < manifold.getNumContacts(); ++k) {
        const btManifoldPoint& p = manifold.getContactPoint(k);
        const Vector3d normal_on_b = eig(p.m_normalWorldOnB);
        const Vector3d on_a = eig(p.getPositionWorldOnA()), on_b = eig(p.getPositionWorldOnB());
        contacts.push_back(oriented(b, a, 0.5 * (on_a + on_b), normal_on_b, -p.getDistance(), p.getLifeTime()));
        if (native)
          *native += format("manifold(A %d %s, B %d %s): onA %s onB %s normalWorldOnB %s distance %.6f lifetime %d\n", a,
                            kind_name(scene_.geoms[a].kind), b, kind_name(scene_.geoms[b].kind), vec(on_a).c_str(),
                            vec(on_b).c_str(), vec(normal_on_b).c_str(), p.getDistance(), p.getLifeTime());
      }
    }
  }

 private:
  static btVector3 bt(const Vector3d& v) { return {v.x(), v.y(), v.z()}; }
  static Vector3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
  static btTransform transform(const Pose& p) {
    const Quaterniond& q = p.orientation;
    return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(p.position));
  }
  // Bullet's default group test, then our rule: neighbours in a chain never collide.
  struct Filter : btOverlapFilterCallback {
    explicit Filter(const Scene& s) : scene(s) {}
    bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
      if (!(p0->m_collisionFilterGroup & p1->m_collisionFilterMask) || !(p1->m_collisionFilterGroup & p0->m_collisionFilterMask))
        return false;
      return !scene.excluded(static_cast<btCollisionObject*>(p0->m_clientObject)->getUserIndex(),
                             static_cast<btCollisionObject*>(p1->m_clientObject)->getUserIndex());
    }
    const Scene& scene;
  };

  const Scene& scene_;
  Filter filter_;
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  btCollisionWorld world_{&dispatcher_, &broadphase_, &configuration_};
  std::vector<std::unique_ptr<btCollisionShape>> shape_;         // [geoms]
  std::vector<std::unique_ptr<btCollisionObject>> object_;       // [geoms]
};
#endif

#ifdef LDLPGS_HAVE_CCD
// libccd: narrow phase only, on support functions; one point per pair. It has no half space, so
// the plane is a box 100 m x 100 m x 2 m whose top face is z = 0 (MuJoCo treats planes
// analytically and gives ccd only convex pairs). Broad phase: AABBs swept along x. Tolerances as
// MuJoCo's defaults (ccd_tolerance 1e-6, ccd_iterations 50). libccd's convention
// (ccdMPRPenetration(obj1, obj2) and ccdGJKPenetration): dir points from obj1 into obj2, moving
// obj2 by depth along dir separates them; depth > 0; pos a point between the two surfaces.
class CcdDetector final : public Detector {
 public:
  enum class Algorithm { mpr, gjk_epa };
  CcdDetector(const Scene& scene, Algorithm algorithm) : scene_(scene), algorithm_(algorithm) {
    CCD_INIT(&ccd_);
    ccd_.support1 = ccd_.support2 = &CcdDetector::support;
    ccd_.center1 = ccd_.center2 = &CcdDetector::center;
    ccd_.max_iterations = 50;
    ccd_.mpr_tolerance = ccd_.epa_tolerance = 1e-6;
    for (const Geom& g : scene.geoms) {
      Shape s{g, g.position, g.orientation.toRotationMatrix()};
      if (g.kind == Kind::plane) {
        s.geom.kind = Kind::box;
        s.geom.half_extents = {50, 50, 1};
        s.position = {5, 0, -1};
      }
      shape_.push_back(s);
    }
    order_.resize(shape_.size());
  }

  void detect(const std::vector<Pose>& poses, std::vector<Contact>& contacts, std::string* native) override {
    for (size_t i = 0; i < shape_.size(); ++i) {
      Shape& s = shape_[i];
      if (i > 0) {
        s.position = poses[i].position;
        s.rotation = poses[i].orientation.toRotationMatrix();
      }
      Vector3d reach = Vector3d::Zero();
      switch (s.geom.kind) {
        case Kind::box: reach = s.rotation.cwiseAbs() * s.geom.half_extents; break;
        case Kind::sphere: reach.setConstant(s.geom.radius); break;
        case Kind::capsule: reach = s.rotation.col(2).cwiseAbs() * s.geom.half_length + Vector3d::Constant(s.geom.radius); break;
        case Kind::plane: break;
      }
      s.low = s.position - reach;
      s.high = s.position + reach;
      order_[i] = static_cast<int>(i);
    }
    std::sort(order_.begin(), order_.end(), [&](int a, int b) { return shape_[a].low.x() < shape_[b].low.x(); });
    contacts.clear();
    for (size_t i = 0; i < order_.size(); ++i) {
      const Shape& a = shape_[order_[i]];
      for (size_t j = i + 1; j < order_.size() && shape_[order_[j]].low.x() <= a.high.x(); ++j) {
        const Shape& b = shape_[order_[j]];
        if ((a.low.array() > b.high.array()).any() || (b.low.array() > a.high.array()).any()) continue;
        if (scene_.excluded(order_[i], order_[j])) continue;
        ccd_real_t depth;
        ccd_vec3_t dir, pos;
        const int hit = algorithm_ == Algorithm::mpr ? ccdMPRPenetration(&a, &b, &ccd_, &depth, &dir, &pos)
                                                     : ccdGJKPenetration(&a, &b, &ccd_, &depth, &dir, &pos);
        if (hit != 0) continue;
        const Vector3d d(dir.v[0], dir.v[1], dir.v[2]), p(pos.v[0], pos.v[1], pos.v[2]);
        contacts.push_back(oriented(order_[i], order_[j], p, d, depth));  // dir: from obj1 into obj2
        if (native)
          *native += format("penetration(obj1 %d %s, obj2 %d %s): pos %s dir %s depth %.6f\n", order_[i],
                            kind_name(scene_.geoms[order_[i]].kind), order_[j], kind_name(scene_.geoms[order_[j]].kind),
                            vec(p).c_str(), vec(d).c_str(), depth);
      }
    }
  }

 private:
  struct Shape {
    Geom geom;  // the plane as its box
    Vector3d position;
    Eigen::Matrix3d rotation;
    Vector3d low = Vector3d::Zero(), high = Vector3d::Zero();  // world AABB
  };
  // The farthest point of a shape along dir: the local support, rotated and moved.
  static void support(const void* object, const ccd_vec3_t* dir, ccd_vec3_t* out) {
    const Shape& s = *static_cast<const Shape*>(object);
    const Vector3d d = s.rotation.transpose() * Vector3d(dir->v[0], dir->v[1], dir->v[2]);
    const Vector3d unit = d.norm() > 0 ? Vector3d(d.normalized()) : Vector3d::UnitZ();
    Vector3d local = Vector3d::Zero();
    switch (s.geom.kind) {
      case Kind::box:
        for (int k = 0; k < 3; ++k) local[k] = d[k] >= 0 ? s.geom.half_extents[k] : -s.geom.half_extents[k];
        break;
      case Kind::sphere: local = s.geom.radius * unit; break;
      case Kind::capsule: local = Vector3d(0, 0, d.z() >= 0 ? s.geom.half_length : -s.geom.half_length) + s.geom.radius * unit; break;
      case Kind::plane: local.setZero(); break;
    }
    const Vector3d w = s.rotation * local + s.position;
    ccdVec3Set(out, w.x(), w.y(), w.z());
  }
  static void center(const void* object, ccd_vec3_t* out) {
    const Shape& s = *static_cast<const Shape*>(object);
    ccdVec3Set(out, s.position.x(), s.position.y(), s.position.z());
  }

  const Scene& scene_;
  Algorithm algorithm_;
  ccd_t ccd_;
  std::vector<Shape> shape_;  // [geoms]
  std::vector<int> order_;    // [geoms] sorted by AABB low x
};
#endif

struct Library {
  const char* name;
  std::unique_ptr<Detector> (*make)(const Scene&);
};

std::vector<Library> libraries() {
  std::vector<Library> out;
#ifdef LDLPGS_HAVE_ODE
  out.push_back({"ODE, dHashSpace", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<OdeDetector>(s, OdeDetector::Space::hash);
                 }});
  out.push_back({"ODE, dSweepAndPruneSpace", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<OdeDetector>(s, OdeDetector::Space::sweep_and_prune);
                 }});
#endif
#ifdef LDLPGS_HAVE_BULLET
  out.push_back({"Bullet, defaults", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<BulletDetector>(s, false);
                 }});
  out.push_back({"Bullet, plane multipoint", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<BulletDetector>(s, true);
                 }});
#endif
#ifdef LDLPGS_HAVE_CCD
  out.push_back({"libccd MPR", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<CcdDetector>(s, CcdDetector::Algorithm::mpr);
                 }});
  out.push_back({"libccd GJK+EPA", [](const Scene& s) -> std::unique_ptr<Detector> {
                   return std::make_unique<CcdDetector>(s, CcdDetector::Algorithm::gjk_epa);
                 }});
#endif
  return out;
}

// ---- Judging a pass ------------------------------------------------------------------------------

// Points per pair, by pair class: "4" when every pair has the same count, else "min-max (mean)";
// pairs of the reference that got no point count as 0.
std::string points_per_pair(const std::vector<Expected>& ref, const std::vector<Contact>& contacts) {
  std::map<std::string, std::vector<int>> counts;
  for (const Expected& e : ref) {
    int n = 0;
    for (const Contact& c : contacts) n += c.a == e.a && c.b == e.b;
    counts[e.pair_class].push_back(n);
  }
  std::string out;
  for (const auto& [name, v] : counts) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    double mean = 0;
    for (int n : v) mean += n;
    mean /= static_cast<double>(v.size());
    if (!out.empty()) out += "; ";
    out += name;
    out += " ";
    out += (*lo == *hi ? std::to_string(*lo) : format("%d-%d (%.2f)", *lo, *hi, mean));
  }
  return out;
}

struct Accuracy {
  double depth_error = 0;    // |deepest point's depth - reference| (m), worst pair that overlaps
  double normal_error = 0;   // angle between a point's normal and the reference (degrees), worst point
  int missing = 0, extra = 0;  // overlapping reference pairs without a point; points on pairs not in the reference
  int not_finite = 0;          // points whose normal or depth is NaN or infinite
};

Accuracy accuracy(const std::vector<Expected>& ref, const std::vector<Contact>& contacts) {
  Accuracy acc;
  for (const Expected& e : ref) {
    double deepest = -1e300;
    for (const Contact& c : contacts) {
      if (c.a != e.a || c.b != e.b) continue;
      if (!c.normal.allFinite() || !std::isfinite(c.depth)) {
        ++acc.not_finite;
        continue;
      }
      deepest = std::max(deepest, c.depth);
      const double cosine = std::clamp(c.normal.normalized().dot(e.normal), -1.0, 1.0);
      if (e.depth > 1e-9) acc.normal_error = std::max(acc.normal_error, std::acos(cosine) * 180 / M_PI);
    }
    if (e.depth <= 1e-9) continue;  // side neighbours: touching, not overlapping
    if (deepest == -1e300) ++acc.missing;
    else acc.depth_error = std::max(acc.depth_error, std::abs(deepest - e.depth));
  }
  for (const Contact& c : contacts) {
    const bool known = std::any_of(ref.begin(), ref.end(), [&](const Expected& e) { return e.a == c.a && e.b == c.b; });
    acc.extra += !known;
  }
  return acc;
}

}  // namespace

int main() {
  std::printf("# Collision detection: ODE, Bullet, libccd\n\n");
#ifdef LDLPGS_HAVE_ODE
  dInitODE2(0);
  std::printf("- ODE %s: dReal %zu bytes, `dCheckConfiguration(\"ODE_double_precision\")` = %d; configuration: %s\n",
              "0.16", sizeof(dReal), dCheckConfiguration("ODE_double_precision"), dGetConfiguration());
#endif
#ifdef LDLPGS_HAVE_BULLET
  std::printf("- Bullet %d: btScalar %zu bytes\n", btGetVersion(), sizeof(btScalar));
#endif
#ifdef LDLPGS_HAVE_CCD
  std::printf("- libccd: ccd_real_t %zu bytes\n", sizeof(ccd_real_t));
#endif
  std::printf("\nTime: median over 301 batches of 20 passes of one pass (us): set the poses of every shape, broad\n"
              "and narrow phase over the scene. Points per pair by pair class: on pass 1 (exact poses, a new\n"
              "world) and on pass 11 (after 10 passes at poses perturbed by up to 1e-3 m and 1e-3 rad). Depth and\n"
              "normal errors against the analytic reference on pass 1: the deepest point of each overlapping pair\n"
              "(all overlap 1 mm), the worst point's normal. Missing: overlapping pairs without a point; extra:\n"
              "points on pairs that neither overlap nor touch; NaN: points with a NaN normal or depth (not in the\n"
              "errors). Separated: points on pass 11 with depth < 0 (the\n"
              "jitter separates some pairs by up to 1 mm). Kept: Bullet's points on pass 11 matched to a point of\n"
              "an earlier pass (lifetime >= 2).\n\n");

  std::vector<Contact> contacts;
  contacts.reserve(1024);
  for (const Scene& scene : scenes()) {
    const auto sets = pose_sets(scene);
    const std::vector<Expected> ref = reference(scene);
    std::printf("## %s (%zu shapes, %zu touching pairs)\n\n", scene.name.c_str(), scene.geoms.size(), ref.size());
    std::printf("| library | us/pass | points per pair, pass 1 | points per pair, pass 11 | separated/all, pass 11 | kept | "
                "depth error (m) | normal error (deg) | missing / extra / NaN |\n");
    std::printf("|---|---:|---|---|---:|---:|---:|---:|---|\n");
    std::string natives;
    for (const Library& lib : libraries()) {
      std::unique_ptr<Detector> detector = lib.make(scene);
      std::string native;
      detector->detect(sets[0], contacts, scene.geoms.size() <= 3 ? &native : nullptr);
      if (!native.empty()) {
        natives += "\n";
        natives += lib.name;
        natives += ", pass 1:\n```\n";
        natives += native;
        natives += "```\n";
      }
      const std::string first = points_per_pair(ref, contacts);
      const Accuracy acc = accuracy(ref, contacts);
      for (int k = 1; k <= 10; ++k) detector->detect(sets[k], contacts, nullptr);
      const std::string tenth = points_per_pair(ref, contacts);
      // Bullet counts a new point's lifetime 1 on the pass that adds it, so 2 or more: matched to
      // a point of an earlier pass. Separated: points with depth < 0 (Bullet keeps them while
      // within its contact breaking threshold).
      int kept = 0, separated = 0;
      const size_t tenth_points = contacts.size();
      for (const Contact& c : contacts) {
        kept += c.age >= 2;
        separated += c.depth < 0;
      }

      constexpr int kBatches = 301, kBatch = 20;
      std::vector<double> per_pass;  // [kBatches] us
      int set = 11;
      for (int b = 0; b < kBatches; ++b) {
        const auto start = std::chrono::steady_clock::now();
        for (int k = 0; k < kBatch; ++k, set = set % (kPoseSets - 1) + 1) detector->detect(sets[set], contacts, nullptr);
        per_pass.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / kBatch);
      }
      const bool bullet = std::string_view(lib.name).starts_with("Bullet");
      std::printf("| %s | %.2f | %s | %s | %d/%zu | %s | %.2e | %.3f | %d / %d / %d |\n", lib.name, ldlpgs::median(per_pass),
                  first.c_str(), tenth.c_str(), separated, tenth_points, bullet ? format("%d", kept).c_str() : "-",
                  acc.depth_error, acc.normal_error, acc.missing, acc.extra, acc.not_finite);
    }
    if (!natives.empty()) std::printf("\nEach library's own contact data on pass 1 (geometry 0 is the plane):\n%s", natives.c_str());
    std::printf("\n");
  }
#ifdef LDLPGS_HAVE_ODE
  dCloseODE();
#endif
}
