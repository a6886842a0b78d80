#pragma once
// Collision shapes carried by a rigid body (RigidBody::shapes). A shape is placed in its body's
// frame; the collision detector (collision.h) turns touching pairs into contact points.
//
//   type     parameters                        geometry (shape frame)
//   plane    normal (body frame)               the half space below the plane through
//                                              `position` with that normal; static bodies only
//   sphere   radius                            ball about the origin
//   capsule  radius, half_length               segment from -half_length to +half_length on z,
//                                              swept by the radius (half_length excludes the caps)
//   box      half_extents                      [-hx, hx] x [-hy, hy] x [-hz, hz]
//   cylinder radius, half_length               the solid cylinder about z, z in [-half_length,
//                                              half_length]
//   ellipsoid half_extents (its semi-axes)     (x/hx)^2 + (y/hy)^2 + (z/hz)^2 <= 1
//   convex   hull (shared, immutable)          the convex polytope of hull->vertices (a mesh's
//                                              convex hull: MuJoCo collides meshes by it)
//   heightfield field (shared, immutable)      the grid's surface z = h(x, y) over [-hx, hx] x
//                                              [-hy, hy] and the solid below it down to
//                                              -field->base; static bodies only
//
// Convex and heightfield shapes carry data that a scene file cannot hold (MJCF models make
// them); their data is shared, so copying a mechanism copies a pointer.
//
// Pair rules (as Box2D mixes them): friction sqrt(mu_a mu_b), restitution max(e_a, e_b); two
// shapes may touch when (a.contype & b.conaffinity) || (b.contype & a.conaffinity) (MuJoCo's
// filter); shapes of one body never touch, nor do two bodies joined by a constraint unless that
// constraint says `collide`.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ldlpgs {

enum class ShapeType { plane, sphere, capsule, box, cylinder, ellipsoid, convex, heightfield };
const char* to_string(ShapeType type);
bool shape_type_from_string(std::string_view name, ShapeType* type);  // false: unknown name

// A convex polytope in its shape frame: its vertices and triangular faces with their outward
// planes (coplanar triangles stay apart: MuJoCo's hulls are triangulated).
struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> faces;  // counter-clockwise seen from outside (size planes)
  std::vector<Eigen::Vector4d> planes;    // each face as n . x <= d, stored (n, d), n unit
};
// The hull of these vertices with these triangles (a hull's, as MuJoCo's compiler gives them),
// each triangle turned to face away from the vertices' centroid and given its plane; triangles
// without area are left out. Whether the result is a convex polytope is shape_problem's check.
ConvexHull make_convex_hull(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> faces);

// Heights on a regular grid in its shape frame, MuJoCo's hfield layout: sample (r, c) at
// x = -half_x + c 2 half_x / (cols - 1), y = -half_y + r 2 half_y / (rows - 1), height z =
// heights[r cols + c] (m); the solid reaches down to z = -base.
struct HeightField {
  int rows = 0, cols = 0;           // at least 2 each
  double half_x = 0, half_y = 0;    // m
  double base = 0;                  // m, > 0: the depth of the solid below z = 0
  std::vector<double> heights;      // (size rows cols)
};

struct Shape {
  ShapeType type = ShapeType::sphere;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // body frame (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // shape -> body frame (unused by a plane)
  double radius = 0;                                                // sphere, capsule, cylinder (m)
  double half_length = 0;                                           // capsule, cylinder (m)
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();           // box, ellipsoid (m)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();                // plane, body frame (unit after checks)
  double friction = 0.5;                                            // Coulomb mu, >= 0
  double restitution = 0;                                           // [0, 1]
  uint32_t contype = 1, conaffinity = 1;                            // the pair filter above
  std::shared_ptr<const ConvexHull> hull;                           // convex
  std::shared_ptr<const HeightField> field;                         // heightfield
};

// What is wrong with `shape` on a body (static or not), one phrase ("radius -1 is not > 0", "a
// plane on a dynamic body"), or empty when nothing is: the check every reader and
// Simulation::add_shape make. Lengths must lie in (0, 1e9] m (MechanismRanges), a normal
// must be finite and not shorter than 1e-12, friction finite and >= 0, restitution in [0, 1];
// a convex hull needs 4 or more vertices within 1e9 m, every one behind every face's plane
// (within 1e-4 of the hull's size) and a volume; a heightfield a grid of at least 2 x 2 finite
// heights within 1e9 m, on a static body.
std::string shape_problem(const Shape& shape, bool body_is_static);

double combined_friction(const Shape& a, const Shape& b);
double combined_restitution(const Shape& a, const Shape& b);
bool may_collide(const Shape& a, const Shape& b);

}  // namespace ldlpgs
