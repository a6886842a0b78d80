// Shape names, the shape check and the pair rules (shape.h).
#include "ldlpgs/physics/shape.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

namespace {
constexpr std::array<const char*, 8> kNames = {"plane",    "sphere",    "capsule", "box",
                                               "cylinder", "ellipsoid", "convex",  "heightfield"};

// "" when x is a length in (0, coordinate_max] (min_zero: [0, ...]), else the phrase.
std::string length_problem(const char* what, double x, bool zero_allowed = false) {
  if ((zero_allowed ? x >= 0 : x > 0) && x <= MechanismRanges::coordinate_max) return "";
  std::string s = what;
  s += " ";
  s += format_number(x);
  s += zero_allowed ? " is not in [0, 1e9] m" : " is not in (0, 1e9] m";
  return s;
}
// "" when the hull is a convex polytope: 4 or more finite vertices within the ranges, faces
// of its vertices with unit normals, every vertex behind every face's plane (within rounding)
// and some vertex clearly behind one: a volume.
std::string hull_problem(const ConvexHull* hull) {
  if (!hull || hull->vertices.size() < 4 || hull->faces.size() < 4 || hull->planes.size() != hull->faces.size())
    return "a convex hull needs 4 or more vertices and faces";
  double size = 0;
  for (const Eigen::Vector3d& v : hull->vertices) {
    if (!(v.cwiseAbs().maxCoeff() <= MechanismRanges::coordinate_max)) return "a hull vertex is not within 1e9 m";
    size = std::max(size, v.cwiseAbs().maxCoeff());
  }
  const int n = static_cast<int>(hull->vertices.size());
  double thickest = 0;  // the largest distance of a vertex behind a face
  for (size_t f = 0; f < hull->faces.size(); ++f) {
    for (int v : hull->faces[f])
      if (v < 0 || v >= n) return "a hull face names a vertex it does not have";
    const Eigen::Vector4d& p = hull->planes[f];
    if (!(std::abs(p.head<3>().norm() - 1) <= 1e-9)) return "a hull face has no plane";
    for (const Eigen::Vector3d& v : hull->vertices) {
      const double behind = p[3] - p.head<3>().dot(v);
      // (1e-4 of its size: MuJoCo's qhull hull of mug.obj, 1873 vertices, has one 1.25e-6 m in
      // front of a face on a 0.076 m mesh, 1.6e-5 of it; a tighter check refused that model)
      if (!(behind >= -1e-4 * size)) return "the hull is not convex (a vertex is in front of a face)";
      thickest = std::max(thickest, behind);
    }
  }
  if (!(thickest > 1e-9 * size)) return "the hull has no volume";
  return "";
}

// "" when the grid has 2 x 2 or more finite heights within the ranges and positive sizes.
std::string field_problem(const HeightField* f) {
  if (!f || f->rows < 2 || f->cols < 2 || f->heights.size() != static_cast<size_t>(f->rows) * static_cast<size_t>(f->cols))
    return "a heightfield needs a grid of at least 2 x 2 heights";
  const std::pair<const char*, double> lengths[] = {{"half_x", f->half_x}, {"half_y", f->half_y}, {"base", f->base}};
  for (const auto& [what, x] : lengths) {
    std::string p = length_problem(what, x);
    if (!p.empty()) return p;
  }
  for (double h : f->heights)
    if (!(std::abs(h) <= MechanismRanges::coordinate_max)) return "a height " + format_number(h) + " is not within 1e9 m";
  return "";
}

}  // namespace

ConvexHull make_convex_hull(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> faces) {
  ConvexHull h;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : vertices) centroid += v;
  if (!vertices.empty()) centroid /= static_cast<double>(vertices.size());
  const int n = static_cast<int>(vertices.size());
  double size = 0;
  for (const Eigen::Vector3d& v : vertices) size = std::max(size, (v - centroid).norm());
  for (std::array<int, 3> f : faces) {
    if (f[0] < 0 || f[1] < 0 || f[2] < 0 || f[0] >= n || f[1] >= n || f[2] >= n) {
      h.faces.push_back(f);
      h.planes.emplace_back(0, 0, 0, 0);  // (refused by shape_problem)
      continue;
    }
    const Eigen::Vector3d &a = vertices[f[0]], &b = vertices[f[1]], &c = vertices[f[2]];
    Eigen::Vector3d normal = (b - a).cross(c - a);
    if (!(normal.norm() > 1e-12 * size * size)) continue;  // a triangle without area bounds nothing
    if (normal.dot(a - centroid) < 0) {
      std::swap(f[1], f[2]);
      normal = -normal;
    }
    normal.normalize();
    h.faces.push_back(f);
    h.planes.emplace_back(normal.x(), normal.y(), normal.z(), normal.dot(a));
  }
  h.vertices = std::move(vertices);
  return h;
}

const char* to_string(ShapeType type) { return kNames[static_cast<int>(type)]; }

bool shape_type_from_string(std::string_view name, ShapeType* type) {
  const auto it = std::find(kNames.begin(), kNames.end(), name);
  if (it == kNames.end()) return false;
  *type = static_cast<ShapeType>(it - kNames.begin());
  return true;
}

std::string shape_problem(const Shape& s, bool body_is_static) {
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(s.position[k]) <= MechanismRanges::coordinate_max)) return "position " + format_number(s.position[k]) + " is not within 1e9 m";
  const double qn = s.orientation.coeffs().norm();
  if (!std::isfinite(qn) || std::abs(qn - 1) > 1e-6) return "orientation's norm " + format_number(qn) + " is not 1";
  if (!(std::isfinite(s.friction) && s.friction >= 0)) return "friction " + format_number(s.friction) + " is not finite and >= 0";
  if (!(s.restitution >= 0 && s.restitution <= 1)) return "restitution " + format_number(s.restitution) + " is not in [0, 1]";
  switch (s.type) {
    case ShapeType::plane: {
      if (!body_is_static) return "a plane on a dynamic body (planes are static only)";
      const double n = s.normal.norm();
      if (!std::isfinite(n) || n < 1e-12) return "normal of length " + format_number(n) + " (finite and >= 1e-12 needed)";
      return "";
    }
    case ShapeType::sphere: return length_problem("radius", s.radius);
    case ShapeType::capsule: {
      std::string p = length_problem("radius", s.radius);
      return p.empty() ? length_problem("half_length", s.half_length, true) : p;
    }
    case ShapeType::cylinder: {
      std::string p = length_problem("radius", s.radius);
      return p.empty() ? length_problem("half_length", s.half_length) : p;
    }
    case ShapeType::box:
    case ShapeType::ellipsoid:
      for (int k = 0; k < 3; ++k) {
        std::string p = length_problem("half_extents component", s.half_extents[k]);
        if (!p.empty()) return p;
      }
      return "";
    case ShapeType::convex: return hull_problem(s.hull.get());
    case ShapeType::heightfield:
      if (!body_is_static) return "a heightfield on a dynamic body (heightfields are static only)";
      return field_problem(s.field.get());
  }
  return "unknown shape type";
}

double combined_friction(const Shape& a, const Shape& b) { return std::sqrt(a.friction * b.friction); }
double combined_restitution(const Shape& a, const Shape& b) { return std::max(a.restitution, b.restitution); }
bool may_collide(const Shape& a, const Shape& b) {
  return (a.contype & b.conaffinity) != 0 || (b.contype & a.conaffinity) != 0;
}

}  // namespace ldlpgs
