// Collision detection with ODE: one geom per shape, placed without an ODE body at its body's pose
// before each pass; a sweep of ours finds the candidate pairs, dCollide their points. ODE has no
// ellipsoid: pairs with one, and pairs of shapes that cannot be grown by a margin (two convex
// hulls, a hull on a heightfield), are found by libccd's MPR on support functions instead.
#include "ldlpgs/physics/collision.h"

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <mutex>

#include <ccd/ccd.h>
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
constexpr int kMaxRawPoints = 32;   // what a pair may yield before keep_four

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
    case ShapeType::cylinder: return s.position.norm() + std::hypot(s.radius, s.half_length);
    case ShapeType::ellipsoid: return s.position.norm() + s.half_extents.maxCoeff();
    case ShapeType::convex: {
      double farthest = 0;
      for (const Eigen::Vector3d& v : s.hull->vertices) farthest = std::max(farthest, v.norm());
      return s.position.norm() + farthest;
    }
    case ShapeType::heightfield: return 0;  // static
  }
  return 0;
}

// ODE grows these by a margin exactly as we place them (sizes, a plane's offset); a convex hull
// or a heightfield keeps its size, and the other shape of a pair grows by both margins instead.
bool growable(ShapeType type) { return type != ShapeType::convex && type != ShapeType::heightfield; }

// A convex hull in ODE's arrays, which dCreateConvex points to (it copies nothing).
struct OdeConvex {
  std::vector<double> planes;      // (n, d) per face (size 4 faces)
  std::vector<double> points;      // (size 3 vertices)
  std::vector<unsigned> polygons;  // 3, i, j, k per face (size 4 faces)
};

}  // namespace

struct CollisionWorld::Geometry {
  std::vector<dGeomID> geoms;       // (size shapes; in no ODE space)
  std::vector<double> inflation;    // what each geom is grown by as placed now (m; size shapes)
  std::vector<std::unique_ptr<OdeConvex>> convex_data;  // the convex geoms' arrays
  std::vector<dHeightfieldDataID> field_data;           // the heightfield geoms' grids
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
    for (dHeightfieldDataID data : field_data) dGeomHeightfieldDataDestroy(data);
  }
  dGeomID make_geom(const Shape& s);
  void grow(int geom, double inflation);
  void sweep_and_prune();
  bool excluded_pair(int a, int b) const {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    return std::binary_search(excluded.begin(), excluded.end(), key);
  }
};

namespace {

// ODE's heightfield lies in its x-z plane with y up; ours (MuJoCo's) in x-y with z up. This turns
// ODE's axes onto ours: its x onto our x (the grid's columns), its y onto our z, its z onto our
// -y (the rows, last first), so that ODE splits each cell along the same diagonal as MuJoCo,
// from sample (r, c) to (r + 1, c + 1).
const Eigen::Quaterniond& ode_field_to_shape() {
  static const Eigen::Quaterniond q(
      (Eigen::Matrix3d() << 1, 0, 0, 0, 0, -1, 0, 1, 0).finished());  // columns: images of ODE's x, y, z
  return q;
}

// The geom at its body's current pose, world pose = body pose * shape pose; a plane as
// n . x = n . p in the world (ODE's planes are not placeable). Sizes are grow()'s.
void place(dGeomID g, const Shape& s, const RigidBody& body) {
  if (s.type == ShapeType::plane) {
    const Eigen::Vector3d n = (body.orientation * s.normal).normalized();
    dGeomPlaneSetParams(g, n.x(), n.y(), n.z(), n.dot(body.to_world(s.position)));
    return;
  }
  const Eigen::Vector3d p = body.to_world(s.position);
  Eigen::Quaterniond q = body.orientation * s.orientation;
  if (s.type == ShapeType::heightfield) q = q * ode_field_to_shape();
  dGeomSetPosition(g, p.x(), p.y(), p.z());
  const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(g, dq);
}

// A shape's frame in the world (rotation, centre), for clamping and support functions.
Eigen::Matrix3d world_rotation(const Shape& s, const RigidBody& body) {
  return (body.orientation * s.orientation).toRotationMatrix();
}

// A box shape's frame in the world (rotation, centre) and half extents, for near_callback.
// A grown box's or cylinder's edges stand out by its margin sideways too: a point of its pair is
// brought back within the real shape, across the contact plane only (the part of what the clamp
// removes that lies along the normal n is kept). Spheres and capsules grow along their own
// normals and need none.
struct GrownShape {
  ShapeType type = ShapeType::box;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d centre, half_extents;  // a cylinder: (radius, radius, half length)
  Eigen::Vector3d clamp(const Eigen::Vector3d& point, const Eigen::Vector3d& n) const {
    const Eigen::Vector3d local = rotation.transpose() * (point - centre), n_local = rotation.transpose() * n;
    Eigen::Vector3d within = local.cwiseMax(-half_extents).cwiseMin(half_extents);
    if (type == ShapeType::cylinder) {
      within.head<2>() = local.head<2>();
      const double r = within.head<2>().norm();
      if (r > half_extents.x()) within.head<2>() *= half_extents.x() / r;
    }
    return centre + rotation * (within + (local - within).dot(n_local) * n_local);
  }
};

// A shape at its world pose grown by `inflation` (its Minkowski sum with that ball), or a
// heightfield's prism (a triangle of its surface down to its base), for libccd's support
// functions.
struct Posed {
  const Shape* shape = nullptr;  // none: the prism
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double inflation = 0;
  std::array<Eigen::Vector3d, 6> prism;  // world
};

// The farthest point of a shape (its own frame, not grown) along d.
Eigen::Vector3d local_support(const Shape& s, const Eigen::Vector3d& d) {
  const auto sign = [](double x) { return x < 0 ? -1.0 : 1.0; };
  switch (s.type) {
    case ShapeType::sphere: return s.radius * d.normalized();
    case ShapeType::capsule: return Eigen::Vector3d(0, 0, sign(d.z()) * s.half_length) + s.radius * d.normalized();
    case ShapeType::box: return Eigen::Vector3d(sign(d.x()), sign(d.y()), sign(d.z())).cwiseProduct(s.half_extents);
    case ShapeType::cylinder: {
      const double r = d.head<2>().norm();
      Eigen::Vector3d p(0, 0, sign(d.z()) * s.half_length);
      if (r > 0) p.head<2>() = s.radius / r * d.head<2>();
      return p;
    }
    case ShapeType::ellipsoid: {
      // maximizes d . x on x^T E^-2 x = 1 (E = diag(semi-axes)): x = E^2 d / |E d|
      const Eigen::Vector3d ed = s.half_extents.cwiseProduct(d);
      const double norm = ed.norm();
      return norm > 0 ? Eigen::Vector3d(s.half_extents.cwiseProduct(ed) / norm) : Eigen::Vector3d::Zero();
    }
    case ShapeType::convex: {
      const std::vector<Eigen::Vector3d>& v = s.hull->vertices;
      size_t best = 0;
      for (size_t i = 1; i < v.size(); ++i)
        if (v[i].dot(d) > v[best].dot(d)) best = i;
      return v[best];
    }
    case ShapeType::plane:
    case ShapeType::heightfield: break;  // unbounded or not convex: never a support path's
  }
  return Eigen::Vector3d::Zero();
}

void ccd_support(const void* object, const ccd_vec3_t* direction, ccd_vec3_t* out) {
  const Posed& o = *static_cast<const Posed*>(object);
  const Eigen::Vector3d d(direction->v[0], direction->v[1], direction->v[2]);
  Eigen::Vector3d p;
  if (o.shape) {
    p = o.centre + o.rotation * local_support(*o.shape, o.rotation.transpose() * d);
    const double norm = d.norm();
    if (norm > 0) p += o.inflation / norm * d;
  } else {
    p = o.prism[0];
    for (const Eigen::Vector3d& v : o.prism)
      if (v.dot(d) > p.dot(d)) p = v;
  }
  for (int k = 0; k < 3; ++k) out->v[k] = p[k];
}

void ccd_centre(const void* object, ccd_vec3_t* out) {
  const Posed& o = *static_cast<const Posed*>(object);
  Eigen::Vector3d c = o.centre;
  if (!o.shape) {
    c.setZero();
    for (const Eigen::Vector3d& v : o.prism) c += v / 6;
  }
  for (int k = 0; k < 3; ++k) out->v[k] = c[k];
}

// MPR's one point for two posed convex shapes, in dCollide's terms (normal along which moving o1
// separates them, depth of the grown shapes' overlap); false if they do not overlap.
bool mpr_contact(const Posed& o1, const Posed& o2, dContactGeom* c) {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccd_support;
  ccd.support2 = ccd_support;
  ccd.center1 = ccd_centre;
  ccd.center2 = ccd_centre;
  ccd.max_iterations = 100;
  ccd.mpr_tolerance = 1e-12;
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  if (ccdMPRPenetration(&o1, &o2, &ccd, &depth, &dir, &pos) != 0) return false;
  // libccd's dir is the way o2 moves out of o1
  for (int k = 0; k < 3; ++k) {
    c->normal[k] = -dir.v[k];
    c->pos[k] = pos.v[k];
  }
  c->depth = depth;
  return std::isfinite(depth) && depth >= 0;
}

// The point of a grown convex shape deepest below a plane n . x = d (world; the plane already
// grown), in dCollide's terms for o1 = the shape when `shape_first`.
int plane_contact(const Posed& o, const Eigen::Vector3d& n, double d, bool shape_first, dContactGeom* c) {
  ccd_vec3_t dir = {{-n.x(), -n.y(), -n.z()}}, lowest;
  ccd_support(&o, &dir, &lowest);
  const Eigen::Vector3d p(lowest.v[0], lowest.v[1], lowest.v[2]);
  const double depth = d - n.dot(p);
  if (!(depth >= 0)) return 0;
  const Eigen::Vector3d normal = shape_first ? n : Eigen::Vector3d(-n);
  for (int k = 0; k < 3; ++k) {
    c->pos[k] = p[k] + 0.5 * depth * n[k];
    c->normal[k] = normal[k];
  }
  c->depth = depth;
  return 1;
}

// A convex shape against the prisms of a heightfield's cells under it (MuJoCo's way,
// mjc_ConvexHField: each cell's two triangles, split along the diagonal from (r, c) to
// (r + 1, c + 1), down to the base), up to `max_points`, in dCollide's terms for o1 = the shape
// when `shape_first`.
int field_contacts(const Posed& o, const Shape& field_shape, const RigidBody& field_body, double field_inflation,
                   bool shape_first, dContactGeom* out, int max_points) {
  const HeightField& f = *field_shape.field;
  const Eigen::Matrix3d rotation = world_rotation(field_shape, field_body);
  const Eigen::Vector3d centre = field_body.to_world(field_shape.position);
  // the shape's extent in the field's frame, by its support along the field's axes
  Eigen::Vector3d low, high;
  for (int k = 0; k < 3; ++k)
    for (double sign : {-1.0, 1.0}) {
      const Eigen::Vector3d axis = sign * rotation.col(k);
      ccd_vec3_t dir = {{axis.x(), axis.y(), axis.z()}}, far;
      ccd_support(&o, &dir, &far);
      const double x = rotation.col(k).dot(Eigen::Vector3d(far.v[0], far.v[1], far.v[2]) - centre);
      (sign < 0 ? low : high)[k] = x;
    }
  const double dx = 2 * f.half_x / (f.cols - 1), dy = 2 * f.half_y / (f.rows - 1);
  const auto cell = [](double x, double step, int count) {
    return std::clamp(static_cast<int>(std::floor(x / step)), 0, count - 2);
  };
  if (high.x() < -f.half_x || low.x() > f.half_x || high.y() < -f.half_y || low.y() > f.half_y || high.z() < -f.base) return 0;
  const int c0 = cell(low.x() + f.half_x, dx, f.cols), c1 = cell(high.x() + f.half_x, dx, f.cols);
  const int r0 = cell(low.y() + f.half_y, dy, f.rows), r1 = cell(high.y() + f.half_y, dy, f.rows);
  // the prisms grow by the field's margin upwards only: the shape carries it instead
  Posed grown = o;
  grown.inflation += field_inflation;
  const auto vertex = [&](int r, int c, bool top) {
    const Eigen::Vector3d local(-f.half_x + c * dx, -f.half_y + r * dy, top ? f.heights[r * f.cols + c] : -f.base);
    return Eigen::Vector3d(centre + rotation * local);
  };
  int n = 0;
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      for (int t = 0; t < 2 && n < max_points; ++t) {
        const int corners[2][3][2] = {{{r, c}, {r + 1, c}, {r + 1, c + 1}}, {{r, c}, {r + 1, c + 1}, {r, c + 1}}};
        Posed prism;
        for (int k = 0; k < 3; ++k) {
          prism.prism[k] = vertex(corners[t][k][0], corners[t][k][1], true);
          prism.prism[k + 3] = vertex(corners[t][k][0], corners[t][k][1], false);
        }
        if (shape_first ? mpr_contact(grown, prism, out + n) : mpr_contact(prism, grown, out + n)) ++n;
      }
  return n;
}

// A box or a convex hull at its world pose, for polytope_points: its vertices and whether a
// point lies within its sides.
struct Polytope {
  const Shape* shape = nullptr;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d centre;
  int vertices() const { return shape->type == ShapeType::box ? 8 : static_cast<int>(shape->hull->vertices.size()); }
  Eigen::Vector3d vertex(int i) const {
    const Eigen::Vector3d& h = shape->half_extents;
    const Eigen::Vector3d local = shape->type == ShapeType::box
                                      ? Eigen::Vector3d(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z())
                                      : shape->hull->vertices[i];
    return centre + rotation * local;
  }
  // q within the faces that do not face along u (the contact normal: q lies on the face that
  // does), to `tolerance`
  bool within_sides(const Eigen::Vector3d& q, const Eigen::Vector3d& u, double tolerance) const {
    const Eigen::Vector3d local = rotation.transpose() * (q - centre), u_local = rotation.transpose() * u;
    const auto inside = [&](const Eigen::Vector3d& n, double d) { return std::abs(n.dot(u_local)) >= 0.99 || n.dot(local) <= d + tolerance; };
    if (shape->type == ShapeType::box) {
      for (int k = 0; k < 3; ++k)
        for (double sign : {-1.0, 1.0})
          if (!inside(sign * Eigen::Vector3d::Unit(k), shape->half_extents[k])) return false;
      return true;
    }
    for (const Eigen::Vector4d& p : shape->hull->planes)
      if (!inside(p.head<3>(), p[3])) return false;
    return true;
  }
};

// The points of two polytopes (boxes or hulls; MPR and ODE's hull colliders give one) about the
// normal u of their one point (dCollide's: moving the first along u separates them): each vertex
// of one within `reach` of the other's extreme plane across u whose foot on that plane lies
// within the other's sides, its depth along u, midway between the two surfaces, as grown shapes'
// points (depth + reach, shifted as near_callback expects, `grown1` and `grown2` each one's
// share). A face on a face gets the corners of the smaller that lie on the larger, an edge its
// two ends; a corner one point.
int polytope_points(const Polytope& p1, const Polytope& p2, const Eigen::Vector3d& u, double grown1, double grown2,
                    dContactGeom* out, int max_points) {
  double low1 = std::numeric_limits<double>::infinity(), high2 = -low1, size = 0;  // p1's extreme towards p2, and p2's
  for (int i = 0; i < p1.vertices(); ++i) {
    low1 = std::min(low1, u.dot(p1.vertex(i)));
    size = std::max(size, (p1.vertex(i) - p1.centre).norm());
  }
  for (int i = 0; i < p2.vertices(); ++i) {
    high2 = std::max(high2, u.dot(p2.vertex(i)));
    size = std::max(size, (p2.vertex(i) - p2.centre).norm());
  }
  const double reach = grown1 + grown2, tolerance = 1e-9 * size;
  const Eigen::Vector3d shift = -0.5 * (grown1 - grown2) * u;  // undone by near_callback
  int n = 0;
  const auto add = [&](double depth, const Eigen::Vector3d& middle) {
    if (n == max_points) return;  // (a hull's face of more vertices: the first of them)
    dContactGeom& c = out[n++];
    for (int k = 0; k < 3; ++k) {
      c.pos[k] = middle[k] + shift[k];
      c.normal[k] = u[k];
    }
    c.depth = depth + reach;
  };
  for (int i = 0; i < p1.vertices(); ++i) {
    const Eigen::Vector3d v = p1.vertex(i);
    const double depth = high2 - u.dot(v);
    if (depth >= -reach && p2.within_sides(v + depth * u, u, tolerance)) add(depth, v + 0.5 * depth * u);
  }
  for (int i = 0; i < p2.vertices(); ++i) {
    const Eigen::Vector3d v = p2.vertex(i);
    const double depth = u.dot(v) - low1;
    if (depth >= -reach && p1.within_sides(v - depth * u, u, tolerance)) add(depth, v - 0.5 * depth * u);
  }
  return n;
}

// Up to 4 of n points of one pair that span its contact patch: the deepest, the farthest from
// it, the one making the largest triangle with those, and the one farthest outside that
// triangle (Bullet's manifold reduction, as areas in the plane of the deepest point's normal).
int keep_four(dContactGeom* points, int n) {
  if (n <= kMaxPointsPerPair) return n;
  const auto at = [&](int i) { return Eigen::Vector3d(points[i].pos[0], points[i].pos[1], points[i].pos[2]); };
  int chosen[4] = {0, -1, -1, -1};
  for (int i = 1; i < n; ++i)
    if (points[i].depth > points[chosen[0]].depth) chosen[0] = i;
  const Eigen::Vector3d normal(points[chosen[0]].normal[0], points[chosen[0]].normal[1], points[chosen[0]].normal[2]);
  const auto area = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
    return normal.dot((q - p).cross(r - p));  // signed: > 0 counter-clockwise about the normal
  };
  const auto best = [&](auto score) {
    int k = -1;
    double top = -1;
    for (int i = 0; i < n; ++i) {
      if (i == chosen[0] || i == chosen[1] || i == chosen[2]) continue;
      const double x = score(at(i));
      if (x > top) {
        top = x;
        k = i;
      }
    }
    return k;
  };
  const Eigen::Vector3d p0 = at(chosen[0]);
  chosen[1] = best([&](const Eigen::Vector3d& q) { return (q - p0 - (q - p0).dot(normal) * normal).squaredNorm(); });
  const Eigen::Vector3d p1 = at(chosen[1]);
  chosen[2] = best([&](const Eigen::Vector3d& q) { return std::abs(area(p0, p1, q)); });
  Eigen::Vector3d p2 = at(chosen[2]);
  const double turn = area(p0, p1, p2) < 0 ? -1 : 1;  // the triangle's orientation
  chosen[3] = best([&](const Eigen::Vector3d& q) {
    return std::max({-turn * area(p0, p1, q), -turn * area(p1, p2, q), -turn * area(p2, p0, q)});
  });
  dContactGeom kept[4];
  int k = 0;
  for (int i : chosen)
    if (i >= 0) kept[k++] = points[i];
  std::copy(kept, kept + k, points);
  return k;
}

}  // namespace

dGeomID CollisionWorld::Geometry::make_geom(const Shape& s) {
  switch (s.type) {
    case ShapeType::plane: return dCreatePlane(nullptr, 0, 0, 1, 0);  // parameters set by place()
    case ShapeType::sphere: return dCreateSphere(nullptr, s.radius);
    case ShapeType::capsule: return dCreateCapsule(nullptr, s.radius, 2 * s.half_length);  // ODE: the segment's length
    case ShapeType::box:
    case ShapeType::ellipsoid:  // (its bounding box: the broad phase's only use of it)
      return dCreateBox(nullptr, 2 * s.half_extents.x(), 2 * s.half_extents.y(), 2 * s.half_extents.z());
    case ShapeType::cylinder: return dCreateCylinder(nullptr, s.radius, 2 * s.half_length);  // ODE: the whole length
    case ShapeType::convex: {
      auto data = std::make_unique<OdeConvex>();
      for (size_t f = 0; f < s.hull->faces.size(); ++f) {
        for (int k = 0; k < 4; ++k) data->planes.push_back(s.hull->planes[f][k]);
        data->polygons.push_back(3);
        for (int v : s.hull->faces[f]) data->polygons.push_back(static_cast<unsigned>(v));
      }
      for (const Eigen::Vector3d& v : s.hull->vertices) data->points.insert(data->points.end(), v.data(), v.data() + 3);
      const dGeomID g = dCreateConvex(nullptr, data->planes.data(), static_cast<unsigned>(s.hull->faces.size()),
                                      data->points.data(), static_cast<unsigned>(s.hull->vertices.size()),
                                      data->polygons.data());
      convex_data.push_back(std::move(data));
      return g;
    }
    case ShapeType::heightfield: {
      // ODE's grid: samples along its x (our columns) then its z (our rows, last first):
      // heights[x + z cols], copied by ODE
      const HeightField& f = *s.field;
      std::vector<double> heights(f.heights.size());
      for (int r = 0; r < f.rows; ++r)
        for (int c = 0; c < f.cols; ++c) heights[c + (f.rows - 1 - r) * f.cols] = f.heights[r * f.cols + c];
      const double lowest = *std::min_element(heights.begin(), heights.end());
      const dHeightfieldDataID data = dGeomHeightfieldDataCreate();
      dGeomHeightfieldDataBuildDouble(data, heights.data(), 1, 2 * f.half_x, 2 * f.half_y, f.cols, f.rows, 1, 0,
                                      std::max(lowest + f.base, 1e-9), 0);
      field_data.push_back(data);
      return dCreateHeightfield(nullptr, data, 1);
    }
  }
  return nullptr;
}

// Grows geom i by `by` (m) from its shape's size: a plane's offset moves out, a box's and an
// ellipsoid's half extents, a sphere's, capsule's and cylinder's radius (and a cylinder's half
// length) grow. Convex hulls and heightfields are never grown.
void CollisionWorld::Geometry::grow(int i, double by) {
  const dGeomID g = geoms[i];
  const Shape& s = mechanism->bodies[owners[i].body].shapes[owners[i].shape];
  switch (s.type) {
    case ShapeType::plane: {
      dVector4 p;
      dGeomPlaneGetParams(g, p);
      dGeomPlaneSetParams(g, p[0], p[1], p[2], p[3] - inflation[i] + by);
      break;
    }
    case ShapeType::sphere: dGeomSphereSetRadius(g, s.radius + by); break;
    case ShapeType::capsule: dGeomCapsuleSetParams(g, s.radius + by, 2 * s.half_length); break;
    case ShapeType::box:
    case ShapeType::ellipsoid: {
      const Eigen::Vector3d l = 2 * (s.half_extents.array() + by).matrix();
      dGeomBoxSetLengths(g, l.x(), l.y(), l.z());
      break;
    }
    case ShapeType::cylinder: dGeomCylinderSetParams(g, s.radius + by, 2 * (s.half_length + by)); break;
    case ShapeType::convex:
    case ShapeType::heightfield: return;  // (inflation stays 0)
  }
  inflation[i] = by;
}

namespace {

// The pairs ODE does not collide as we need: an ellipsoid (ODE has none), or two shapes that
// cannot grow (so that a margin would be lost): by support functions.
bool by_support(const Shape& a, const Shape& b) {
  return a.type == ShapeType::ellipsoid || b.type == ShapeType::ellipsoid || (!growable(a.type) && !growable(b.type));
}

// A support path's points for geoms i1 and i2 (dCollide's terms), their grown sizes being each
// body's margin; *applied1, *applied2 say what each was grown by.
int support_contacts(const CollisionWorld::Geometry& g, int i1, int i2, dContactGeom* out, int max_points,
                     double* applied1, double* applied2) {
  const Mechanism& m = *g.mechanism;
  const RigidBody &b1 = m.bodies[g.owners[i1].body], &b2 = m.bodies[g.owners[i2].body];
  const Shape &s1 = b1.shapes[g.owners[i1].shape], &s2 = b2.shapes[g.owners[i2].shape];
  const auto posed = [&](const Shape& s, const RigidBody& body, double inflation) {
    Posed o;
    o.shape = &s;
    o.rotation = world_rotation(s, body);
    o.centre = body.to_world(s.position);
    o.inflation = inflation;
    return o;
  };
  const double m1 = g.margin[g.owners[i1].body], m2 = g.margin[g.owners[i2].body];
  *applied1 = m1;
  *applied2 = m2;
  for (const bool first : {true, false}) {  // a plane or a heightfield on either side
    const Shape& flat = first ? s2 : s1;
    const RigidBody& flat_body = first ? b2 : b1;
    const Posed o = first ? posed(s1, b1, m1) : posed(s2, b2, m2);
    const double flat_margin = first ? m2 : m1;
    if (flat.type == ShapeType::plane) {
      const Eigen::Vector3d n = (flat_body.orientation * flat.normal).normalized();
      return plane_contact(o, n, n.dot(flat_body.to_world(flat.position)) + flat_margin, first, out);
    }
    if (flat.type == ShapeType::heightfield) {
      (first ? *applied1 : *applied2) += flat_margin;  // the shape carries the field's margin
      (first ? *applied2 : *applied1) = 0;
      return field_contacts(o, flat, flat_body, flat_margin, first, out, max_points);
    }
  }
  return mpr_contact(posed(s1, b1, m1), posed(s2, b2, m2), out) ? 1 : 0;
}

// The broad phase's candidate pair (their bounding boxes overlap) to dCollide or the support
// path, unless the rules of shape.h keep it apart. dCollide's normal points into the first geom
// (moving o1 along it separates them). Each geom is grown by its body's margin; a hull's or a
// heightfield's partner grows by both margins for the call. Body a is the pair's lower index
// whatever order the sweep passes them in (its order follows the bodies' coordinates), so that
// a pair's points keep their identity from step to step (contact.h's matching).
void near_callback(void* data, dGeomID o1, dGeomID o2) {
  auto& g = *static_cast<CollisionWorld::Geometry*>(data);
  const int i1 = static_cast<int>(reinterpret_cast<size_t>(dGeomGetData(o1)));
  const int i2 = static_cast<int>(reinterpret_cast<size_t>(dGeomGetData(o2)));
  const GeomOwner& x = g.owners[i1];
  const GeomOwner& y = g.owners[i2];
  const Mechanism& m = *g.mechanism;
  const RigidBody &bx = m.bodies[x.body], &by = m.bodies[y.body];
  if (x.body == y.body || (bx.is_static && by.is_static)) return;
  const Shape &sx = bx.shapes[x.shape], &sy = by.shapes[y.shape];
  if (!may_collide(sx, sy) || g.excluded_pair(x.body, y.body)) return;
  // Pairs of planes, spheres, capsules and boxes (the enum's first four): ODE's own choice of at
  // most 4 points; the others' points (a cylinder's rim, a hull's vertices) are reduced to 4.
  const bool classic = static_cast<int>(sx.type) <= static_cast<int>(ShapeType::box) &&
                       static_cast<int>(sy.type) <= static_cast<int>(ShapeType::box);
  dContactGeom points[kMaxRawPoints];
  const int wanted = classic ? kMaxPointsPerPair : kMaxRawPoints;
  double grown1 = g.inflation[i1], grown2 = g.inflation[i2];
  int n = 0;
  if (by_support(sx, sy)) {
    n = support_contacts(g, i1, i2, points, wanted, &grown1, &grown2);
  } else if (growable(sx.type) != growable(sy.type)) {
    const int carrier = growable(sx.type) ? i1 : i2;
    const double own = g.inflation[carrier], both = g.margin[x.body] + g.margin[y.body];
    g.grow(carrier, both);
    n = dCollide(o1, o2, wanted, points, sizeof(dContactGeom));
    g.grow(carrier, own);
    (carrier == i1 ? grown1 : grown2) = both;
  } else {
    n = dCollide(o1, o2, wanted, points, sizeof(dContactGeom));
  }
  const auto polytope = [](const Shape& s) { return s.type == ShapeType::box || s.type == ShapeType::convex; };
  if (n == 1 && polytope(sx) && polytope(sy) && !classic) {  // (two boxes: ODE's own points)
    const Polytope p1{&sx, world_rotation(sx, bx), bx.to_world(sx.position)};
    const Polytope p2{&sy, world_rotation(sy, by), by.to_world(sy.position)};
    dContactGeom spread[kMaxRawPoints];
    const Eigen::Vector3d u(points[0].normal[0], points[0].normal[1], points[0].normal[2]);
    const int k = polytope_points(p1, p2, u, grown1, grown2, spread, kMaxRawPoints);
    if (k > 1) n = static_cast<int>(std::copy(spread, spread + k, points) - points);
  }
  n = keep_four(points, n);
  const bool flip = x.body < y.body;  // then a = o1's body and the normal is ODE's reversed
  const GeomOwner &a = flip ? x : y, &b = flip ? y : x;
  const double ma = flip ? grown1 : grown2, mb = flip ? grown2 : grown1;
  GrownShape grown[2];
  int clamped = 0;
  for (const GeomOwner* o : {&a, &b}) {
    const RigidBody& body = m.bodies[o->body];
    const Shape& s = body.shapes[o->shape];
    if ((o == &a ? ma : mb) == 0 || (s.type != ShapeType::box && s.type != ShapeType::cylinder)) continue;
    const Eigen::Vector3d half =
        s.type == ShapeType::box ? s.half_extents : Eigen::Vector3d(s.radius, s.radius, s.half_length);
    grown[clamped++] = {s.type, world_rotation(s, body), body.to_world(s.position), half};
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
    // The grown surfaces overlap by c.depth about c.pos; the real ones lie ma and mb behind
    // them: their depth is c.depth - ma - mb, about the point midway between them.
    p.depth = c.depth - ma - mb;
    p.position = Eigen::Vector3d(c.pos[0], c.pos[1], c.pos[2]) + 0.5 * (mb - ma) * p.normal;
    for (int k = 0; k < clamped; ++k) p.position = grown[k].clamp(p.position, p.normal);
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
      const dGeomID geom = g.make_geom(m.bodies[b].shapes[s]);
      const int index = static_cast<int>(g.geoms.size());
      dGeomSetData(geom, reinterpret_cast<void*>(static_cast<size_t>(index)));
      (m.bodies[b].shapes[s].type == ShapeType::plane ? g.planes : g.swept).push_back(index);
      g.geoms.push_back(geom);
      g.owners.push_back({b, s});
    }
  g.enabled.assign(g.geoms.size(), 1);
  g.inflation.assign(g.geoms.size(), 0.0);
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
  g.mechanism = &m;  // (grow() reads the shapes)
  if (g.geoms.empty()) {
    g.mechanism = nullptr;
    return;
  }
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
    const Shape& s = body.shapes[g.owners[i].shape];
    const double grown = g.margin[g.owners[i].body];
    place(g.geoms[i], s, body);
    g.inflation[i] = 0;
    g.grow(static_cast<int>(i), grown);
    dGeomGetAABB(g.geoms[i], g.box[i].data());
    if (!growable(s.type))  // its partner grows for it: the box must reach as far
      for (int k = 0; k < 6; ++k) g.box[i][k] += k % 2 ? grown : -grown;
  }
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
