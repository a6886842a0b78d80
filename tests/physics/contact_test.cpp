// Contacts: physics/collision.cpp (the detected points against analytic geometry), contact.cpp
// (rows against finite differences, matching) and the step with contacts against analytic
// motion (friction on an incline) and the targets of the hard cases: a 1:1000 stack, a heavy
// ball on a chain, a pyramid, each with PGS shown failing where LDL-PGS holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>

#include <Eigen/Geometry>

#include "ldlpgs/physics/collision.h"
#include "ldlpgs/physics/contact.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "tests/support/allocation_counter.h"  // (replaces operator new: one per executable)

namespace ldlpgs {
namespace {

using Eigen::Vector3d;

Shape plane_shape(const Vector3d& normal = Vector3d::UnitY()) {
  Shape s;
  s.type = ShapeType::plane;
  s.normal = normal;
  return s;
}
Shape sphere_shape(double radius) {
  Shape s;
  s.type = ShapeType::sphere;
  s.radius = radius;
  return s;
}
Shape box_shape(const Vector3d& half_extents) {
  Shape s;
  s.type = ShapeType::box;
  s.half_extents = half_extents;
  return s;
}

// A cylinder whose axis (its frame's z) lies along `axis` in the body frame.
Shape cylinder_shape(double radius, double half_length, const Vector3d& axis = Vector3d::UnitZ()) {
  Shape s;
  s.type = ShapeType::cylinder;
  s.radius = radius;
  s.half_length = half_length;
  s.orientation = Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), axis);
  return s;
}
Shape ellipsoid_shape(const Vector3d& semi_axes) {
  Shape s;
  s.type = ShapeType::ellipsoid;
  s.half_extents = semi_axes;
  return s;
}
// The convex hull of a box's 8 corners, 2 triangles per side (as MuJoCo's hulls are triangulated).
Shape cube_hull_shape(const Vector3d& half) {
  std::vector<Vector3d> corners;
  for (int k = 0; k < 8; ++k)
    corners.emplace_back(k & 1 ? half.x() : -half.x(), k & 2 ? half.y() : -half.y(), k & 4 ? half.z() : -half.z());
  // each side by its 4 corners in cyclic order; make_convex_hull turns the triangles outwards
  const int sides[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  std::vector<std::array<int, 3>> faces;
  for (const auto& q : sides) {
    faces.push_back({q[0], q[1], q[2]});
    faces.push_back({q[0], q[2], q[3]});
  }
  Shape s;
  s.type = ShapeType::convex;
  s.hull = std::make_shared<const ConvexHull>(make_convex_hull(corners, faces));
  return s;
}

int add(Mechanism* m, const std::string& name, bool is_static, const Vector3d& position, const Shape& shape,
        double mass = 1) {
  RigidBody b;
  b.name = name;
  b.is_static = is_static;
  b.mass = mass;
  b.inertia = Vector3d::Constant(mass / 6);  // a unit cube's
  b.position = position;
  b.shapes.push_back(shape);
  return m->add_body(b);
}

Mechanism scene(const std::string& name) {
  Mechanism m;
  if (!builtin_scene(name, &m)) throw std::runtime_error(name);
  return m;
}

// ---- collision detection ----

TEST(Collision, SpherePenetratingAPlaneIsOnePointWithTheNormalFromAToB) {
  for (bool ground_first : {true, false}) {
    Mechanism m;
    if (ground_first) add(&m, "ground", true, Vector3d::Zero(), plane_shape());
    add(&m, "ball", false, Vector3d(0.3, 0.49, -0.2), sphere_shape(0.5));
    if (!ground_first) add(&m, "ground", true, Vector3d::Zero(), plane_shape());
    CollisionWorld world(m);
    std::vector<ContactPoint> points;
    world.detect(m, 0, 0, &points);
    ASSERT_EQ(points.size(), 1u);
    const ContactPoint& p = points[0];
    const RigidBody &a = m.bodies[p.body_a], &b = m.bodies[p.body_b];
    // n from a into b: b's centre minus a's point lies along +n
    EXPECT_GT(p.normal.dot(b.position - a.position), 0) << "ground first " << ground_first;
    EXPECT_NEAR(std::abs(p.normal.y()), 1, 1e-12);
    EXPECT_NEAR(p.depth, 0.01, 1e-12);
    EXPECT_NEAR(p.position.x(), 0.3, 1e-12);
    EXPECT_NEAR(p.position.z(), -0.2, 1e-12);
  }
}

// Within the margin plus what a body travels in the horizon, a gap is a contact of negative depth.
TEST(Collision, SpeculativeContactsReportTheGapWithinTheMargin) {
  Mechanism m;
  add(&m, "ground", true, Vector3d::Zero(), plane_shape());
  const int ball = add(&m, "ball", false, Vector3d(0, 0.55, 0), sphere_shape(0.5));
  m.gravity = Vector3d::Zero();
  CollisionWorld world(m);
  std::vector<ContactPoint> points;
  world.detect(m, 0.04, 0.1, &points);  // 4 cm and a body at rest: the 5 cm gap is out of reach
  EXPECT_TRUE(points.empty());
  m.bodies[ball].linear_velocity = Vector3d(0, -0.2, 0);  // travels 2 cm in 0.1 s: reached
  world.detect(m, 0.04, 0.1, &points);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].depth, -0.05, 1e-12);
  EXPECT_GE(points[0].position.y(), 0);  // across the gap
  EXPECT_LE(points[0].position.y(), 0.05);
}

// Gravity's pull in the horizon reaches a static body's gap (the box 1 mm above the ground is a
// speculative contact) but no gap between two dynamic bodies, which it moves alike: the two boxes
// at rest 1 mm apart are none until they approach.
TEST(Collision, GravityClosesGapsToStaticBodiesOnly) {
  Mechanism m;
  add(&m, "ground", true, Vector3d::Zero(), plane_shape());
  const int left = add(&m, "left", false, Vector3d(-0.5005, 0.501, 0), box_shape(Vector3d(0.5, 0.5, 0.5)));
  const int right = add(&m, "right", false, Vector3d(0.5005, 0.501, 0), box_shape(Vector3d(0.5, 0.5, 0.5)));
  const double horizon = 1.0 / 60;  // falls |g| horizon^2 = 2.7 mm
  CollisionWorld world(m);
  std::vector<ContactPoint> points;
  world.detect(m, 0, horizon, &points);
  ASSERT_EQ(points.size(), 8u);
  for (const ContactPoint& p : points) {
    EXPECT_EQ(p.body_a, 0);  // the ground
    EXPECT_NEAR(p.depth, -0.001, 1e-12);
  }
  m.bodies[left].linear_velocity = Vector3d(0.04, 0, 0);  // closes 0.67 mm in the horizon: not yet
  world.detect(m, 0, horizon, &points);
  EXPECT_EQ(points.size(), 8u);
  m.bodies[right].linear_velocity = Vector3d(-0.04, 0, 0);  // together 1.33 mm: reached
  world.detect(m, 0, horizon, &points);
  ASSERT_GT(points.size(), 8u);
  for (const ContactPoint& p : points)
    if (p.body_a == left) {
      EXPECT_EQ(p.body_b, right);
      EXPECT_NEAR(p.depth, -0.001, 1e-12);
    }
}

TEST(Collision, BoxOnAPlaneGetsItsFourCorners) {
  Mechanism m;
  add(&m, "ground", true, Vector3d::Zero(), plane_shape());
  const int box = add(&m, "box", false, Vector3d(0, 0.499, 0), box_shape(Vector3d(0.5, 0.5, 0.5)));
  m.bodies[box].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vector3d::UnitY()));  // about the normal
  CollisionWorld world(m);
  std::vector<ContactPoint> points;
  world.detect(m, 0, 0, &points);
  ASSERT_EQ(points.size(), 4u);
  for (const ContactPoint& p : points) {
    EXPECT_NEAR(p.depth, 0.001, 1e-12);
    // each at a bottom corner of the box, within the depth
    const Vector3d local = m.bodies[box].orientation.conjugate() * (p.position - m.bodies[box].position);
    EXPECT_NEAR(std::abs(local.x()), 0.5, 1e-9);
    EXPECT_NEAR(std::abs(local.z()), 0.5, 1e-9);
    EXPECT_NEAR(local.y(), -0.5, 0.001);
  }
}

TEST(Collision, JointedBodiesTouchOnlyWhenTheirConstraintSaysCollide) {
  for (bool collide : {false, true}) {
    Mechanism m;
    const int a = add(&m, "a", false, Vector3d::Zero(), sphere_shape(0.5));
    const int b = add(&m, "b", false, Vector3d(0.9, 0, 0), sphere_shape(0.5));
    Constraint c = m.ball(a, b, Vector3d(0.45, 0, 0));
    c.collide = collide;
    m.add_constraint(c);
    CollisionWorld world(m);
    std::vector<ContactPoint> points;
    world.detect(m, 0, 0, &points);
    EXPECT_EQ(points.size(), collide ? 1u : 0u);
  }
}

TEST(Collision, ContypeAndConaffinityFilterPairsAsMuJoCoDoes) {
  struct Case {
    uint32_t type_a, affinity_a, type_b, affinity_b;
    bool touch;
  };
  for (const Case& c : {Case{1, 1, 1, 1, true}, Case{1, 0, 0, 1, true}, Case{0, 1, 1, 0, true}, Case{1, 0, 1, 0, false},
                        Case{2, 2, 1, 1, false}, Case{0, 0, 1, 1, false}}) {
    Mechanism m;
    Shape sa = sphere_shape(0.5), sb = sphere_shape(0.5);
    sa.contype = c.type_a;
    sa.conaffinity = c.affinity_a;
    sb.contype = c.type_b;
    sb.conaffinity = c.affinity_b;
    add(&m, "a", false, Vector3d::Zero(), sa);
    add(&m, "b", false, Vector3d(0.9, 0, 0), sb);
    CollisionWorld world(m);
    std::vector<ContactPoint> points;
    world.detect(m, 0, 0, &points);
    EXPECT_EQ(!points.empty(), c.touch) << c.type_a << c.affinity_a << c.type_b << c.affinity_b;
  }
}

// ---- cylinders, ellipsoids, convex hulls, heightfields ----

// Body b's point p in its shape's frame (the tests' shapes sit at their body's centre).
Vector3d in_shape(const Mechanism& m, int b, const Vector3d& p) {
  const RigidBody& body = m.bodies[b];
  const Shape& s = body.shapes[0];
  return (body.orientation * s.orientation).conjugate() * (p - body.to_world(s.position));
}

std::vector<ContactPoint> detect(const Mechanism& m, double margin = 0, double horizon = 0) {
  CollisionWorld world(m);
  std::vector<ContactPoint> points;
  world.detect(m, margin, horizon, &points);
  return points;
}

// A cylinder standing on the ground (y up) meets it with its bottom rim, lying with its lowest
// line: depth 1 cm each, the normal the ground's, every point on the cylinder's surface. Seen
// from 5 cm up and falling into the margin, its gap; its grown rim is clamped back onto the rim.
TEST(Collision, CylinderStandingAndLyingOnAPlane) {
  const double r = 0.3, h = 0.5;
  struct Case {
    const char* name;
    Vector3d axis;
    double centre_height;  // the bottom 1 cm below the ground
    size_t points;
  };
  for (const Case& c : {Case{"standing", Vector3d::UnitY(), h - 0.01, 4}, Case{"lying", Vector3d::UnitX(), r - 0.01, 2}}) {
    SCOPED_TRACE(c.name);
    Mechanism m;
    add(&m, "ground", true, Vector3d::Zero(), plane_shape());
    const int cylinder = add(&m, "cylinder", false, Vector3d(0.2, c.centre_height, -0.1), cylinder_shape(r, h, c.axis));
    std::vector<ContactPoint> points = detect(m);
    ASSERT_EQ(points.size(), c.points);
    for (const ContactPoint& p : points) {
      EXPECT_EQ(p.body_a, 0);
      EXPECT_NEAR(p.normal.y(), 1, 1e-12);
      EXPECT_NEAR(p.depth, 0.01, 1e-12);
      const Vector3d local = in_shape(m, cylinder, p.position);
      if (c.axis.y() == 1) {  // on the bottom rim
        EXPECT_NEAR(local.head<2>().norm(), r, 1e-9);
        EXPECT_NEAR(local.z(), -h, 0.01);
      } else {  // on the lowest line, at its ends
        EXPECT_NEAR(std::abs(local.z()), h, 1e-9);
        EXPECT_NEAR(p.position.y(), -0.005, 0.005 + 1e-12);
      }
    }
    m.bodies[cylinder].position.y() += 0.06;  // 5 cm above, falling 10 cm in the horizon
    m.bodies[cylinder].linear_velocity = Vector3d(0, -1, 0);
    m.gravity = Vector3d::Zero();
    points = detect(m, 0, 0.1);
    ASSERT_EQ(points.size(), c.points);
    for (const ContactPoint& p : points) {
      EXPECT_NEAR(p.depth, -0.05, 1e-12);
      // across the gap, and sideways within the real cylinder
      EXPECT_NEAR(p.position.y(), 0.025, 0.025 + 1e-12);
      const Vector3d local = in_shape(m, cylinder, p.position);
      if (c.axis.y() == 1) {
        EXPECT_LE(local.head<2>().norm(), r + 1e-9);
      } else {
        EXPECT_LE(std::abs(local.z()), h + 1e-9);
        EXPECT_LE(std::abs(p.position.z() - m.bodies[cylinder].position.z()), r + 1e-9);
      }
    }
  }
}

// A sphere on a standing cylinder's top, a box under a lying one, a sphere against its side: the
// depths and normals of the two surfaces' geometry.
TEST(Collision, CylinderAgainstASphereAndABox) {
  const double r = 0.3, h = 0.5;
  {
    Mechanism m;
    add(&m, "cylinder", false, Vector3d::Zero(), cylinder_shape(r, h, Vector3d::UnitY()));
    add(&m, "top", false, Vector3d(0.1, h + 0.2 - 0.01, 0.05), sphere_shape(0.2));
    add(&m, "side", false, Vector3d(r + 0.2 - 0.02, 0.1, 0), sphere_shape(0.2));
    const std::vector<ContactPoint> points = detect(m);
    ASSERT_EQ(points.size(), 2u);
    for (const ContactPoint& p : points) {
      EXPECT_EQ(p.body_a, 0);
      if (p.body_b == 1) {
        EXPECT_NEAR(p.depth, 0.01, 1e-9);
        EXPECT_NEAR(p.normal.y(), 1, 1e-9);
      } else {
        EXPECT_NEAR(p.depth, 0.02, 1e-9);
        EXPECT_NEAR(p.normal.x(), 1, 1e-9);
      }
    }
  }
  // lying on a box, and standing on it: ODE finds 8 points of the rim, of which the 4 kept
  // span it (their centre near the axis, not on one side)
  for (const bool standing : {false, true}) {
    Mechanism m;
    add(&m, "table", true, Vector3d::Zero(), box_shape(Vector3d(1, 0.5, 1)));
    const Vector3d axis = standing ? Vector3d::UnitY() : Vector3d::UnitZ();
    const Vector3d centre(0.1, 0.5 + (standing ? h : r) - 0.01, 0);
    add(&m, "cylinder", false, centre, cylinder_shape(r, h, axis));
    const std::vector<ContactPoint> points = detect(m);
    ASSERT_EQ(points.size(), standing ? 4u : 2u);
    Vector3d mean = Vector3d::Zero();
    for (const ContactPoint& p : points) {
      EXPECT_NEAR(p.depth, 0.01, 1e-9);
      EXPECT_NEAR(p.normal.y(), 1, 1e-9);
      mean += p.position / static_cast<double>(points.size());
    }
    EXPECT_LT(std::hypot(mean.x() - centre.x(), mean.z() - centre.z()), 0.1 * r) << "standing " << standing;
  }
}

// The lowest point of an ellipsoid in a general orientation over the ground (y up), found by
// sampling its surface on a fine grid of angles: the analytic answer's independent reference.
Vector3d lowest_sampled(const Vector3d& semi_axes, const Eigen::Quaterniond& q) {
  Vector3d best(0, 1e9, 0);
  const int n = 2000;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = M_PI * i / n, phi = M_PI * j / n;
      const Vector3d p = q * semi_axes.cwiseProduct(
                                 Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
      if (p.y() < best.y()) best = p;
    }
  return best;
}

// An ellipsoid at rest on the ground touches it at its lowest point, one contact 1 cm deep there
// with the ground's normal; lifted 4 cm and falling into the margin, the gap.
TEST(Collision, EllipsoidRestsOnAPlaneAtItsLowestPoint) {
  const Vector3d semi_axes(0.2, 0.5, 0.3);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Vector3d(1, 2, -1).normalized()));
  const Vector3d lowest = lowest_sampled(semi_axes, q);  // relative to the centre
  Mechanism m;
  add(&m, "ground", true, Vector3d::Zero(), plane_shape());
  const int e = add(&m, "ellipsoid", false, Vector3d(0.3, -lowest.y() - 0.01, 0.2), ellipsoid_shape(semi_axes));
  m.bodies[e].orientation = q;
  std::vector<ContactPoint> points = detect(m);
  ASSERT_EQ(points.size(), 1u);
  const Vector3d touch = m.bodies[e].position + lowest;
  EXPECT_NEAR(points[0].depth, 0.01, 1e-6);  // (the sampling's resolution)
  EXPECT_NEAR(points[0].normal.y(), 1, 1e-12);
  EXPECT_NEAR(points[0].position.x(), touch.x(), 2e-3);
  EXPECT_NEAR(points[0].position.z(), touch.z(), 2e-3);
  m.bodies[e].position.y() += 0.05;
  m.bodies[e].linear_velocity = Vector3d(0, -1, 0);
  m.gravity = Vector3d::Zero();
  points = detect(m, 0, 0.1);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].depth, -0.04, 1e-6);
}

// An ellipsoid against a sphere on its long axis and a box face on its short one (libccd's MPR):
// the depths of the axes' lengths, the normals along the axes.
TEST(Collision, EllipsoidAgainstASphereAndABox) {
  const Vector3d semi_axes(0.2, 0.5, 0.3);
  Mechanism m;
  add(&m, "ellipsoid", false, Vector3d::Zero(), ellipsoid_shape(semi_axes));
  add(&m, "sphere", false, Vector3d(0, 0.5 + 0.1 - 0.01, 0), sphere_shape(0.1));
  add(&m, "box", false, Vector3d(0.2 + 0.25 - 0.02, 0, 0), box_shape(Vector3d::Constant(0.25)));
  const std::vector<ContactPoint> points = detect(m);
  ASSERT_EQ(points.size(), 2u);
  for (const ContactPoint& p : points) {
    EXPECT_EQ(p.body_a, 0);
    const Vector3d axis = p.body_b == 1 ? Vector3d::UnitY() : Vector3d::UnitX();
    EXPECT_NEAR(p.depth, p.body_b == 1 ? 0.01 : 0.02, 1e-6);
    EXPECT_NEAR(p.normal.dot(axis), 1, 1e-6);
  }
}

// The hull of a cube's 8 corners is the box: on the ground, turned about the normal or tipped
// onto an edge, its points are the box's (1 mm deep at the lowest corners). Lifted 5 cm and
// falling into the margin, each point is a corner's gap, exactly (the ground grows for the hull;
// a grown box's tipped corner stands out further than its margin, so the box is no reference
// there).
TEST(Collision, ConvexHullOfACubeOnAPlaneMatchesTheBox) {
  const Vector3d half(0.5, 0.4, 0.3);
  const Eigen::Quaterniond poses[] = {Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vector3d::UnitY())),
                                      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 0, 1).normalized()))};
  for (const Eigen::Quaterniond& q : poses) {
    std::vector<Vector3d> corners;  // about the centre, world frame
    for (int c = 0; c < 8; ++c) corners.push_back(q * Vector3d(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1).cwiseProduct(half));
    double lowest = 0;
    for (const Vector3d& c : corners) lowest = std::min(lowest, c.y());
    for (const bool falling : {false, true}) {
      SCOPED_TRACE(falling ? "falling" : "resting");
      std::vector<ContactPoint> of[2];
      Vector3d centre;
      for (int k = 0; k < 2; ++k) {
        Mechanism m;
        add(&m, "ground", true, Vector3d::Zero(), plane_shape());
        const Shape s = k == 0 ? box_shape(half) : cube_hull_shape(half);
        const int b = add(&m, "body", false, Vector3d(0.1, -lowest + (falling ? 0.05 : -0.001), 0.2), s);
        m.bodies[b].orientation = q;
        m.bodies[b].linear_velocity = Vector3d(0, falling ? -1 : 0, 0);
        m.gravity = Vector3d::Zero();
        of[k] = detect(m, 0, 0.1);
        centre = m.bodies[b].position;
      }
      ASSERT_FALSE(of[1].empty());
      double deepest = -1;
      for (const ContactPoint& p : of[1]) {
        EXPECT_EQ(p.body_a, 0);
        EXPECT_NEAR(p.normal.y(), 1, 1e-12);
        // the corner under the point: its depth is that corner's below the ground
        const Vector3d* under = &corners[0];
        for (const Vector3d& c : corners)
          if ((c - p.position + centre).cwiseProduct(Vector3d(1, 0, 1)).norm() <
              (*under - p.position + centre).cwiseProduct(Vector3d(1, 0, 1)).norm())
            under = &c;
        EXPECT_NEAR(p.depth, -(centre + *under).y(), 1e-12);
        EXPECT_LE((p.position - centre - *under).cwiseProduct(Vector3d(1, 0, 1)).norm(), 1e-9);
        deepest = std::max(deepest, p.depth);
      }
      EXPECT_NEAR(deepest, falling ? -0.05 : 0.001, 1e-12);
      if (falling) continue;
      ASSERT_EQ(of[1].size(), of[0].size());
      const auto key = [](const ContactPoint& p) { return std::make_tuple(p.position.x(), p.position.z()); };
      for (auto& points : of)
        std::sort(points.begin(), points.end(), [&](const ContactPoint& x, const ContactPoint& y) { return key(x) < key(y); });
      for (size_t i = 0; i < of[0].size(); ++i) {
        EXPECT_NEAR(of[1][i].depth, of[0][i].depth, 1e-12);
        EXPECT_LE((of[1][i].position - of[0][i].position).norm(), 1e-9);
        EXPECT_LE((of[1][i].normal - of[0][i].normal).norm(), 1e-12);
      }
    }
  }
}

// A cube's hull under a sphere, a box and another hull (the support path) set off sideways: the
// depth between the faces and the normal across them, and for the box and the hull the two
// corners of the faces' overlap (polytope_points; ODE and MPR find one point).
TEST(Collision, ConvexHullAgainstASphereABoxAndAHull) {
  const Vector3d half = Vector3d::Constant(0.25);
  for (const ShapeType other : {ShapeType::sphere, ShapeType::box, ShapeType::convex}) {
    SCOPED_TRACE(to_string(other));
    Mechanism m;
    add(&m, "hull", false, Vector3d::Zero(), cube_hull_shape(half));
    const Shape s = other == ShapeType::sphere ? sphere_shape(0.2) : other == ShapeType::box ? box_shape(half) : cube_hull_shape(half);
    const double reach = other == ShapeType::sphere ? 0.2 : 0.25;
    add(&m, "other", false, Vector3d(0.05, 0.25 + reach - 0.01, -0.03), s);
    const std::vector<ContactPoint> points = detect(m);
    // a face on a face: the corners of each that lie on the other (here two), not one point
    ASSERT_EQ(points.size(), other == ShapeType::sphere ? 1u : 2u);
    for (const ContactPoint& p : points) {
      EXPECT_EQ(p.body_a, 0);
      EXPECT_NEAR(p.depth, 0.01, 1e-9);
      EXPECT_NEAR(p.normal.y(), 1, 1e-9);
      EXPECT_NEAR(p.position.y(), 0.25 - 0.005, 0.005 + 1e-9);
    }
  }
}

// A heightfield sampling the plane z = 0.1 + 0.2 x - 0.1 y on 4 x 5 points 1 m apart, one sample
// raised by 1 m, turned so that its z is our y: a ball 0.09 m from the ramp's plane is 1 cm deep
// with the ramp's normal, over the ramp and over a triangle beside the raised sample that is on
// the ramp when cells are split as MuJoCo splits them, from (r, c) to (r + 1, c + 1).
TEST(Collision, BallOnAHeightfieldAtItsHeight) {
  auto field = std::make_shared<HeightField>();
  field->rows = 4;
  field->cols = 5;
  field->half_x = 2;
  field->half_y = 1.5;
  field->base = 0.5;
  for (int r = 0; r < field->rows; ++r)
    for (int c = 0; c < field->cols; ++c) {
      const double x = -2 + c, y = -1.5 + r;
      field->heights.push_back(0.1 + 0.2 * x - 0.1 * y);
    }
  field->heights[1 * field->cols + 1] += 1;  // sample (r 1, c 1) at x = -1, y = -0.5
  Shape ground;
  ground.type = ShapeType::heightfield;
  ground.field = field;
  ground.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()));  // its z up onto our y
  const Vector3d up = Vector3d::UnitY();
  const auto height = [](double x, double y) { return 0.1 + 0.2 * x - 0.1 * y; };
  const Vector3d n = Vector3d(-0.2, 0.1, 1).normalized();  // the ramp's normal, field frame
  struct Case {
    double x, y;  // field frame
  };
  // over the ramp in cell (r 1, c 3); over cell (r 0, c 1) at u = 0.7 of its columns' side and
  // v = 0.2 of its rows', in its triangle (0, 1), (1, 2), (0, 2) on the ramp: split along the
  // other diagonal, the raised sample (1, 1) would lift the surface there by 0.2 m
  for (const Case& c : {Case{1.3, 0.4}, Case{-0.3, -1.3}}) {
    SCOPED_TRACE(c.x);
    Mechanism m;
    add(&m, "ground", true, Vector3d::Zero(), ground);
    // the ball's centre at distance 0.09 from the ramp plane through (x, y, height)
    const Vector3d surface(c.x, c.y, height(c.x, c.y));
    const Vector3d centre_field = surface + 0.09 * n;
    const Vector3d centre = ground.orientation * centre_field;
    add(&m, "ball", false, centre, sphere_shape(0.1));
    const std::vector<ContactPoint> points = detect(m);
    ASSERT_FALSE(points.empty());
    double deepest = -1;
    for (const ContactPoint& p : points) {
      EXPECT_EQ(p.body_a, 0);
      deepest = std::max(deepest, p.depth);
      EXPECT_LE((p.normal - ground.orientation * n).norm(), 1e-9);
    }
    EXPECT_NEAR(deepest, 0.01, 1e-9);
    EXPECT_GT(up.dot(ground.orientation * n), 0);
  }
}

// ---- contact rows ----

// J V is dc/dt: the rows' Jacobian against central differences of c along a random motion.
TEST(Contact, RowsAreTheDerivativeOfTheirPositionErrors) {
  Mechanism m;
  add(&m, "a", false, Vector3d(0.1, -0.2, 0.3), box_shape(Vector3d(0.5, 0.4, 0.3)));
  add(&m, "b", false, Vector3d(0.2, 0.6, 0.1), box_shape(Vector3d(0.3, 0.4, 0.5)));
  m.bodies[0].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));
  m.bodies[1].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(-0.7, Vector3d(3, -1, 2).normalized()));
  ContactPoint p;
  p.body_a = 0;
  p.body_b = 1;
  p.shape_a = p.shape_b = 0;
  p.position = Vector3d(0.15, 0.2, 0.2);
  p.normal = Vector3d(0.2, 1, -0.1).normalized();
  p.depth = 0.01;
  std::vector<Contact> contacts;
  std::vector<ContactKey> order;
  std::vector<Eigen::Matrix3d> rotations;
  body_rotations(m, &rotations);
  make_contacts(m, rotations, std::span<const ContactPoint>(&p, 1), {}, 0.02, &order, &contacts);
  ASSERT_EQ(contacts.size(), 1u);
  const ConstraintRows rows = evaluate(contacts[0], m.bodies[0], m.bodies[1]);
  EXPECT_NEAR(rows.c[0], -0.01, 1e-12);  // the separation at detection
  const double v[12] = {0.3, -0.1, 0.2, 0.5, -0.4, 0.1, -0.2, 0.4, 0.1, -0.3, 0.2, 0.6};
  const auto moved = [&](double h) {
    Mechanism copy = m;
    for (int side = 0; side < 2; ++side) {
      RigidBody& b = copy.bodies[side];
      b.position += h * Vector3d(v[6 * side], v[6 * side + 1], v[6 * side + 2]);
      const Vector3d w(v[6 * side + 3], v[6 * side + 4], v[6 * side + 5]);
      b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(h * w.norm(), w.normalized())) * b.orientation;
    }
    return evaluate(contacts[0], copy.bodies[0], copy.bodies[1]);
  };
  const double h = 1e-6;
  const ConstraintRows plus = moved(h), minus = moved(-h);
  for (int r = 0; r < 3; ++r) {
    double jv = 0;
    for (int x = 0; x < 12; ++x) jv += rows.jacobian[12 * r + x] * v[x];
    EXPECT_NEAR(jv, (plus.c[r] - minus.c[r]) / (2 * h), 1e-8) << "row " << r;
  }
}

// ---- the step with contacts ----

struct Run {
  double penetration_max = 0;
};

// A unit cube on the ground under gravity tilted by theta along `slope` (a unit tangent of the
// ground): below the friction angle it stays, above it slides at g (sin theta - mu cos theta).
Vector3d incline_velocity(double tan_theta, const Vector3d& slope, double seconds, Vector3d* moved) {
  Mechanism m;
  Shape ground = plane_shape();
  ground.friction = 0.6;
  Shape cube = box_shape(Vector3d::Constant(0.5));
  cube.friction = 0.6;
  add(&m, "ground", true, Vector3d::Zero(), ground);
  add(&m, "cube", false, Vector3d(0, 0.4995, 0), cube);
  m.timestep = 1.0 / 60;
  const double theta = std::atan(tan_theta);
  m.gravity = 9.81 * (-std::cos(theta) * Vector3d::UnitY() + std::sin(theta) * slope);
  Simulation sim(m, StepOptions{});
  const Vector3d start = sim.mechanism().bodies[1].position;
  const int steps = static_cast<int>(std::lround(seconds / m.timestep));
  for (int s = 0; s < steps; ++s) sim.step();
  *moved = sim.mechanism().bodies[1].position - start;
  return sim.mechanism().bodies[1].linear_velocity;
}

TEST(ContactStep, FrictionHoldsBelowTheFrictionAngleAndSlidesAtTheCoulombRateAbove) {
  const double mu = 0.6;
  for (const Vector3d& slope : {Vector3d(1, 0, 0), Vector3d(0, 0, 1), Vector3d(1, 0, 1).normalized()}) {
    SCOPED_TRACE(slope.transpose());
    Vector3d moved;
    incline_velocity(0.8 * mu, slope, 2, &moved);
    EXPECT_LT(moved.norm(), 1e-4);
    const double tan_theta = 1.3 * mu, theta = std::atan(tan_theta);
    const Vector3d v = incline_velocity(tan_theta, slope, 2, &moved);
    const double expected = 9.81 * (std::sin(theta) - mu * std::cos(theta));
    // from rest, the velocity after 2 s along the slope is a t
    EXPECT_NEAR(v.dot(slope) / 2, expected, 0.02 * expected);
    EXPECT_LT((v - v.dot(slope) * slope).norm(), 0.02 * expected * 2);  // straight down the slope
  }
}

struct StackResult {
  double sink = 0, speed = 0, penetration = 0;
};
StackResult run_stack(SolverKind kind, int factor_after, int steps) {
  StepOptions o;
  o.solver.kind = kind;
  o.contacts.factor_after = factor_after;
  o.diagnostics = true;  // (the deepest contact)
  Simulation sim(scene("box-stack-1000"), o);
  const int heavy = sim.mechanism().find_body("heavy");
  const double start = sim.mechanism().bodies[heavy].position.y();
  StackResult r;
  for (int s = 0; s < steps; ++s) r.penetration = std::max(r.penetration, sim.step().penetration_max_m);
  r.sink = start - sim.mechanism().bodies[heavy].position.y();
  r.speed = sim.mechanism().bodies[heavy].linear_velocity.norm();
  return r;
}

TEST(ContactStep, HeavyBoxOnALightOneHoldsWithContactsInTheFactorWherePgsSinks) {
  const double slop = ContactOptions{}.slop;
  const StackResult held = run_stack(SolverKind::ldl_pgs, ContactOptions{}.factor_after, 120);
  std::printf("ldl-pgs (contacts in the factor): sink %.3g m, speed %.3g m/s, penetration %.3g m\n", held.sink,
              held.speed, held.penetration);
  EXPECT_LT(held.sink, 0.01);
  EXPECT_LT(held.speed, 0.01);
  EXPECT_LE(held.penetration, slop + 0.001);
  // the baseline at the same iterations: the heavy box pushes the light one into the ground
  const StackResult pgs = run_stack(SolverKind::pgs, 0, 120);
  std::printf("pgs: sink %.3g m, speed %.3g m/s, penetration %.3g m\n", pgs.sink, pgs.speed, pgs.penetration);
  EXPECT_TRUE(pgs.sink >= 0.01 || pgs.penetration > slop + 0.001);
  const StackResult rows = run_stack(SolverKind::ldl_pgs, 0, 120);
  std::printf("ldl-pgs, contacts as projected rows only: sink %.3g m, speed %.3g m/s, penetration %.3g m\n", rows.sink,
              rows.speed, rows.penetration);
}

// ldl-pgs factors the contacts of a body that carries one at least factor_mass_ratio times
// heavier (the light box under the heavy one) and leaves a pyramid of equal boxes to PGS; with
// the ratio 0 it factors every pushing contact.
int factored_after(const std::string& name, double mass_ratio, int steps) {
  StepOptions o;
  o.contacts.factor_mass_ratio = mass_ratio;
  Simulation sim(scene(name), o);
  for (int s = 0; s < steps; ++s) sim.step();
  int factored = 0;
  for (const Contact& c : sim.contacts()) factored += c.factored;
  return factored;
}

TEST(ContactStep, ContactsJoinTheFactorWhereAMassRatioAsksForIt) {
  const double ratio = ContactOptions{}.factor_mass_ratio;
  EXPECT_GT(factored_after("box-stack-1000", ratio, 10), 0);
  EXPECT_EQ(factored_after("pyramid-10", ratio, 10), 0);
  EXPECT_GT(factored_after("pyramid-10", 0, 10), 0);
}

TEST(ContactStep, PyramidOf55BoxesStands) {
  StepOptions o;
  o.diagnostics = true;  // (the deepest contact)
  Simulation sim(scene("pyramid-10"), o);
  const int top = static_cast<int>(sim.mechanism().bodies.size()) - 1;
  const Vector3d start = sim.mechanism().bodies[top].position;
  double penetration = 0;
  for (int s = 0; s < 500; ++s) penetration = std::max(penetration, sim.step().penetration_max_m);
  const double moved = (sim.mechanism().bodies[top].position - start).norm();
  std::printf("pyramid-10: top moved %.3g m, penetration %.3g m, %lld symbolic phases\n", moved, penetration,
              static_cast<long long>(sim.solver().symbolic_stats().analyses));
  EXPECT_LT(moved, 0.01);
}

#ifdef __SANITIZE_ADDRESS__
constexpr int kBallChainSteps = 3000;
#else
constexpr int kBallChainSteps = 10000;
#endif
// Released horizontal, the chain swings its 1000:1 ball onto the ground and ends lying there:
// finite, every joint within 1e-6 m and no contact deeper than the slop plus 1 mm at the end of
// every step, the swing and the landing included.
TEST(ContactStep, HeavyBallOnAChainEndsOnTheGroundWithItsJointsHeld) {
  StepOptions o;
  o.diagnostics = true;
  Simulation sim(scene("ball-chain-20-1000"), o);
  const double slop = o.contacts.slop;
  double joints_swing = 0, penetration_swing = 0;
  StepReport r;
  for (int s = 0; s < kBallChainSteps; ++s) {
    r = sim.step();
    ASSERT_TRUE(std::isfinite(r.energy) && run_failure(r, 10.5).empty()) << "step " << s << ": " << run_failure(r, 10.5);
    joints_swing = std::max(joints_swing, r.error.position_max);
    penetration_swing = std::max(penetration_swing, r.penetration_max_m);
  }
  const RigidBody& ball = sim.mechanism().bodies[sim.mechanism().find_body("ball")];
  std::printf("ball-chain-20-1000: during the run joints %.3g m, penetration %.3g m; at the end joints %.3g m, "
              "penetration %.3g m, ball at y = %.4f m\n",
              joints_swing, penetration_swing, r.error.position_max, r.penetration_max_m, ball.position.y());
  EXPECT_LT(joints_swing, 1e-6);
  EXPECT_LE(penetration_swing, slop + 0.001);
  EXPECT_NEAR(ball.position.y(), 0.25, slop + 0.001);  // on the ground (rolling: no rolling friction)
}

// The 1000:1 ball on a 6-link chain: a link spins up about its own axis, which a ball joint leaves
// free, and with the rotation keeping each body's angular momentum (the default) the chain gains
// energy and comes apart near step 1000. The implicit gyroscopic term
// (ContactOptions::implicit_gyroscopic) keeps it whole, its energy not above the start's, over
// 3000 steps.
TEST(ContactStep, ShortHeavyBallChainStaysWholeWithTheImplicitGyroscopicTerm) {
  for (bool implicit : {true, false}) {
    SCOPED_TRACE(implicit ? "implicit" : "angular momentum kept");
    StepOptions o;
    o.diagnostics = true;
    o.contacts.implicit_gyroscopic = implicit;
    Simulation sim(scene("ball-chain-6-1000"), o);
    const double size = mechanism_size(sim.mechanism());
    double start = 0, highest = 0;
    std::string failure;
    for (int s = 0; s < 3000 && failure.empty(); ++s) {
      const StepReport r = sim.step();
      failure = run_failure(r, size);
      if (s == 0) start = r.energy;
      highest = std::max(highest, r.energy);
    }
    std::printf("ball-chain-6-1000, %s: energy %.6g J at the start, at most %.6g; %s\n", implicit ? "implicit" : "momentum",
                start, highest, failure.empty() ? "whole" : failure.c_str());
    if (implicit) {
      EXPECT_EQ(failure, "");
      EXPECT_LE(highest, start * (1 + 1e-6));
    } else {
      EXPECT_NE(failure, "");  // the baseline, shown failing
    }
  }
}

#ifdef LDLPGS_HAVE_MUJOCO
// MuJoCo's humanoid models fall onto their floor and stay on it: no contact deeper than the slop
// plus 1 mm at the end of any step, every body's centre above the floor, no run failure.
TEST(ContactStep, MujocoHumanoidsFallOntoTheirFloorAndStayOnIt) {
  struct Case {
    const char* file;
    int steps;
  };
#ifdef __SANITIZE_ADDRESS__
  const Case cases[] = {{"humanoid.xml", 1000}, {"22_humanoids.xml", 50}};
#else
  const Case cases[] = {{"humanoid.xml", 10000}, {"22_humanoids.xml", 1000}};
#endif
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    StepOptions o;
    o.diagnostics = true;
    Simulation sim(load_mechanism(std::string("/usr/share/mujoco/model/humanoid/") + c.file), o);
    const double size = mechanism_size(sim.mechanism());
    double penetration = 0;
    for (int s = 0; s < c.steps; ++s) {
      const StepReport r = sim.step();
      ASSERT_EQ(run_failure(r, size), "") << "step " << s;
      penetration = std::max(penetration, r.penetration_max_m);
    }
    double lowest = kUnbounded;
    for (const RigidBody& b : sim.mechanism().bodies)
      if (!b.is_static) lowest = std::min(lowest, b.position.z());
    std::printf("%s, %d steps: deepest contact %.3g m, lowest centre z = %.3g m\n", c.file, c.steps, penetration, lowest);
    EXPECT_LE(penetration, o.contacts.slop + 0.001);
    EXPECT_GT(lowest, 0);
  }
}
#endif

// The talk's two vehicles on the ground, driven by their wheels' torques: they move forward (+x),
// their joints at the post-stabilization's tolerance and their contacts at the slop at the end of
// every step (the tracked vehicle's through the contact rows' Schur complement: papers/physics.md,
// "Vehicles on the ground").
TEST(ContactStep, VehiclesOnTheGroundDriveForward) {
  for (const char* name : {"tracked-vehicle-on-ground", "multi-wheeled-vehicle-on-ground"}) {
    SCOPED_TRACE(name);
    StepOptions o;
    o.diagnostics = true;
    Simulation sim(scene(name), o);
    const double size = mechanism_size(sim.mechanism());
    const int chassis = sim.mechanism().find_body("chassis");
    const double start = sim.mechanism().bodies[chassis].position.x();
    double joints = 0, penetration = 0;
    for (int s = 0; s < 120; ++s) {
      const StepReport r = sim.step();
      ASSERT_EQ(run_failure(r, size), "") << "step " << s;
      joints = std::max(joints, r.error.position_max);
      penetration = std::max(penetration, r.penetration_max_m);
    }
    const double advanced = sim.mechanism().bodies[chassis].position.x() - start;
    std::printf("%s, 2 s: advanced %.3g m, joints %.3g m, penetration %.3g m\n", name, advanced, joints, penetration);
    EXPECT_GT(advanced, 0.5);
    EXPECT_LE(joints, o.post_stabilize_tolerance);
    EXPECT_LE(penetration, o.contacts.slop + 1e-6);
  }
}

// A body with one shape of each new kind, dropped from 0.5 m onto the ground, comes to rest
// standing on it (a cylinder on its end and a cube's hull on a face, both dropped slightly
// tipped; an ellipsoid on its shortest axis, dropped upright: tipped, it would rock without end,
// as nothing resists rolling): at the end at rest with its centre at the height of its resting
// pose, no contact deeper than the slop plus 1 mm after any step.
TEST(ContactStep, CylinderHullAndEllipsoidDroppedOnTheGroundComeToRestOnIt) {
  struct Case {
    const char* name;
    Shape shape;
    Vector3d inertia;  // of mass 1
    double rest;       // the centre's height at rest
    double tip;        // rad
    Shape ground = plane_shape();  // its top at y = 0
  };
  const double r = 0.2, h = 0.25;
  const Case cases[] = {
      {"cylinder", cylinder_shape(r, h, Vector3d::UnitY()),
       Vector3d((3 * r * r + 4 * h * h) / 12, r * r / 2, (3 * r * r + 4 * h * h) / 12), h, 0.05},
      {"convex", cube_hull_shape(Vector3d::Constant(0.25)), Vector3d::Constant(0.5 * 0.5 / 6), 0.25, 0.05},
      {"ellipsoid", ellipsoid_shape(Vector3d(0.3, 0.2, 0.4)), Vector3d(0.2 * 0.2 + 0.4 * 0.4, 0.3 * 0.3 + 0.4 * 0.4, 0.3 * 0.3 + 0.2 * 0.2) / 5,
       0.2, 0},
      {"convex on a box", cube_hull_shape(Vector3d::Constant(0.25)), Vector3d::Constant(0.5 * 0.5 / 6), 0.25, 0.05,
       box_shape(Vector3d(2, 0.5, 2))},
      {"convex on a hull", cube_hull_shape(Vector3d::Constant(0.25)), Vector3d::Constant(0.5 * 0.5 / 6), 0.25, 0.05,
       cube_hull_shape(Vector3d(2, 0.5, 2))},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Mechanism m;
    add(&m, "ground", true, Vector3d(0, c.ground.type == ShapeType::plane ? 0 : -0.5, 0), c.ground);
    const int b = add(&m, c.name, false, Vector3d(0, c.rest + 0.5, 0), c.shape);
    m.bodies[b].inertia = c.inertia;
    m.bodies[b].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(c.tip, Vector3d(1, 0, 1).normalized()));
    m.timestep = 1.0 / 60;
    StepOptions o;
    o.diagnostics = true;
    Simulation sim(m, o);
    const double size = mechanism_size(sim.mechanism());
    double penetration = 0;
    for (int s = 0; s < 180; ++s) {
      const StepReport report = sim.step();
      ASSERT_EQ(run_failure(report, size), "") << "step " << s;
      penetration = std::max(penetration, report.penetration_max_m);
    }
    const RigidBody& body = sim.mechanism().bodies[b];
    std::printf("%s dropped 0.5 m, 3 s: centre %.4g m (at rest %.4g), speed %.2g m/s, deepest contact %.3g m\n", c.name,
                body.position.y(), c.rest, body.linear_velocity.norm(), penetration);
    EXPECT_NEAR(body.position.y(), c.rest, o.contacts.slop + 0.001);
    EXPECT_LT(body.linear_velocity.norm(), 0.01);
    EXPECT_LT(body.angular_velocity.norm(), 0.05);
    EXPECT_LE(penetration, o.contacts.slop + 0.001);
  }
}

// The allocations of 30 steps after `settle` steps.
int64_t allocations_after(Simulation& sim, int settle) {
  for (int s = 0; s < settle; ++s) sim.step();
  allocations = 0;
  counting = true;
  for (int s = 0; s < 30; ++s) sim.step();
  counting = false;
  return allocations;
}

TEST(ContactStep, AllocatesNothingOnceTheContactsHaveSettled) {
  for (SolverKind kind : {SolverKind::ldl_pgs, SolverKind::pgs}) {
    StepOptions o;
    o.solver.kind = kind;
    Simulation sim(scene("box-stack-1000"), o);
    EXPECT_EQ(allocations_after(sim, 30), 0) << to_string(kind);
  }
  // a cylinder, a hull, an ellipsoid and a hull on a hull at rest on the ground, a ball on a
  // heightfield (their collision paths), after 60 steps as the vehicle: the hull on the hull
  // gains its points over the first ones
  {
    Mechanism m;
    add(&m, "ground", true, Vector3d::Zero(), plane_shape());
    add(&m, "cylinder", false, Vector3d(0, 0.3, 0), cylinder_shape(0.2, 0.3, Vector3d::UnitY()));
    add(&m, "hull", false, Vector3d(1, 0.25, 0), cube_hull_shape(Vector3d::Constant(0.25)));
    add(&m, "ellipsoid", false, Vector3d(-1, 0.2, 0), ellipsoid_shape(Vector3d(0.3, 0.2, 0.4)));
    add(&m, "on the hull", false, Vector3d(1, 0.75, 0), cube_hull_shape(Vector3d::Constant(0.25)));
    Shape field;  // a flat 4 x 4 m heightfield beside them, a ball on it
    field.type = ShapeType::heightfield;
    field.field = std::make_shared<const HeightField>(HeightField{5, 5, 2, 2, 0.5, std::vector<double>(25, 0.0)});
    field.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()));  // its z up onto our y
    add(&m, "field", true, Vector3d(5, 0, 0), field);
    add(&m, "on the field", false, Vector3d(5, 0.2, 0), sphere_shape(0.2));
    Simulation sim(m, StepOptions{});
    EXPECT_EQ(allocations_after(sim, 60), 0) << "new shapes";
  }
  // the position level's Schur complement too, on a vehicle
  Simulation sim(scene("tracked-vehicle-on-ground"), StepOptions{});
  EXPECT_EQ(allocations_after(sim, 60), 0) << "tracked-vehicle-on-ground";
}

TEST(ContactStep, AddShapeChecksTheShapeAndTheSolver) {
  Mechanism m;
  RigidBody b;
  b.name = "b";
  m.add_body(b);
  Simulation sim(m, StepOptions{});
  EXPECT_THROW(sim.add_shape(0, sphere_shape(-1)), InputError);
  EXPECT_THROW(sim.add_shape(0, plane_shape()), InputError);  // a plane on a dynamic body
  Shape field;  // a heightfield: static only, with a grid; a hull needs vertices
  field.type = ShapeType::heightfield;
  field.field = std::make_shared<const HeightField>(HeightField{2, 2, 1, 1, 0.1, {0, 0, 0, 0}});
  EXPECT_EQ(shape_problem(field, true), "");
  EXPECT_THROW(sim.add_shape(0, field), InputError);
  field.field = std::make_shared<const HeightField>(HeightField{2, 2, 1, 1, 0.1, {0, 0, 0}});
  EXPECT_NE(shape_problem(field, true), "");
  Shape hull;
  hull.type = ShapeType::convex;
  EXPECT_THROW(sim.add_shape(0, hull), InputError);
  EXPECT_THROW(sim.add_shape(0, cylinder_shape(0.1, 0)), InputError);  // a cylinder needs a length
  EXPECT_THROW(sim.add_shape(1, sphere_shape(1)), InputError);
  sim.add_shape(0, sphere_shape(1));
  EXPECT_EQ(sim.mechanism().bodies[0].shapes.size(), 1u);
  StepOptions direct;
  direct.solver.kind = SolverKind::direct;
  EXPECT_THROW(Simulation(sim.mechanism(), direct), InputError);
}

TEST(ContactStep, SimulationRefusesAMarginOutsideZeroToOneMetre) {
  for (double margin : {-0.01, std::nan(""), 2.0}) {
    StepOptions o;
    o.contacts.margin = margin;
    EXPECT_THROW(Simulation(scene("box-stack-1000"), o), InputError) << margin;
  }
  StepOptions o;
  o.contacts.margin = 0.02;  // Box2D's and Jolt's speculative distance
  EXPECT_NO_THROW(Simulation(scene("box-stack-1000"), o));
}

}  // namespace
}  // namespace ldlpgs
