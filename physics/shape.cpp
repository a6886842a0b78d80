// Shape names, the shape check and the pair rules (shape.h).
#include "ldlpgs/physics/shape.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ldlpgs/physics/mechanism.h"
#include "ldlpgs/physics/scene.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

namespace {
constexpr std::array<const char*, 4> kNames = {"plane", "sphere", "capsule", "box"};

// "" when x is a length in (0, coordinate_max] (min_zero: [0, ...]), else the phrase.
std::string length_problem(const char* what, double x, bool zero_allowed = false) {
  if ((zero_allowed ? x >= 0 : x > 0) && x <= MechanismRanges::coordinate_max) return "";
  std::string s = what;
  s += " ";
  s += format_number(x);
  s += zero_allowed ? " is not in [0, 1e9] m" : " is not in (0, 1e9] m";
  return s;
}
}  // namespace

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
    case ShapeType::box:
      for (int k = 0; k < 3; ++k) {
        std::string p = length_problem("half_extents component", s.half_extents[k]);
        if (!p.empty()) return p;
      }
      return "";
  }
  return "unknown shape type";
}

double combined_friction(const Shape& a, const Shape& b) { return std::sqrt(a.friction * b.friction); }
double combined_restitution(const Shape& a, const Shape& b) { return std::max(a.restitution, b.restitution); }
bool may_collide(const Shape& a, const Shape& b) {
  return (a.contype & b.conaffinity) != 0 || (b.contype & a.conaffinity) != 0;
}

}  // namespace ldlpgs
