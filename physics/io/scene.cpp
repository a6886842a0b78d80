// Scene files. The format (orientation is [w, x, y, z]; anchors and axes are world frame at the
// initial pose):
//   {"name": "...", "gravity": [0, -9.81, 0], "timestep": 0.01,
//    "bodies": [{"name": "b1", "mass": 1, "inertia": [Ix, Iy, Iz], "position": [x, y, z],
//                "orientation": [w, x, y, z], "linear_velocity": [..], "angular_velocity": [..],
//                "force": [fx, fy, fz], "torque": [tx, ty, tz], "shapes": [SHAPE, ..]},
//               {"name": "ground", "static": true, "position": [x, y, z], "orientation": [..],
//                "shapes": [SHAPE, ..]}],
//    "constraints": [{"type": "ball" | "hinge" | "prismatic" | "cylindrical" | "weld",
//                     "bodies": ["a", "b"], "anchor": [x, y, z], "axis": [x, y, z], "collide": false},
//                    {"type": "rod" | "rope", "bodies": ["a", "b"], "anchors": [[..], [..]], "length": l},
//                    {"type": "angular_limit", "bodies": ["a", "b"], "axis": [..], "min": lo, "max": hi},
//                    {"type": "positional_limit", "bodies": ["a", "b"], "anchor": [..], "axis": [..],
//                     "min": lo, "max": hi}]}
// Optional: the scene's name (default: the file's stem), gravity and timestep (the Mechanism
// defaults), constraints (none), a body's orientation (identity) and velocities (zero), the axis
// of a ball (unused) and of a weld (x), the length of a rod or rope (the anchors' initial
// distance), a body's force and torque (zero): a constant load besides gravity, applied every
// step, a force through the centre of mass (N) and a torque (N m), world frame
// (RigidBody::applied_force, applied_torque). A static body has only name, static, position and
// orientation (a force or torque on it is refused: it never moves). Every other key is refused,
// so that a typo ("positon") is never silently a default.
// A body's collision shapes (physics/shape.h), each SHAPE one of
//   {"type": "sphere", "radius": r}
//   {"type": "capsule", "radius": r, "half_length": h}      axis: the shape's z; h excludes the caps
//   {"type": "box", "half_extents": [hx, hy, hz]}
//   {"type": "plane", "normal": [x, y, z]}                   static bodies only; through `position`
// with, for all, "position": [x, y, z] and (but a plane) "orientation": [w, x, y, z], the pose in
// the body frame (default: the body's own), and "friction" (0.5), "restitution" (0), "contype"
// and "conaffinity" (1: integers in [0, 2^32 - 1]). A type's own keys are required, another
// type's refused; the values must pass shape_problem; a plane's normal (body frame) is normalized
// after that check. A constraint's "collide" (default false): whether the shapes of the two
// bodies it joins touch each other.
#include "ldlpgs/physics/io/scene.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <istream>
#include <set>
#include <span>
#include <streambuf>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

using nlohmann::json;

namespace {

// Axes, quaternions and rod directions shorter than this are refused: they have no direction.
constexpr double kTiny = 1e-12;

std::string format_vector(std::span<const double> v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) {
    if (i) s += ", ";
    s += format_number(v[i]);
  }
  s += "]";
  return s;
}

// A name in quotes, escaped as JSON: one line of printable ASCII whatever it holds (ensure_ascii:
// DEL and non-ASCII as \uXXXX, invalid UTF-8 as \ufffd; they went in raw before), and at most
// 48 bytes of it, then "..." (a 100 KB unknown key must not make a 100 KB message).
std::string in_quotes(std::string_view s) {
  constexpr size_t kMax = 48;
  std::string quoted = json(std::string(s.substr(0, kMax))).dump(-1, ' ', true, json::error_handler_t::replace);
  if (s.size() > kMax) quoted += "...";
  return quoted;
}

// A JSON value as it appears in a message: one line, at most 60 characters, cut with "...".
// Written with an explicit stack and a budget, not nlohmann's dump, which recurses on the depth
// and prints everything: a 8 KB scene of 4000 nested arrays would overflow the stack in this
// error path.
std::string describe(const json& v) {
  constexpr size_t kMax = 60;
  std::string s;
  std::vector<std::pair<const json*, json::const_iterator>> open;  // containers being written
  auto write = [&](const json& x) {
    if (x.is_array() || x.is_object()) {
      s += x.is_array() ? "[" : "{";
      open.emplace_back(&x, x.cbegin());
    } else if (x.is_string()) {
      s += in_quotes(std::string_view(x.get_ref<const std::string&>()).substr(0, kMax));
    } else {
      s += x.dump(-1, ' ', false, json::error_handler_t::replace);  // a scalar: short
    }
  };
  write(v);
  while (!open.empty() && s.size() <= kMax) {
    const json* container = open.back().first;
    const json::const_iterator it = open.back().second;
    if (it == container->cend()) {
      s += container->is_array() ? "]" : "}";
      open.pop_back();
      continue;
    }
    if (it != container->cbegin()) s += ",";  // compact, as nlohmann's dump(-1) writes it
    if (container->is_object()) {
      s += in_quotes(it.key());
      s += ":";
    }
    ++open.back().second;
    write(*it);
  }
  if (s.size() > kMax) {
    s.resize(kMax - 3);
    s += "...";
  }
  return s;
}

// One object of the file (the scene, a body, a constraint) and how messages name it.
class Entry {
 public:
  Entry(const std::string& source, std::string label, const json& value)
      : source_(source), label_(std::move(label)), value_(value) {}

  void append_to_label(const std::string& s) { label_ += s; }

  // An entry inside this one ("bodies[2] (\"wheel\"): shapes[0]").
  Entry child(const std::string& label, const json& value) const { return Entry(source_, cat(label_, ": ", label), value); }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(cat(source_, ": ", label_, label_.empty() ? "" : ": ", problem));
  }

  void require_object(const char* what) const {
    if (!value_.is_object()) fail(cat(what, " must be a JSON object, got ", describe(value_)));
  }

  // Refuses any key not in `keys`; `whose` says for what kind of entry they are the keys.
  void allow_only(std::initializer_list<std::string_view> keys, const std::string& whose) const {
    allow_only(std::span<const std::string_view>(keys.begin(), keys.size()), whose);
  }
  void allow_only(std::span<const std::string_view> keys, const std::string& whose) const {
    for (auto it = value_.begin(); it != value_.end(); ++it) {
      if (std::find(keys.begin(), keys.end(), it.key()) != keys.end()) continue;
      std::string problem = cat("unknown key ", in_quotes(it.key()), " (", whose, " has:");
      for (auto k = keys.begin(); k != keys.end(); ++k) {
        problem += k == keys.begin() ? " " : ", ";
        problem += *k;
      }
      fail(problem + ")");
    }
  }

  bool has(const char* key) const { return value_.contains(key); }

  const json& required(const char* key) const {
    const auto it = value_.find(key);
    if (it == value_.end()) fail(cat("missing ", in_quotes(key)));
    return *it;
  }

  std::string string(const char* key) const {
    const json& v = required(key);
    if (!v.is_string()) fail(std::string(key) + " must be a string, got " + describe(v));
    return v.get<std::string>();
  }

  bool boolean_or(const char* key, bool fallback) const {
    if (!has(key)) return fallback;
    const json& v = required(key);
    if (!v.is_boolean()) fail(std::string(key) + " must be true or false, got " + describe(v));
    return v.get<bool>();
  }

  double number(const char* key) const { return number_value(required(key), key); }

  uint32_t uint32(const char* key) const {
    const json& v = required(key);
    if (!v.is_number_unsigned() || v.get<uint64_t>() > UINT32_MAX)
      fail(cat(key, " must be an integer in [0, 4294967295], got ", describe(v)));
    return static_cast<uint32_t>(v.get<uint64_t>());
  }

  double positive(const char* key) const {
    const double x = number(key);
    if (!(x > 0)) fail(std::string(key) + " must be positive, got " + format_number(x));
    return x;
  }

  // n finite numbers
  template <int n>
  Eigen::Matrix<double, n, 1> numbers(const json& v, const std::string& what) const {
    if (!v.is_array() || v.size() != static_cast<size_t>(n) ||
        !std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
      fail(cat(what, " must be an array of ", std::to_string(n), " numbers, got ", describe(v)));
    Eigen::Matrix<double, n, 1> out;
    for (int i = 0; i < n; ++i) out[i] = v[i].get<double>();
    if (!out.allFinite()) fail(what + " must be finite, got " + format_vector({out.data(), static_cast<size_t>(n)}));
    return out;
  }

  Eigen::Vector3d vector(const char* key) const { return numbers<3>(required(key), key); }

  Eigen::Vector3d positive_vector(const char* key) const {
    const Eigen::Vector3d v = vector(key);
    if (!(v.minCoeff() > 0)) fail(std::string(key) + " must be positive, got " + format_vector({v.data(), 3}));
    return v;
  }

  Eigen::Vector3d axis(const char* key) const {
    const Eigen::Vector3d v = vector(key);
    if (!(v.stableNorm() >= kTiny))
      fail(std::string(key) + " must be a non-zero vector, got " + format_vector({v.data(), 3}));
    return v;
  }

  Eigen::Quaterniond orientation(const char* key) const {
    const Eigen::Vector4d wxyz = numbers<4>(required(key), key);
    const double norm = wxyz.stableNorm();
    if (!(norm >= kTiny))
      fail(std::string(key) + " must be a non-zero quaternion [w, x, y, z], got " + format_vector({wxyz.data(), 4}));
    return Eigen::Quaterniond(wxyz[0] / norm, wxyz[1] / norm, wxyz[2] / norm, wxyz[3] / norm);
  }

 private:
  double number_value(const json& v, const std::string& what) const {
    if (!v.is_number()) fail(what + " must be a number, got " + describe(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(what + " must be finite, got " + format_number(x));
    return x;
  }

  const std::string& source_;
  std::string label_;
  const json& value_;
};

// The keys of a shape of `type` besides the common ones, all required (physics/shape.h).
std::vector<std::string_view> own_shape_keys(ShapeType type) {
  switch (type) {
    case ShapeType::plane: return {"normal"};
    case ShapeType::sphere: return {"radius"};
    case ShapeType::capsule: return {"radius", "half_length"};
    case ShapeType::box:
    case ShapeType::ellipsoid: return {"half_extents"};
    case ShapeType::cylinder: return {"radius", "half_length"};
    case ShapeType::convex:
    case ShapeType::heightfield: break;  // refused by parse_shape: their data has no scene-file form
  }
  return {};
}

// One of a body's "shapes" (the format above), checked by shape_problem.
Shape parse_shape(const Entry& e, bool body_is_static) {
  e.require_object("a shape");
  const std::string type_name = e.string("type");
  Shape s;
  if (!shape_type_from_string(type_name, &s.type))
    e.fail(cat("unknown shape type ", in_quotes(type_name), " (known: plane, sphere, capsule, box, cylinder, ellipsoid)"));
  if (s.type == ShapeType::convex || s.type == ShapeType::heightfield)
    e.fail(cat("a ", type_name, " shape has no scene-file form (its vertices or grid come from MJCF models)"));
  std::vector<std::string_view> keys = {"type", "position", "friction", "restitution", "contype", "conaffinity"};
  if (s.type != ShapeType::plane) keys.push_back("orientation");  // a plane's is its normal
  const std::vector<std::string_view> own = own_shape_keys(s.type);
  keys.insert(keys.end(), own.begin(), own.end());
  e.allow_only(keys, cat("a ", type_name, " shape"));
  if (e.has("position")) s.position = e.vector("position");
  if (e.has("orientation")) s.orientation = e.orientation("orientation");
  if (e.has("friction")) s.friction = e.number("friction");
  if (e.has("restitution")) s.restitution = e.number("restitution");
  if (e.has("contype")) s.contype = e.uint32("contype");
  if (e.has("conaffinity")) s.conaffinity = e.uint32("conaffinity");
  switch (s.type) {
    case ShapeType::plane: s.normal = e.vector("normal"); break;
    case ShapeType::capsule:
    case ShapeType::cylinder: s.half_length = e.number("half_length"); [[fallthrough]];
    case ShapeType::sphere: s.radius = e.number("radius"); break;
    case ShapeType::box:
    case ShapeType::ellipsoid: s.half_extents = e.vector("half_extents"); break;
    case ShapeType::convex:
    case ShapeType::heightfield: break;  // (refused above)
  }
  const std::string problem = shape_problem(s, body_is_static);
  if (!problem.empty()) e.fail(problem);
  s.normal.normalize();  // the check above bounds its length away from 0
  return s;
}

std::vector<Shape> parse_shapes(const Entry& body, const json& shapes, bool body_is_static) {
  if (!shapes.is_array()) body.fail(cat("shapes must be an array, got ", describe(shapes)));
  std::vector<Shape> out;
  for (size_t i = 0; i < shapes.size(); ++i)
    out.push_back(parse_shape(body.child(cat("shapes[", std::to_string(i), "]"), shapes[i]), body_is_static));
  return out;
}

// The body's data but its name (read first, to name the entry in messages).
void parse_body_data(const Entry& e, RigidBody* b) {
  b->is_static = e.boolean_or("static", false);
  if (b->is_static) {
    for (const char* load : {"force", "torque"})
      if (e.has(load)) e.fail(cat("a static body cannot carry a ", load, " (it never moves)"));
    e.allow_only({"name", "static", "position", "orientation", "shapes"}, "a static body");
  } else {
    e.allow_only({"name", "static", "mass", "inertia", "position", "orientation", "linear_velocity",
                  "angular_velocity", "force", "torque", "shapes"},
                 "a body");
    b->mass = e.positive("mass");
    b->inertia = e.positive_vector("inertia");
    if (e.has("linear_velocity")) b->linear_velocity = e.vector("linear_velocity");
    if (e.has("angular_velocity")) b->angular_velocity = e.vector("angular_velocity");
    if (e.has("force")) b->applied_force = e.vector("force");
    if (e.has("torque")) b->applied_torque = e.vector("torque");
  }
  b->position = e.vector("position");
  if (e.has("orientation")) b->orientation = e.orientation("orientation");
  if (e.has("shapes")) b->shapes = parse_shapes(e, e.required("shapes"), b->is_static);
}

// The two endpoints of a rod or rope.
std::pair<Eigen::Vector3d, Eigen::Vector3d> parse_anchors(const Entry& e) {
  const json& v = e.required("anchors");
  if (!v.is_array() || v.size() != 2) e.fail(cat("anchors must be an array of 2 points [x, y, z], got ", describe(v)));
  const Eigen::Vector3d p = e.numbers<3>(v[0], "anchors[0]"), q = e.numbers<3>(v[1], "anchors[1]");
  if (!((p - q).stableNorm() >= kTiny))
    e.fail(cat("anchors coincide (distance ", format_number((p - q).norm()), " m): a rod or rope needs a direction"));
  return {p, q};
}

void check_limit_range(const Entry& e, double min, double max) {
  if (min > max) e.fail(cat("min (", format_number(min), ") exceeds max (", format_number(max), ")"));
}

Constraint parse_constraint(const Entry& e, const Mechanism& m,
                            const std::unordered_map<std::string, int>& index) {
  const std::string type_name = e.string("type");
  ConstraintType type;
  if (!constraint_type_from_string(type_name, &type)) {
    e.fail(cat("unknown constraint type ", in_quotes(type_name),
               " (known: ball, hinge, prismatic, cylindrical, weld, rod, rope, angular_limit, positional_limit)"));
  }
  const std::string whose = cat("a ", type_name, " constraint");
  switch (type) {
    case ConstraintType::ball:
    case ConstraintType::weld:
    case ConstraintType::hinge:
    case ConstraintType::prismatic:
    case ConstraintType::cylindrical: e.allow_only({"type", "bodies", "anchor", "axis", "collide"}, whose); break;
    case ConstraintType::rod:
    case ConstraintType::rope: e.allow_only({"type", "bodies", "anchors", "length", "collide"}, whose); break;
    case ConstraintType::angular_limit: e.allow_only({"type", "bodies", "axis", "min", "max", "collide"}, whose); break;
    case ConstraintType::positional_limit:
      e.allow_only({"type", "bodies", "anchor", "axis", "min", "max", "collide"}, whose);
      break;
    case ConstraintType::joint_set:
    case ConstraintType::coordinate_limit:
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: e.fail(cat(whose, " comes from MJCF models only (a scene file has no joint sets)"));
  }

  const json& names = e.required("bodies");
  if (!names.is_array() || names.size() != 2 || !names[0].is_string() || !names[1].is_string())
    e.fail(cat("bodies must be an array of 2 body names, got ", describe(names)));
  int ids[2];
  for (int k = 0; k < 2; ++k) {
    const auto it = index.find(names[k].get<std::string>());
    if (it == index.end()) e.fail(cat("unknown body ", in_quotes(names[k].get<std::string>())));
    ids[k] = it->second;
  }
  const int ia = ids[0], ib = ids[1];
  if (ia == ib)
    e.fail(cat("a constraint must join two different bodies, got ", in_quotes(m.bodies[ia].name), " twice"));
  const RigidBody &a = m.bodies[ia], &b = m.bodies[ib];
  if (a.is_static && b.is_static)
    e.fail(cat("constrains two static bodies (", in_quotes(a.name), ", ", in_quotes(b.name), "): it would do nothing"));

  switch (type) {
    case ConstraintType::ball: {
      const Eigen::Vector3d anchor = e.vector("anchor");
      if (e.has("axis")) e.axis("axis");  // allowed (a ball has no axis), but still checked
      return make_ball(ia, a, ib, b, anchor);
    }
    case ConstraintType::weld:
    case ConstraintType::hinge:
    case ConstraintType::prismatic:
    case ConstraintType::cylindrical: {
      const Eigen::Vector3d anchor = e.vector("anchor");
      const Eigen::Vector3d axis =
          type == ConstraintType::weld && !e.has("axis") ? Eigen::Vector3d::UnitX() : e.axis("axis");
      return make_axial(type, ia, a, ib, b, anchor, axis);
    }
    case ConstraintType::rod:
    case ConstraintType::rope: {
      const auto [p, q] = parse_anchors(e);
      const double length = e.has("length") ? e.positive("length") : -1.0;
      return make_distance(type, ia, a, ib, b, p, q, length);
    }
    case ConstraintType::angular_limit: {
      const Eigen::Vector3d axis = e.axis("axis");
      const double min = e.number("min"), max = e.number("max");
      check_limit_range(e, min, max);
      return make_angular_limit(ia, a, ib, b, axis, min, max);
    }
    case ConstraintType::positional_limit: {
      const Eigen::Vector3d anchor = e.vector("anchor");
      const Eigen::Vector3d axis = e.axis("axis");
      const double min = e.number("min"), max = e.number("max");
      check_limit_range(e, min, max);
      return make_positional_limit(ia, a, ib, b, anchor, axis, min, max);
    }
    case ConstraintType::joint_set:
    case ConstraintType::coordinate_limit:
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor: break;  // refused above
  }
  e.fail("unhandled constraint type");  // unreachable: the switch covers every type
}

const json& array_of(const Entry& e, const json& v, const char* key) {
  if (!v.is_array()) e.fail(std::string(key) + " must be an array, got " + describe(v));
  return v;
}

}  // namespace

Mechanism parse_scene(const json& scene, const std::string& file) {
  const std::string source = printable(file);  // as messages name the file: one printable line
  const Entry top(source, "", scene);
  top.require_object("the scene");
  top.allow_only({"name", "gravity", "timestep", "bodies", "constraints"}, "a scene");
  Mechanism m;
  m.name = top.has("name") ? top.string("name") : std::filesystem::path(file).stem().string();
  if (top.has("gravity")) m.gravity = top.vector("gravity");
  if (top.has("timestep")) m.timestep = top.positive("timestep");

  const json& bodies = array_of(top, top.required("bodies"), "bodies");
  std::unordered_map<std::string, int> index;  // body name -> index
  for (size_t i = 0; i < bodies.size(); ++i) {
    Entry e(source, cat("bodies[", std::to_string(i), "]"), bodies[i]);
    e.require_object("a body");
    RigidBody b;
    b.name = e.string("name");
    if (b.name.empty()) e.fail("name must not be empty");
    e.append_to_label(cat(" (", in_quotes(b.name), ")"));
    const auto [it, inserted] = index.emplace(b.name, static_cast<int>(i));
    if (!inserted) e.fail(cat("duplicate body name (also bodies[", std::to_string(it->second), "])"));
    parse_body_data(e, &b);
    m.add_body(std::move(b));
  }

  if (top.has("constraints")) {
    const json& constraints = array_of(top, top.required("constraints"), "constraints");
    for (size_t i = 0; i < constraints.size(); ++i) {
      const Entry e(source, cat("constraints[", std::to_string(i), "]"), constraints[i]);
      e.require_object("a constraint");
      Constraint c = parse_constraint(e, m, index);
      c.collide = e.boolean_or("collide", false);
      m.add_constraint(std::move(c));
    }
  }
  check_ranges(m, file);  // (which quotes it through printable())
  return m;
}

namespace {

// Refuses duplicate keys, which nlohmann-json would silently resolve to the last one. The
// parser's callback sees the structure as it is read: a stack of the containers open, each with
// the child being read (an array's index, an object's key), names where the duplicate is.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& source) : source_(source) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    using E = json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
      case E::value:
        if (!stack_.empty() && stack_.back().is_array) ++stack_.back().index;
        if (event != E::value) stack_.push_back({event == E::array_start, -1, {}, {}});
        break;
      case E::key: {
        Open& top = stack_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          const std::string where = path();
          throw InputError(cat(source_, ": ", where, where.empty() ? "" : ": ", "duplicate key ", in_quotes(top.key)));
        }
        break;
      }
      case E::object_end:
      case E::array_end: stack_.pop_back(); break;
    }
    return true;
  }

 private:
  struct Open {
    bool is_array;
    int index;                   // arrays: the element being read
    std::string key;             // objects: the member being read
    std::set<std::string> keys;  // objects: the keys seen
  };

  // Where the innermost open object is, as messages name entries ("bodies[2]"): keys escaped
  // (printable()), and cut after 200 characters (the depth is the input's).
  std::string path() const {
    constexpr size_t kMax = 200;
    std::string p;
    for (size_t i = 0; i + 1 < stack_.size(); ++i) {
      if (p.size() > kMax) {
        p += "...";
        break;
      }
      if (stack_[i].is_array) {
        p += cat("[", std::to_string(stack_[i].index), "]");
      } else {
        if (!p.empty()) p += ".";
        p += printable(stack_[i].key, 48);
      }
    }
    return p;
  }

  const std::string& source_;
  std::vector<Open> stack_;
};

// The file as the parser reads it, a chunk at a time (FileChunks), each chunk kept in `text` for
// the messages' line and column: the parser stops at the first byte that cannot be JSON, having
// read one chunk past it at most.
class ChunkReader : public std::streambuf {
 public:
  ChunkReader(FileChunks& file, std::string* text) : file_(file), text_(text) {}

 protected:
  int_type underflow() override {
    const size_t old = text_->size();
    if (!file_.append_to(*text_)) return traits_type::eof();
    char* const begin = text_->data() + old;
    setg(begin, begin, text_->data() + text_->size());
    return traits_type::to_int_type(*begin);
  }

 public:
  // Bytes the parser has taken (read past by at most a chunk in `text`).
  size_t consumed() const { return text_->size() - static_cast<size_t>(egptr() - gptr()); }

 private:
  FileChunks& file_;
  std::string* text_;
};

}  // namespace

Mechanism load_scene(const std::string& file) {
  FileChunks chunked(file);
  const std::string& path = chunked.name();  // (through printable(): messages stay one line)
  std::string text;  // what the parser has read, and at most a chunk more
  ChunkReader reader(chunked, &text);
  std::istream chunks(&reader);

  // "path:line:column" of the character at 0-based offset `at`
  auto where = [&](size_t at) {
    at = std::min(at, text.size());
    const size_t line = 1 + std::count(text.begin(), text.begin() + at, '\n');
    const size_t line_start = at == 0 ? std::string::npos : text.rfind('\n', at - 1);
    const size_t column = line_start == std::string::npos ? at + 1 : at - line_start;
    return cat(path, ":", std::to_string(line), ":", std::to_string(column));
  };
  json scene;
  try {
    scene = json::parse(chunks, DuplicateKeyCheck(path));
  } catch (const json::parse_error& e) {
    // e.byte: 1-based offset of the character the parser stopped at.
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line L, column C: what"
    // (its "last read: '...'" quotes the input: a 1 MB token made a 1 MB message)
    std::string what = e.what();
    const size_t colon = what.find(": ", what.find("parse error"));
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw InputError(cat(where(e.byte == 0 ? 0 : e.byte - 1), ": invalid JSON: ", printable(what, 200)));
  } catch (const json::out_of_range& e) {
    // 406: a number beyond the range of a double ("number overflow parsing '1e400'"), which
    // carries no position: the number's first occurrence in the text gives it
    const std::string what = e.what();
    const size_t open = what.find("parsing '"), close = what.rfind('\'');
    if (e.id == 406 && open != std::string::npos && close > open + 9) {
      const std::string number = what.substr(open + 9, close - open - 9);
      throw InputError(cat(where(text.find(number)), ": number ", printable(number, 40), " is out of the range of a double"));
    }
    throw InputError(cat(path, ": invalid JSON: ", printable(what, 200)));
  } catch (const json::exception& e) {
    throw InputError(cat(path, ": invalid JSON: ", printable(e.what(), 200)));
  }
  // nlohmann-json takes a NUL byte for the end of the input, so that a scene followed by one and
  // anything at all (a NUL-padded file, `cat scene.json /dev/zero`) was accepted, the rest unread.
  if (reader.consumed() > 0 && text[reader.consumed() - 1] == '\0') {
    throw InputError(cat(where(reader.consumed() - 1), ": invalid JSON: a NUL byte after the scene"));
  }
  return parse_scene(scene, file);
}

namespace {

// x + 0.0 writes -0.0 as 0.0 (rounding to nearest): the same value, a tidier file
json to_json(const Eigen::Vector3d& v) { return json::array({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0}); }
json to_json(const Eigen::Quaterniond& q) { return json::array({q.w() + 0.0, q.x() + 0.0, q.y() + 0.0, q.z() + 0.0}); }

// Every key of the shape, defaults included: a shape is a line of the file anyway.
json to_json(const Shape& s) {
  json o = json::object();
  o["type"] = to_string(s.type);
  o["position"] = to_json(s.position);
  switch (s.type) {
    case ShapeType::plane: o["normal"] = to_json(s.normal); break;
    case ShapeType::capsule:
    case ShapeType::cylinder: o["half_length"] = s.half_length; [[fallthrough]];
    case ShapeType::sphere: o["radius"] = s.radius; break;
    case ShapeType::box:
    case ShapeType::ellipsoid: o["half_extents"] = to_json(s.half_extents); break;
    case ShapeType::convex:
    case ShapeType::heightfield: break;  // (refused by scene_to_json)
  }
  if (s.type != ShapeType::plane) o["orientation"] = to_json(s.orientation.normalized());
  o["friction"] = s.friction;
  o["restitution"] = s.restitution;
  o["contype"] = s.contype;
  o["conaffinity"] = s.conaffinity;
  return o;
}

// Inline JSON with the keys in the order the format lists them (nlohmann sorts them).
int key_rank(const std::string& key) {
  static constexpr std::string_view order[] = {
      "name", "static", "type", "bodies", "mass", "inertia", "position", "orientation", "linear_velocity",
      "angular_velocity", "force", "torque", "shapes", "anchor", "anchors", "axis", "length", "min", "max",
      "collide", "radius", "half_length", "half_extents", "normal", "friction", "restitution", "contype",
      "conaffinity"};
  const auto it = std::find(std::begin(order), std::end(order), key);
  return static_cast<int>(it - std::begin(order));
}

void write_inline(const json& v, std::string* out) {
  if (v.is_object()) {
    std::vector<std::string> keys;
    for (auto it = v.begin(); it != v.end(); ++it) keys.push_back(it.key());
    std::stable_sort(keys.begin(), keys.end(),
                     [](const std::string& a, const std::string& b) { return key_rank(a) < key_rank(b); });
    *out += "{";
    for (size_t i = 0; i < keys.size(); ++i) {
      if (i) *out += ", ";
      *out += in_quotes(keys[i]);
      *out += ": ";
      write_inline(v[keys[i]], out);
    }
    *out += "}";
  } else if (v.is_array()) {
    *out += "[";
    for (size_t i = 0; i < v.size(); ++i) {
      if (i) *out += ", ";
      write_inline(v[i], out);
    }
    *out += "]";
  } else {
    *out += v.dump(-1, ' ', false, json::error_handler_t::replace);
  }
}

}  // namespace

json scene_to_json(const Mechanism& m) {
  if (!m.dofs.empty() || !m.actuators.empty() || m.fluid.active())
    throw InputError(cat(m.name, ": joint dynamics, actuators and fluid forces (from an MJCF model) have no scene-file form"));
  json scene = json::object();
  scene["name"] = m.name;
  scene["gravity"] = to_json(m.gravity);
  scene["timestep"] = m.timestep;
  json bodies = json::array();
  for (const RigidBody& b : m.bodies) {
    json o = json::object();
    o["name"] = b.name;
    if (b.is_static) {
      o["static"] = true;
    } else {
      o["mass"] = b.mass;
      o["inertia"] = to_json(b.inertia);
    }
    o["position"] = to_json(b.position);
    o["orientation"] = to_json(b.orientation.normalized());
    if (!b.is_static) {
      // zero velocities are the default: left out to keep files short
      if (!b.linear_velocity.isZero(0)) o["linear_velocity"] = to_json(b.linear_velocity);
      if (!b.angular_velocity.isZero(0)) o["angular_velocity"] = to_json(b.angular_velocity);
      // so are zero loads
      if (!b.applied_force.isZero(0)) o["force"] = to_json(b.applied_force);
      if (!b.applied_torque.isZero(0)) o["torque"] = to_json(b.applied_torque);
    }
    if (!b.shapes.empty()) {  // none is the default
      json shapes = json::array();
      for (const Shape& s : b.shapes) {
        if (s.type == ShapeType::convex || s.type == ShapeType::heightfield)
          throw InputError(cat(m.name, ": body ", in_quotes(b.name), ": a ", to_string(s.type),
                               " shape (from an MJCF model) has no scene-file form"));
        shapes.push_back(to_json(s));
      }
      o["shapes"] = std::move(shapes);
    }
    bodies.push_back(std::move(o));
  }
  scene["bodies"] = std::move(bodies);

  json constraints = json::array();
  for (const Constraint& c : m.constraints) {
    const RigidBody &a = m.bodies[c.body_a], &b = m.bodies[c.body_b];
    json o = json::object();
    o["type"] = to_string(c.type);
    o["bodies"] = json::array({a.name, b.name});
    const Eigen::Vector3d anchor = a.to_world(c.anchor_a);
    const Eigen::Vector3d axis = a.orientation * c.frame_a.col(2);
    switch (c.type) {
      case ConstraintType::ball: o["anchor"] = to_json(anchor); break;
      case ConstraintType::hinge:
      case ConstraintType::prismatic:
      case ConstraintType::cylindrical:
      case ConstraintType::weld:
        o["anchor"] = to_json(anchor);
        o["axis"] = to_json(axis);
        break;
      case ConstraintType::rod:
      case ConstraintType::rope:
        o["anchors"] = json::array({to_json(anchor), to_json(b.to_world(c.anchor_b))});
        o["length"] = c.length;
        break;
      case ConstraintType::positional_limit: o["anchor"] = to_json(anchor); [[fallthrough]];
      case ConstraintType::angular_limit:
        o["axis"] = to_json(axis);
        o["min"] = c.min;
        o["max"] = c.max;
        break;
      case ConstraintType::joint_set:
      case ConstraintType::coordinate_limit:
      case ConstraintType::dof_drive:
      case ConstraintType::dof_motor:
        throw InputError(cat(m.name, ": ", constraint_label(m, static_cast<int>(&c - m.constraints.data())),
                             ": a joint set (from an MJCF model) has no scene-file form"));
    }
    if (c.collide) o["collide"] = true;  // false is the default
    constraints.push_back(std::move(o));
  }
  scene["constraints"] = std::move(constraints);
  return scene;
}

void save_scene(const Mechanism& m, const std::string& path) {
  const json scene = scene_to_json(m);
  // One line per body and per constraint: diffable, and readable for the scenes' sizes.
  std::string text = "{\n";
  for (const char* key : {"name", "gravity", "timestep"}) {
    text += "  ";
    text += in_quotes(key);
    text += ": ";
    write_inline(scene[key], &text);
    text += ",\n";
  }
  for (const char* key : {"bodies", "constraints"}) {
    const json& list = scene[key];
    text += "  ";
    text += in_quotes(key);
    text += ": [";
    for (size_t i = 0; i < list.size(); ++i) {
      text += i ? ",\n    " : "\n    ";
      write_inline(list[i], &text);
    }
    text += list.empty() ? "]" : "\n  ]";
    text += std::string_view(key) == "bodies" ? ",\n" : "\n";
  }
  text += "}\n";
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    throw InputError(cat(path, ": cannot write: ", std::strerror(errno)));
  }
}

}  // namespace ldlpgs
