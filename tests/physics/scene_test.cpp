// Scene files: parse_scene against the values written in the file (defaults, normalisation, the
// builders' arguments), round trips through scene_to_json and through a file reproducing every
// body and every constraint's local data, and one named test per kind of bad input, each
// checking that the one-line message names the file and the entry.
#include "ldlpgs/physics/io/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "tests/support/bodies.h"
#include "tests/support/mechanism_compare.h"
#include "tests/support/bytes_read.h"
#include "tests/support/temp_files.h"

namespace ldlpgs {
namespace {

using nlohmann::json;
using testing::temp_file;
using testing::temp_path;
using testing::expect_same;
using testing::static_body;

const std::string kTestData = LDLPGS_TESTDATA;

RigidBody dynamic(const std::string& name, double mass, const Eigen::Vector3d& position,
                  const Eigen::Quaterniond& orientation) {
  RigidBody b;
  b.name = name;
  b.mass = mass;
  b.inertia = mass * Eigen::Vector3d(0.02, 0.03, 0.04);
  b.position = position;
  b.orientation = orientation.normalized();
  return b;
}

// Every constraint type, between bodies turned every which way, some moving, two static.
Mechanism every_type() {
  Mechanism m;
  m.name = "every type";
  m.gravity = Eigen::Vector3d(0.5, -9.81, 0.25);
  m.timestep = 1.0 / 240;
  RigidBody ground = static_body("ground", Eigen::Vector3d(0.1, 0.2, -0.3));
  ground.orientation = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  m.add_body(ground);
  for (int i = 0; i < 8; ++i) {
    RigidBody b = dynamic(std::string("b") + std::to_string(i), 1 + 0.5 * i,
                          Eigen::Vector3d(0.7 * i, 0.1 * i * i - 1, 0.3 * std::sin(i)),
                          Eigen::Quaterniond(1 + 0.1 * i, 0.3 * std::cos(i), -0.2 * i, 0.4));
    b.linear_velocity = Eigen::Vector3d(0.1 * i, -0.2, 0.3);
    b.angular_velocity = Eigen::Vector3d(-0.5, 0.25 * i, 1.5);
    m.add_body(b);
  }
  m.add_body(static_body("wall", Eigen::Vector3d(10, 0, 0)));
  auto mid = [&](int a, int b) { return (0.5 * (m.bodies[a].position + m.bodies[b].position)).eval(); };
  const Eigen::Vector3d axis(0.3, -1, 0.7);
  const auto& B = m.bodies;
  m.add_constraint(make_ball(0, B[0], 1, B[1], Eigen::Vector3d(0.1, 0, 0)));
  m.add_constraint(make_axial(ConstraintType::hinge, 1, B[1], 2, B[2], mid(1, 2), axis));
  m.add_constraint(make_axial(ConstraintType::prismatic, 2, B[2], 3, B[3], mid(2, 3), Eigen::Vector3d(0, 0, 2)));
  m.add_constraint(make_axial(ConstraintType::cylindrical, 3, B[3], 4, B[4], mid(3, 4), Eigen::Vector3d(1, 0, 0)));
  m.add_constraint(make_axial(ConstraintType::weld, 4, B[4], 5, B[5], mid(4, 5), Eigen::Vector3d(0, 1, 0)));
  m.add_constraint(make_distance(ConstraintType::rod, 5, B[5], 6, B[6], B[5].position, B[6].position + axis));
  m.add_constraint(make_distance(ConstraintType::rope, 6, B[6], 7, B[7], B[6].position, B[7].position, 3.5));
  m.add_constraint(make_angular_limit(1, B[1], 2, B[2], axis, -0.75, 1.25));
  m.add_constraint(make_positional_limit(2, B[2], 3, B[3], mid(2, 3), Eigen::Vector3d(0, 0, 2), -0.1, 0.3));
  m.add_constraint(make_distance(ConstraintType::rope, 8, B[8], 9, B[9], B[8].position, B[9].position));
  m.add_constraint(make_axial(ConstraintType::hinge, 9, B[9], 7, B[7], mid(7, 9), axis));
  return m;
}

// The message parse_scene throws for scene (a test failure if it does not throw).
std::string error_of(const json& scene) {
  try {
    parse_scene(scene, "scene.json");
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
    return message;
  }
  ADD_FAILURE() << scene.dump() << " was accepted";
  return {};
}

// Checks that parsing scene fails with "scene.json: ENTRY: ..." containing every one of words
// (entry empty: "scene.json: ...", a problem of the scene itself).
void expect_error(const json& scene, const std::string& entry, const std::vector<std::string>& words) {
  const std::string message = error_of(scene);
  std::string prefix = "scene.json: ";
  if (!entry.empty()) prefix += entry + ": ";
  EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
  for (const std::string& w : words)
    EXPECT_NE(message.find(w), std::string::npos) << "'" << w << "' not in: " << message;
}

// The same for a file, whose message starts with its path.
std::string file_error_of(const std::string& path) {
  try {
    load_scene(path);
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
    EXPECT_EQ(message.substr(0, path.size() + 1), path + ":") << message;
    return message;
  }
  ADD_FAILURE() << path << " was accepted";
  return {};
}

// A small valid scene the bad-input tests break one thing of: ground, b1, b2, wall.
json valid() {
  return json::parse(R"({
    "name": "valid", "gravity": [0, -9.81, 0], "timestep": 0.01,
    "bodies": [
      {"name": "ground", "static": true, "position": [0, 0, 0]},
      {"name": "b1", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": [0, -1, 0]},
      {"name": "b2", "mass": 2, "inertia": [0.2, 0.3, 0.4], "position": [1, -1, 0], "orientation": [1, 0, 0, 0],
       "linear_velocity": [0, 0, 1], "angular_velocity": [1, 0, 0]},
      {"name": "wall", "static": true, "position": [5, 0, 0], "orientation": [0, 0, 1, 0]}],
    "constraints": [
      {"type": "ball", "bodies": ["ground", "b1"], "anchor": [0, 0, 0]},
      {"type": "hinge", "bodies": ["b1", "b2"], "anchor": [0.5, -1, 0], "axis": [0, 0, 1]},
      {"type": "rope", "bodies": ["b2", "wall"], "anchors": [[1, -1, 0], [5, 0, 0]], "length": 5},
      {"type": "angular_limit", "bodies": ["b1", "b2"], "axis": [0, 0, 1], "min": -0.5, "max": 0.5},
      {"type": "positional_limit", "bodies": ["b1", "b2"], "anchor": [0.5, -1, 0], "axis": [1, 0, 0],
       "min": -0.1, "max": 0.1},
      {"type": "rod", "bodies": ["b1", "b2"], "anchors": [[0, -1, 0], [1, -1, 0]]},
      {"type": "weld", "bodies": ["b2", "wall"], "anchor": [3, 0, 0]}]})");
}

// ---- reading ----

TEST(Scene, ValidSceneReadsAsWritten) {
  const Mechanism m = parse_scene(valid(), "scene.json");
  EXPECT_EQ(m.name, "valid");
  EXPECT_EQ(m.timestep, 0.01);
  EXPECT_EQ(m.gravity, Eigen::Vector3d(0, -9.81, 0));
  ASSERT_EQ(m.bodies.size(), 4u);
  ASSERT_EQ(m.constraints.size(), 7u);
  EXPECT_TRUE(m.bodies[0].is_static);
  EXPECT_FALSE(m.bodies[1].is_static);
  EXPECT_EQ(m.bodies[2].inertia, Eigen::Vector3d(0.2, 0.3, 0.4));
  EXPECT_EQ(m.bodies[2].linear_velocity, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(m.bodies[2].angular_velocity, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(m.bodies[1].linear_velocity, Eigen::Vector3d::Zero());  // optional: zero
  EXPECT_EQ(m.bodies[3].orientation.coeffs(), Eigen::Quaterniond(0, 0, 1, 0).coeffs());  // [w, x, y, z]
  // each constraint as the builder makes it from the file's world data
  const auto& B = m.bodies;
  Mechanism expected = m;
  expected.constraints = {
      make_ball(0, B[0], 1, B[1], Eigen::Vector3d(0, 0, 0)),
      make_axial(ConstraintType::hinge, 1, B[1], 2, B[2], Eigen::Vector3d(0.5, -1, 0), Eigen::Vector3d(0, 0, 1)),
      make_distance(ConstraintType::rope, 2, B[2], 3, B[3], Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(5, 0, 0), 5),
      make_angular_limit(1, B[1], 2, B[2], Eigen::Vector3d(0, 0, 1), -0.5, 0.5),
      make_positional_limit(1, B[1], 2, B[2], Eigen::Vector3d(0.5, -1, 0), Eigen::Vector3d(1, 0, 0), -0.1, 0.1),
      make_distance(ConstraintType::rod, 1, B[1], 2, B[2], Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, -1, 0)),
      make_axial(ConstraintType::weld, 2, B[2], 3, B[3], Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(1, 0, 0))};
  expect_same(m, expected, 0);
  EXPECT_EQ(m.constraints[5].length, 1);  // a rod's length defaults to the anchors' distance
  // the weld without an axis takes x
  EXPECT_LE((B[2].orientation * m.constraints[6].frame_a.col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-15);
}

TEST(Scene, OptionalTopLevelKeysTakeTheMechanismDefaults) {
  json s = valid();
  s.erase("name");
  s.erase("gravity");
  s.erase("timestep");
  s.erase("constraints");
  const Mechanism m = parse_scene(s, "dir/bridge.json");
  EXPECT_EQ(m.name, "bridge");  // the file's stem
  EXPECT_EQ(m.gravity, Mechanism().gravity);
  EXPECT_EQ(m.timestep, Mechanism().timestep);
  EXPECT_TRUE(m.constraints.empty());
  EXPECT_EQ(m.bodies.size(), 4u);
}

TEST(Scene, QuaternionsAreNormalised) {
  json s = valid();
  s["bodies"][1]["orientation"] = {2, 0, 0, 0};
  s["bodies"][2]["orientation"] = {1, 2, -2, 4};  // |q| = 5
  const Mechanism m = parse_scene(s, "scene.json");
  EXPECT_EQ(m.bodies[1].orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  const Eigen::Quaterniond q = m.bodies[2].orientation;
  EXPECT_NEAR(q.w(), 0.2, 1e-15);
  EXPECT_NEAR(q.x(), 0.4, 1e-15);
  EXPECT_NEAR(q.y(), -0.4, 1e-15);
  EXPECT_NEAR(q.z(), 0.8, 1e-15);
}

TEST(Scene, BallAcceptsAnAxisAndIgnoresIt) {
  json s = valid();
  s["constraints"][0]["axis"] = {0, 1, 0};
  const Mechanism with_axis = parse_scene(s, "scene.json");
  expect_same(with_axis, parse_scene(valid(), "scene.json"), 0);
}

// valid() with a shape of each type: a plane and a box on the ground, a sphere with every
// default and a capsule with every key on b1, a box on b2; the hinge's bodies collide.
json with_shapes() {
  json s = valid();
  s["bodies"][0]["shapes"] = json::parse(R"([
      {"type": "plane", "position": [0, -2, 0], "normal": [0, 2, 0], "friction": 0.8, "restitution": 0.1},
      {"type": "box", "position": [3, -1.5, 0], "half_extents": [0.5, 0.25, 1], "contype": 2, "conaffinity": 6}])");
  s["bodies"][1]["shapes"] = json::parse(R"([
      {"type": "sphere", "radius": 0.3},
      {"type": "capsule", "position": [0.1, 0.2, -0.3], "orientation": [0.5, 0.5, -0.5, 0.5], "radius": 0.05,
       "half_length": 0.4, "friction": 0, "restitution": 1, "contype": 0, "conaffinity": 4294967295}])");
  s["bodies"][2]["shapes"] = json::parse(R"([{"type": "box", "orientation": [2, 0, 0, 0], "half_extents": [0.1, 0.2, 0.3]}])");
  s["constraints"][1]["collide"] = true;
  s["constraints"][2]["collide"] = false;
  return s;
}

Eigen::Vector3d vector_of(const json& v) { return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()); }

TEST(Scene, ShapesReadAsWritten) {
  const json s = with_shapes();
  const Mechanism m = parse_scene(s, "scene.json");
  ASSERT_EQ(m.bodies[0].shapes.size(), 2u);
  ASSERT_EQ(m.bodies[1].shapes.size(), 2u);
  ASSERT_EQ(m.bodies[2].shapes.size(), 1u);
  EXPECT_TRUE(m.bodies[3].shapes.empty()) << "no \"shapes\": none";
  const json& ground = s["bodies"][0]["shapes"];
  const json& b1 = s["bodies"][1]["shapes"];
  const json& b2 = s["bodies"][2]["shapes"];

  const Shape& plane = m.bodies[0].shapes[0];
  EXPECT_EQ(plane.type, ShapeType::plane);
  EXPECT_EQ(plane.position, vector_of(ground[0]["position"]));
  EXPECT_EQ(plane.normal, vector_of(ground[0]["normal"]).normalized()) << "normalized";
  EXPECT_EQ(plane.normal, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(plane.friction, ground[0]["friction"].get<double>());
  EXPECT_EQ(plane.restitution, ground[0]["restitution"].get<double>());

  const Shape& ground_box = m.bodies[0].shapes[1];
  EXPECT_EQ(ground_box.type, ShapeType::box);
  EXPECT_EQ(ground_box.position, vector_of(ground[1]["position"]));
  EXPECT_EQ(ground_box.half_extents, vector_of(ground[1]["half_extents"]));
  EXPECT_EQ(ground_box.contype, ground[1]["contype"].get<uint32_t>());
  EXPECT_EQ(ground_box.conaffinity, ground[1]["conaffinity"].get<uint32_t>());

  // every default (physics/shape.h): the body's own pose, friction 0.5, restitution 0, filter 1/1
  const Shape& sphere = m.bodies[1].shapes[0];
  EXPECT_EQ(sphere.type, ShapeType::sphere);
  EXPECT_EQ(sphere.radius, b1[0]["radius"].get<double>());
  EXPECT_EQ(sphere.position, Eigen::Vector3d::Zero());
  EXPECT_EQ(sphere.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(sphere.friction, 0.5);
  EXPECT_EQ(sphere.restitution, 0);
  EXPECT_EQ(sphere.contype, 1u);
  EXPECT_EQ(sphere.conaffinity, 1u);

  const Shape& capsule = m.bodies[1].shapes[1];
  EXPECT_EQ(capsule.type, ShapeType::capsule);
  EXPECT_EQ(capsule.position, vector_of(b1[1]["position"]));
  const json& q = b1[1]["orientation"];  // [w, x, y, z], unit already
  EXPECT_EQ(capsule.orientation.coeffs(),
            Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>()).coeffs());
  EXPECT_EQ(capsule.radius, b1[1]["radius"].get<double>());
  EXPECT_EQ(capsule.half_length, b1[1]["half_length"].get<double>());
  EXPECT_EQ(capsule.friction, b1[1]["friction"].get<double>());
  EXPECT_EQ(capsule.restitution, b1[1]["restitution"].get<double>());
  EXPECT_EQ(capsule.contype, b1[1]["contype"].get<uint32_t>());
  EXPECT_EQ(capsule.conaffinity, b1[1]["conaffinity"].get<uint32_t>());

  const Shape& box = m.bodies[2].shapes[0];
  EXPECT_EQ(box.half_extents, vector_of(b2[0]["half_extents"]));
  EXPECT_EQ(box.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs()) << "[2, 0, 0, 0] normalised";

  // "collide": as given, false by default
  for (size_t i = 0; i < m.constraints.size(); ++i)
    EXPECT_EQ(m.constraints[i].collide, s["constraints"][i].value("collide", false)) << i;
  EXPECT_TRUE(m.constraints[1].collide);
}

// ---- round trips ----

TEST(Scene, RoundTripThroughJsonReproducesEveryBodyAndConstraint) {
  const Mechanism m = every_type();
  const json j = scene_to_json(m);
  expect_same(parse_scene(j, "round trip"), m, 1e-12);
  // and the format is the documented one: world anchors and axes at the pose
  const json& hinge = j["constraints"][1];
  EXPECT_EQ(hinge["type"], "hinge");
  EXPECT_EQ(hinge["bodies"], json({"b0", "b1"}));
  const Eigen::Vector3d mid = 0.5 * (m.bodies[1].position + m.bodies[2].position);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(hinge["anchor"][k].get<double>(), mid[k], 1e-12);
    EXPECT_NEAR(hinge["axis"][k].get<double>(), Eigen::Vector3d(0.3, -1, 0.7).normalized()[k], 1e-12);
  }
}

TEST(Scene, RoundTripThroughAFile) {
  const Mechanism m = every_type();
  const std::string path = temp_path("every_type.json");
  save_scene(m, path);
  const Mechanism back = load_scene(path);
  expect_same(back, m, 1e-12);
  // and again: the local data do not drift (world -> body -> world rounds, the text need not
  // be a fixed point)
  const std::string again = temp_path("again.json");
  save_scene(back, again);
  expect_same(load_scene(again), m, 1e-12);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(json::accept(text.str()));
}

TEST(Scene, RoundTripOfAMovedMechanismKeepsItsPose) {
  // a mechanism moved rigidly as a whole (every constraint still holds): the file holds the new pose
  Mechanism m = every_type();
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d shift(1, -2, 0.5);
  for (RigidBody& b : m.bodies) {
    b.position = turn * b.position + shift;
    b.orientation = turn * b.orientation;
  }
  const Mechanism back = parse_scene(scene_to_json(m), "moved");
  for (size_t i = 0; i < m.bodies.size(); ++i)
    EXPECT_LE((back.bodies[i].position - m.bodies[i].position).norm(), 1e-12);
  // anchors and axes are the same points and directions of the bodies (frames about the axis may
  // be chosen afresh, the axis itself may not)
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const Constraint &x = m.constraints[i], &y = back.constraints[i];
    EXPECT_LE((x.anchor_a - y.anchor_a).norm(), 1e-12) << i;
    EXPECT_LE((x.anchor_b - y.anchor_b).norm(), 1e-12) << i;
    EXPECT_LE((x.frame_a.col(2) - y.frame_a.col(2)).norm(), 1e-12) << i;
    EXPECT_LE((x.frame_b.col(2) - y.frame_b.col(2)).norm(), 1e-12) << i;
    EXPECT_NEAR(x.length, y.length, 1e-12);
  }
}

TEST(Scene, LoadsReadAsWrittenAndRoundTrip) {
  // read: "force" and "torque" are the body's constant load, zero when left out
  json s = valid();
  s["bodies"][2]["force"] = {1.5, -2, 0.25};
  s["bodies"][2]["torque"] = {0, 0, 3};
  s["bodies"][1]["torque"] = {-0.5, 0, 0};
  const Mechanism read = parse_scene(s, "scene.json");
  EXPECT_EQ(read.bodies[2].applied_force, Eigen::Vector3d(1.5, -2, 0.25));
  EXPECT_EQ(read.bodies[2].applied_torque, Eigen::Vector3d(0, 0, 3));
  EXPECT_EQ(read.bodies[1].applied_force, Eigen::Vector3d::Zero());
  EXPECT_EQ(read.bodies[1].applied_torque, Eigen::Vector3d(-0.5, 0, 0));
  // written when non-zero only, and read back (expect_same compares the loads)
  Mechanism m = every_type();
  m.bodies[2].applied_force = Eigen::Vector3d(0.1, -30, 7);
  m.bodies[2].applied_torque = Eigen::Vector3d(1.0 / 3, 0, -2);
  m.bodies[5].applied_torque = Eigen::Vector3d(0, 0, 12.5);
  m.bodies[7].applied_force = Eigen::Vector3d(-4, 0, 0);
  const json j = scene_to_json(m);
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    EXPECT_EQ(j["bodies"][i].contains("force"), !m.bodies[i].applied_force.isZero(0)) << i;
    EXPECT_EQ(j["bodies"][i].contains("torque"), !m.bodies[i].applied_torque.isZero(0)) << i;
  }
  EXPECT_EQ(j["bodies"][5]["torque"], json({0.0, 0.0, 12.5}));
  expect_same(parse_scene(j, "round trip"), m, 1e-12);
  const std::string path = temp_path("loads.json");
  save_scene(m, path);
  const Mechanism back = load_scene(path);
  expect_same(back, m, 1e-12);
  // world-frame vectors written as the shortest text that reads back: exact
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    EXPECT_EQ(back.bodies[i].applied_force, m.bodies[i].applied_force) << i;
    EXPECT_EQ(back.bodies[i].applied_torque, m.bodies[i].applied_torque) << i;
  }
}

// every_type() with shapes on a static and on moving bodies, and two constraints that collide.
Mechanism every_type_with_shapes() {
  Mechanism m = every_type();
  Shape plane;
  plane.type = ShapeType::plane;
  plane.position = Eigen::Vector3d(0.1, -3, 0.2);
  plane.normal = Eigen::Vector3d(0.1, 1, -0.2).normalized();
  plane.friction = 0.9;
  Shape sphere;
  sphere.radius = 0.25;
  sphere.restitution = 0.3;
  sphere.contype = 3;
  Shape capsule;
  capsule.type = ShapeType::capsule;
  capsule.position = Eigen::Vector3d(1.0 / 3, 0, -0.1);
  capsule.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -1, 2).normalized()));
  capsule.radius = 0.04;
  capsule.half_length = 0.35;
  capsule.conaffinity = 0xffffffffu;
  Shape box;
  box.type = ShapeType::box;
  box.half_extents = Eigen::Vector3d(0.5, 0.1, 2.5);
  box.orientation = Eigen::Quaterniond(0.8, 0.1, 0.2, -0.3).normalized();
  Shape cylinder = capsule;
  cylinder.type = ShapeType::cylinder;
  cylinder.half_length = 0.15;
  Shape ellipsoid = box;
  ellipsoid.type = ShapeType::ellipsoid;
  ellipsoid.half_extents = Eigen::Vector3d(0.3, 0.1, 0.2);
  m.bodies[0].shapes = {plane, box};
  m.bodies[1].shapes = {sphere, ellipsoid};
  m.bodies[4].shapes = {capsule, box, sphere, cylinder};
  m.bodies.back().shapes = {box};
  m.constraints[1].collide = true;
  m.constraints[6].collide = true;
  return m;
}

TEST(Scene, RoundTripOfShapesAndCollide) {
  const Mechanism m = every_type_with_shapes();
  const json j = scene_to_json(m);
  EXPECT_FALSE(j["bodies"][2].contains("shapes")) << "no shapes: left out";
  EXPECT_EQ(j["constraints"][1]["collide"], true);
  EXPECT_FALSE(j["constraints"][0].contains("collide")) << "false: left out";
  expect_same(parse_scene(j, "round trip"), m, 1e-15);
  const std::string path = temp_path("shapes.json");
  save_scene(m, path);
  const Mechanism back = load_scene(path);
  expect_same(back, m, 1e-15);
  // body-frame numbers written as the shortest text that reads back: the sizes exactly
  EXPECT_EQ(back.bodies[4].shapes[0].radius, 0.04);
  EXPECT_EQ(back.bodies[4].shapes[0].position, m.bodies[4].shapes[0].position);
  // and a file's shapes read, written and read again
  const Mechanism read = parse_scene(with_shapes(), "scene.json");
  expect_same(parse_scene(scene_to_json(read), "scene.json"), read, 1e-15);
}

// A hull's vertices and a heightfield's grid have no scene-file form: the writer refuses them,
// naming the body, rather than write a shape without its data.
TEST(Scene, ConvexAndHeightfieldShapesAreNotWritten) {
  for (const ShapeType type : {ShapeType::convex, ShapeType::heightfield}) {
    Mechanism m = every_type();
    Shape s;
    s.type = type;
    m.bodies[0].shapes = {s};
    try {
      scene_to_json(m);
      ADD_FAILURE() << "wrote a " << to_string(type);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(std::string("a ") + to_string(type) + " shape (from an MJCF model) has no scene-file form"),
                std::string::npos)
          << message;
      EXPECT_NE(message.find(m.bodies[0].name), std::string::npos) << message;
    }
  }
}

TEST(Scene, SavedFileHasOneLinePerBodyAndConstraint) {
  const Mechanism m = every_type_with_shapes();  // shapes stay on their body's line
  const std::string path = temp_path("lines.json");
  save_scene(m, path);
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  // {, name, gravity, timestep, "bodies": [, bodies, ], "constraints": [, constraints, ], }
  EXPECT_EQ(lines, 4 + 2 + static_cast<int>(m.bodies.size()) + 2 + static_cast<int>(m.constraints.size()) + 1);
}

TEST(Scene, UnwritableFileIsAnInputError) {
  const std::string path = temp_path("no_such_dir") + "/scene.json";
  try {
    save_scene(every_type(), path);
    ADD_FAILURE() << "wrote " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).substr(0, path.size() + 1), path + ":") << e.what();
  }
}

// ---- bad input: one test per kind ----

TEST(SceneBadInput, UnknownBodyName) {
  json s = valid();
  s["constraints"][3]["bodies"][1] = "link9";
  expect_error(s, "constraints[3]", {"unknown body \"link9\""});
}

TEST(SceneBadInput, DuplicateBodyName) {
  json s = valid();
  s["bodies"][2]["name"] = "b1";
  expect_error(s, "bodies[2] (\"b1\")", {"duplicate body name", "bodies[1]"});
}

TEST(SceneBadInput, UnknownConstraintType) {
  json s = valid();
  s["constraints"][1]["type"] = "hinje";
  expect_error(s, "constraints[1]", {"unknown constraint type \"hinje\"", "hinge"});
}

TEST(SceneBadInput, ConstraintBetweenABodyAndItself) {
  json s = valid();
  s["constraints"][1]["bodies"] = {"b2", "b2"};
  expect_error(s, "constraints[1]", {"two different bodies", "\"b2\""});
}

TEST(SceneBadInput, TwoStaticBodiesConstrainedTogether) {
  json s = valid();
  s["constraints"][6]["bodies"] = {"ground", "wall"};
  expect_error(s, "constraints[6]", {"two static bodies", "\"ground\"", "\"wall\""});
}

TEST(SceneBadInput, NonPositiveMass) {
  for (double mass : {0.0, -1.0}) {
    json s = valid();
    s["bodies"][2]["mass"] = mass;
    expect_error(s, "bodies[2] (\"b2\")", {std::string("mass must be positive, got ") + (mass == 0 ? "0" : "-1")});
  }
}

TEST(SceneBadInput, NonPositiveInertia) {
  json s = valid();
  s["bodies"][1]["inertia"] = {0.1, 0, 0.1};
  expect_error(s, "bodies[1] (\"b1\")", {"inertia must be positive", "[0.1, 0, 0.1]"});
  s["bodies"][1]["inertia"] = {0.1, 0.1, -2};
  expect_error(s, "bodies[1] (\"b1\")", {"inertia must be positive"});
}

TEST(SceneBadInput, ZeroAxis) {
  json s = valid();
  s["constraints"][1]["axis"] = {0, 0, 0};
  expect_error(s, "constraints[1]", {"axis", "non-zero"});
  s = valid();
  s["constraints"][3]["axis"] = {1e-13, 0, 0};  // near zero: no direction either
  expect_error(s, "constraints[3]", {"axis", "non-zero"});
  s = valid();
  s["constraints"][6]["axis"] = {0, 0, 0};  // the weld's optional axis is checked when given
  expect_error(s, "constraints[6]", {"axis", "non-zero"});
}

TEST(SceneBadInput, ZeroQuaternion) {
  json s = valid();
  s["bodies"][3]["orientation"] = {0, 0, 0, 0};
  expect_error(s, "bodies[3] (\"wall\")", {"orientation", "non-zero quaternion"});
}

TEST(SceneBadInput, NonFiniteNumber) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  json s = valid();
  s["bodies"][1]["mass"] = nan;
  expect_error(s, "bodies[1] (\"b1\")", {"mass must be finite"});
  s = valid();
  s["bodies"][2]["position"][1] = inf;
  expect_error(s, "bodies[2] (\"b2\")", {"position must be finite", "inf"});
  s = valid();
  s["constraints"][2]["anchors"][1][0] = -inf;
  expect_error(s, "constraints[2]", {"anchors[1] must be finite"});
  s = valid();
  s["timestep"] = nan;
  expect_error(s, "", {"timestep must be finite"});
  s = valid();
  s["constraints"][3]["max"] = inf;
  expect_error(s, "constraints[3]", {"max must be finite"});
  s = valid();
  s["bodies"][1]["force"] = {0, nan, 0};
  expect_error(s, "bodies[1] (\"b1\")", {"force must be finite", "nan"});
  s = valid();
  s["bodies"][2]["torque"] = {0, 0, -inf};
  expect_error(s, "bodies[2] (\"b2\")", {"torque must be finite", "-inf"});
  // in a file: a number too large for a double, refused where it stands
  std::string text = valid().dump(1);
  text.replace(text.find("\"mass\": 2"), 9, "\"mass\": 1e400");
  const std::string path = temp_file("scene.json", text);
  const std::string message = file_error_of(path);
  const size_t at = text.find("1e400");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  const int column = static_cast<int>(at - text.rfind('\n', at));
  EXPECT_EQ(message, path + ":" + std::to_string(line) + ":" + std::to_string(column) +
                         ": number 1e400 is out of the range of a double");
}

TEST(SceneBadInput, LoadOnAStaticBody) {
  // a static body never moves: a load on it would do nothing, so it is a mistake in the file
  json s = valid();
  s["bodies"][0]["force"] = {0, 1, 0};
  expect_error(s, "bodies[0] (\"ground\")", {"a static body cannot carry a force"});
  s = valid();
  s["bodies"][3]["torque"] = {0, 0, 0};  // even a zero one
  expect_error(s, "bodies[3] (\"wall\")", {"a static body cannot carry a torque"});
}

TEST(SceneBadInput, WrongArrayLength) {
  json s = valid();
  s["bodies"][1]["position"] = {0, -1};
  expect_error(s, "bodies[1] (\"b1\")", {"position must be an array of 3 numbers", "[0,-1]"});
  s = valid();
  s["bodies"][2]["orientation"] = {1, 0, 0};
  expect_error(s, "bodies[2] (\"b2\")", {"orientation must be an array of 4 numbers"});
  s = valid();
  s["constraints"][2]["anchors"] = {{1, -1, 0}};
  expect_error(s, "constraints[2]", {"anchors must be an array of 2 points"});
  s = valid();
  s["constraints"][2]["anchors"][0] = {1, -1, 0, 0};
  expect_error(s, "constraints[2]", {"anchors[0] must be an array of 3 numbers"});
  s = valid();
  s["constraints"][0]["bodies"] = {"ground", "b1", "b2"};
  expect_error(s, "constraints[0]", {"bodies must be an array of 2 body names"});
  s = valid();
  s["gravity"] = {0, -9.81, 0, 1};
  expect_error(s, "", {"gravity must be an array of 3 numbers"});
  s = valid();
  s["bodies"][2]["force"] = {1, 2};
  expect_error(s, "bodies[2] (\"b2\")", {"force must be an array of 3 numbers"});
}

TEST(SceneBadInput, WrongJsonType) {
  json s = valid();
  s["bodies"][1]["mass"] = "heavy";
  expect_error(s, "bodies[1] (\"b1\")", {"mass must be a number, got \"heavy\""});
  s = valid();
  s["bodies"][1]["static"] = "yes";
  expect_error(s, "bodies[1] (\"b1\")", {"static must be true or false"});
  s = valid();
  s["bodies"][1]["name"] = 7;
  expect_error(s, "bodies[1]", {"name must be a string, got 7"});
  s = valid();
  s["bodies"][1]["position"] = {0, "-1", 0};
  expect_error(s, "bodies[1] (\"b1\")", {"position must be an array of 3 numbers"});
  s = valid();
  s["bodies"][1]["inertia"] = true;
  expect_error(s, "bodies[1] (\"b1\")", {"inertia must be an array of 3 numbers, got true"});
  s = valid();
  s["bodies"] = json::object();
  expect_error(s, "", {"bodies must be an array"});
  s = valid();
  s["constraints"][4] = "hinge";
  expect_error(s, "constraints[4]", {"a constraint must be a JSON object"});
  s = valid();
  s["bodies"][0] = json::array();
  expect_error(s, "bodies[0]", {"a body must be a JSON object"});
  s = valid();
  s["constraints"][1]["type"] = 5;
  expect_error(s, "constraints[1]", {"type must be a string"});
  s = valid();
  s["constraints"][0]["bodies"] = {"ground", 1};
  expect_error(s, "constraints[0]", {"bodies must be an array of 2 body names"});
  s = valid();
  s["name"] = json::array();
  expect_error(s, "", {"name must be a string"});
  expect_error(json::array(), "", {"the scene must be a JSON object"});
}

TEST(SceneBadInput, MissingRequiredField) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"bodies", {}},
      {"bodies/1/mass", {"bodies[1] (\"b1\")"}},
      {"bodies/1/inertia", {"bodies[1] (\"b1\")"}},
      {"bodies/1/position", {"bodies[1] (\"b1\")"}},
      {"bodies/0/position", {"bodies[0] (\"ground\")"}},
      {"bodies/2/name", {"bodies[2]"}},
      {"constraints/1/anchor", {"constraints[1]"}},
      {"constraints/1/axis", {"constraints[1]"}},
      {"constraints/1/type", {"constraints[1]"}},
      {"constraints/1/bodies", {"constraints[1]"}},
      {"constraints/2/anchors", {"constraints[2]"}},
      {"constraints/3/min", {"constraints[3]"}},
      {"constraints/4/max", {"constraints[4]"}},
      {"constraints/4/anchor", {"constraints[4]"}},
  };
  for (const auto& [pointer, entry] : cases) {
    SCOPED_TRACE(pointer);
    json s = valid();
    const json::json_pointer p(std::string("/") + pointer);
    s[p.parent_pointer()].erase(p.back());
    expect_error(s, entry.empty() ? "" : entry[0], {std::string("missing \"") + p.back() + "\""});
  }
}

// ---- bad shapes (physics/shape.h: shape_problem): one test per kind ----

const std::string kB1Shape = "bodies[1] (\"b1\"): shapes[0]";

// valid() with one shape on b1 (or on the static ground).
json with_shape(const json& shape, int body = 1) {
  json s = valid();
  s["bodies"][body]["shapes"] = json::array({shape});
  return s;
}

TEST(SceneBadInput, ShapeNonPositiveRadius) {
  EXPECT_EQ(error_of(with_shape({{"type", "sphere"}, {"radius", -1}})),
            "scene.json: bodies[1] (\"b1\"): shapes[0]: radius -1 is not in (0, 1e9] m");
  expect_error(with_shape({{"type", "capsule"}, {"radius", 0}, {"half_length", 1}}), kB1Shape, {"radius 0 is not in (0, 1e9] m"});
  expect_error(with_shape({{"type", "capsule"}, {"radius", 0.1}, {"half_length", -0.5}}), kB1Shape,
               {"half_length -0.5 is not in [0, 1e9] m"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 2e9}}), kB1Shape, {"radius 2e+09 is not in (0, 1e9] m"});
  // a capsule of half length 0 is a sphere: allowed
  EXPECT_NO_THROW(parse_scene(with_shape({{"type", "capsule"}, {"radius", 0.1}, {"half_length", 0}}), "scene.json"));
}

TEST(SceneBadInput, ShapeZeroHalfExtent) {
  expect_error(with_shape({{"type", "box"}, {"half_extents", {0.1, 0, 0.1}}}), kB1Shape,
               {"half_extents component 0 is not in (0, 1e9] m"});
  expect_error(with_shape({{"type", "box"}, {"half_extents", {0.1, 0.1, -3}}}), kB1Shape, {"half_extents component -3"});
}

TEST(SceneBadInput, PlaneOnADynamicBody) {
  const json plane = {{"type", "plane"}, {"normal", {0, 1, 0}}};
  expect_error(with_shape(plane), kB1Shape, {"a plane on a dynamic body"});
  EXPECT_NO_THROW(parse_scene(with_shape(plane, 0), "scene.json"));  // on the static ground
}

TEST(SceneBadInput, PlaneWithZeroNormal) {
  expect_error(with_shape({{"type", "plane"}, {"normal", {0, 0, 0}}}, 3), "bodies[3] (\"wall\"): shapes[0]",
               {"normal of length 0"});
  expect_error(with_shape({{"type", "plane"}, {"normal", {1e-13, 0, 0}}}, 0), "bodies[0] (\"ground\"): shapes[0]",
               {"normal of length 1e-13"});
}

TEST(SceneBadInput, ShapeRestitutionOrFrictionOutOfRange) {
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"restitution", 2}}), kB1Shape,
               {"restitution 2 is not in [0, 1]"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"restitution", -0.5}}), kB1Shape, {"restitution -0.5"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"friction", -0.1}}), kB1Shape,
               {"friction -0.1 is not finite and >= 0"});
}

TEST(SceneBadInput, ShapeNonFiniteNumber) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  expect_error(with_shape({{"type", "sphere"}, {"radius", nan}}), kB1Shape, {"radius must be finite"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"friction", inf}}), kB1Shape, {"friction must be finite"});
  expect_error(with_shape({{"type", "box"}, {"half_extents", {1, nan, 1}}}), kB1Shape, {"half_extents must be finite"});
  expect_error(with_shape({{"type", "plane"}, {"normal", {0, -inf, 0}}}, 0), "bodies[0] (\"ground\"): shapes[0]",
               {"normal must be finite"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"position", {nan, 0, 0}}}), kB1Shape, {"position must be finite"});
  // in a file: a number too large for a double, refused where it stands
  std::string text = with_shape({{"type", "sphere"}, {"radius", 7}}).dump(1);
  text.replace(text.find("\"radius\": 7"), 11, "\"radius\": 1e999");
  const std::string path = temp_file("scene.json", text);
  const std::string message = file_error_of(path);
  EXPECT_NE(message.find(": number 1e999 is out of the range of a double"), std::string::npos) << message;
}

TEST(SceneBadInput, ShapeWrongJsonType) {
  expect_error(with_shape({{"type", "sphere"}, {"radius", "big"}}), kB1Shape, {"radius must be a number, got \"big\""});
  expect_error(with_shape({{"type", "capsule"}, {"radius", 1}, {"half_length", true}}), kB1Shape, {"half_length must be a number"});
  expect_error(with_shape({{"type", "box"}, {"half_extents", 1}}), kB1Shape, {"half_extents must be an array of 3 numbers"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"orientation", {1, 0, 0}}}), kB1Shape,
               {"orientation must be an array of 4 numbers"});
  expect_error(with_shape({{"type", 3}, {"radius", 1}}), kB1Shape, {"type must be a string"});
  expect_error(with_shape("sphere"), kB1Shape, {"a shape must be a JSON object, got \"sphere\""});
  for (const json& filter : {json(-1), json(1.5), json(4294967296), json("1")}) {
    expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"contype", filter}}), kB1Shape,
                 {"contype must be an integer in [0, 4294967295], got " + filter.dump()});
    expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"conaffinity", filter}}), kB1Shape,
                 {"conaffinity must be an integer in [0, 4294967295]"});
  }
}

TEST(SceneBadInput, ShapeZeroOrientation) {
  expect_error(with_shape({{"type", "box"}, {"half_extents", {1, 1, 1}}, {"orientation", {0, 0, 0, 0}}}), kB1Shape,
               {"orientation must be a non-zero quaternion"});
}

TEST(SceneBadInput, UnknownShapeType) {
  expect_error(with_shape({{"type", "torus"}, {"radius", 1}}), kB1Shape,
               {"unknown shape type \"torus\"", "plane, sphere, capsule, box, cylinder, ellipsoid"});
}

// Convex hulls and heightfields come from MJCF models only: a scene file names them in vain,
// and a mechanism with one is refused by the writer rather than written without its data.
TEST(SceneBadInput, ConvexAndHeightfieldShapesHaveNoSceneFileForm) {
  for (const char* type : {"convex", "heightfield"})
    expect_error(with_shape({{"type", type}}), kB1Shape, {std::string("a ") + type + " shape has no scene-file form"});
}

TEST(SceneBadInput, ShapeKeyForeignToItsType) {
  expect_error(with_shape({{"type", "box"}, {"half_extents", {1, 1, 1}}, {"radius", 1}}), kB1Shape,
               {"unknown key \"radius\"", "a box shape has:", "half_extents"});
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"half_length", 1}}), kB1Shape,
               {"unknown key \"half_length\"", "a sphere shape"});
  expect_error(with_shape({{"type", "capsule"}, {"radius", 1}, {"half_length", 1}, {"normal", {0, 0, 1}}}), kB1Shape,
               {"unknown key \"normal\"", "a capsule shape"});
  expect_error(with_shape({{"type", "plane"}, {"normal", {0, 1, 0}}, {"half_extents", {1, 1, 1}}}, 0),
               "bodies[0] (\"ground\"): shapes[0]", {"unknown key \"half_extents\"", "a plane shape"});
  // a plane's direction is its normal: an orientation on it would be ignored
  expect_error(with_shape({{"type", "plane"}, {"normal", {0, 1, 0}}, {"orientation", {1, 0, 0, 0}}}, 0),
               "bodies[0] (\"ground\"): shapes[0]", {"unknown key \"orientation\"", "a plane shape"});
  // and a typo is no default
  expect_error(with_shape({{"type", "sphere"}, {"radius", 1}, {"fricton", 1}}), kB1Shape, {"unknown key \"fricton\""});
}

TEST(SceneBadInput, ShapeMissingRequiredKey) {
  expect_error(with_shape({{"type", "sphere"}}), kB1Shape, {"missing \"radius\""});
  expect_error(with_shape({{"type", "capsule"}, {"radius", 1}}), kB1Shape, {"missing \"half_length\""});
  expect_error(with_shape({{"type", "capsule"}, {"half_length", 1}}), kB1Shape, {"missing \"radius\""});
  expect_error(with_shape({{"type", "box"}}), kB1Shape, {"missing \"half_extents\""});
  expect_error(with_shape({{"type", "plane"}}, 0), "bodies[0] (\"ground\"): shapes[0]", {"missing \"normal\""});
  expect_error(with_shape({{"radius", 1}}), kB1Shape, {"missing \"type\""});
}

TEST(SceneBadInput, ShapesNotAnArray) {
  json s = valid();
  s["bodies"][2]["shapes"] = {{"type", "sphere"}, {"radius", 1}};
  expect_error(s, "bodies[2] (\"b2\")", {"shapes must be an array, got {"});
  s["bodies"][2]["shapes"] = "sphere";
  expect_error(s, "bodies[2] (\"b2\")", {"shapes must be an array"});
  // the index names the shape at fault
  s["bodies"][2]["shapes"] = {{{"type", "sphere"}, {"radius", 1}}, {{"type", "sphere"}, {"radius", 0}}};
  expect_error(s, "bodies[2] (\"b2\"): shapes[1]", {"radius 0"});
}

TEST(SceneBadInput, CollideNotABoolean) {
  json s = valid();
  s["constraints"][1]["collide"] = "yes";
  expect_error(s, "constraints[1]", {"collide must be true or false, got \"yes\""});
  s["constraints"][1]["collide"] = 1;
  expect_error(s, "constraints[1]", {"collide must be true or false"});
}

TEST(SceneBadInput, UnknownTopLevelKey) {
  json s = valid();
  s["gravty"] = {0, -1, 0};
  expect_error(s, "", {"unknown key \"gravty\"", "gravity"});
}

TEST(SceneBadInput, UnknownKeyInAnEntry) {
  json s = valid();
  s["bodies"][1]["positon"] = {0, 0, 0};
  expect_error(s, "bodies[1] (\"b1\")", {"unknown key \"positon\"", "position"});
  s = valid();
  s["constraints"][1]["length"] = 1;  // a key of other types, not of a hinge
  expect_error(s, "constraints[1]", {"unknown key \"length\"", "a hinge constraint"});
  s = valid();
  s["bodies"][0]["mass"] = 1;  // a static body has no mass
  expect_error(s, "bodies[0] (\"ground\")", {"unknown key \"mass\"", "a static body"});
  s = valid();
  s["constraints"][3]["anchor"] = {0, 0, 0};  // an angular limit has no anchor
  expect_error(s, "constraints[3]", {"unknown key \"anchor\""});
}

TEST(SceneBadInput, MinGreaterThanMax) {
  json s = valid();
  s["constraints"][3]["min"] = 0.6;
  expect_error(s, "constraints[3]", {"min (0.6) exceeds max (0.5)"});
  s = valid();
  s["constraints"][4]["max"] = -0.2;
  expect_error(s, "constraints[4]", {"min (-0.1) exceeds max (-0.2)"});
  s = valid();
  s["constraints"][4]["max"] = -0.1;  // equal is a locked slide: allowed
  EXPECT_NO_THROW(parse_scene(s, "scene.json"));
}

TEST(SceneBadInput, NonPositiveLength) {
  for (double length : {0.0, -1.0}) {
    json s = valid();
    s["constraints"][2]["length"] = length;
    expect_error(s, "constraints[2]", {"length must be positive"});
  }
}

TEST(SceneBadInput, NonPositiveTimestep) {
  for (double dt : {0.0, -0.01}) {
    json s = valid();
    s["timestep"] = dt;
    expect_error(s, "", {"timestep must be positive"});
  }
}

TEST(SceneBadInput, RodOrRopeWithCoincidentAnchors) {
  json s = valid();
  s["constraints"][5]["anchors"] = {{0.5, -1, 0}, {0.5, -1, 0}};
  expect_error(s, "constraints[5]", {"anchors coincide"});
  s = valid();
  s["constraints"][2]["anchors"] = {{1, -1, 0}, {1, -1, 1e-13}};
  expect_error(s, "constraints[2]", {"anchors coincide"});
}

TEST(SceneBadInput, InvalidJsonSyntaxGivesTheParsersPosition) {
  // line 3, column 15: the stray '}' where a value should be
  const std::string path = temp_file("scene.json", "{\n  \"name\": \"x\",\n  \"timestep\": },\n  \"bodies\": []\n}\n");
  const std::string message = file_error_of(path);
  EXPECT_EQ(message.substr(0, path.size() + 6), path + ":3:15:") << message;
  EXPECT_NE(message.find("invalid JSON"), std::string::npos) << message;
  // an empty file, a truncated one
  EXPECT_NE(file_error_of(temp_file("empty.json", "")).find("invalid JSON"), std::string::npos);
  const std::string cut = temp_file("cut.json", "{\"bodies\": [");
  EXPECT_EQ(file_error_of(cut).substr(0, cut.size() + 5), cut + ":1:13");
}

TEST(SceneBadInput, DuplicateKeyInAFile) {
  // nlohmann-json would keep the last "mass" silently
  std::string text = valid().dump(1);
  text.replace(text.find("\"mass\": 2"), 9, "\"mass\": 2, \"mass\": 3");
  const std::string message = file_error_of(temp_file("scene.json", text));
  EXPECT_NE(message.find("bodies[2]: duplicate key \"mass\""), std::string::npos) << message;
  const std::string top = file_error_of(temp_file("top.json", "{\"bodies\": [], \"bodies\": []}"));
  EXPECT_NE(top.find(": duplicate key \"bodies\""), std::string::npos) << top;
}

// The file name is escaped once in every message, a value out of range included (a backslash
// shows as \\, not \\\\).
TEST(SceneBadInput, FileNameIsEscapedOnceInARangeError) {
  json s = valid();
  s["bodies"][2]["mass"] = 1e60;
  const std::string path = temp_file("back\\slash.json", s.dump());
  std::string message;
  try {
    load_scene(path);
  } catch (const InputError& e) {
    message = e.what();
  }
  const std::string escaped = path.substr(0, path.find('\\')) + "\\\\" + path.substr(path.find('\\') + 1);
  EXPECT_EQ(message.rfind(escaped + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("mass 1e+60"), std::string::npos) << message;
}

TEST(SceneBadInput, UnreadableFile) {
  const std::string missing = kTestData + "/scenes/no_such_file.json";
  EXPECT_EQ(file_error_of(missing), missing + ": cannot open file: No such file or directory");
  const std::string dir = temp_path("a_directory.json");
  std::filesystem::create_directory(dir);
  EXPECT_EQ(file_error_of(dir), dir + ": cannot read: it is a directory");
}

TEST(SceneBadInput, BadFixturesNameTheirFileAndEntry) {
  // files as a user writes them, under tests/data/scenes
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"typo_positon.json", ": bodies[1] (\"link0\"): unknown key \"positon\""},
      {"unknown_body.json", ": constraints[1]: unknown body \"link9\""},
      {"zero_mass.json", ": bodies[2] (\"link1\"): mass must be positive, got 0"},
      {"syntax_error.json", ":8:"},
  };
  for (const auto& [file, expected] : cases) {
    const std::string path = kTestData + "/scenes/" + file;
    const std::string message = file_error_of(path);
    EXPECT_EQ(message.substr(0, path.size() + expected.size()), path + expected) << message;
  }
}

using ::testing::bytes_read_by;

// The whole file was read before parsing: a scene that is /dev/zero never failed, a 2 GB file of
// NUL bytes took 30 s and 4.2 GB. Now the parser stops at the first byte that cannot be JSON,
// with the message it always gave, having read a chunk (64 KiB) past it at most.
TEST(SceneBadInput, NulBytesAreRefusedWhereTheyStart) {
  for (const std::string& start : {std::string(), std::string("{\n  \"name\": \"x\", ")}) {
    const std::string path = temp_file("nul.json", start);
    std::filesystem::resize_file(path, uintmax_t{256} << 20);  // NUL bytes, a sparse file
    std::string message;
    const int64_t read = bytes_read_by([&] { message = file_error_of(path); });
    const std::string where = start.empty() ? ":1:1: invalid JSON: " : ":2:16: invalid JSON: ";
    EXPECT_EQ(message.substr(0, path.size() + where.size()), path + where) << message;
    ASSERT_GE(read, 0) << "no /proc/self/io to count the bytes read";
    EXPECT_LT(read, 1 << 20);
  }
}

// nlohmann-json takes a NUL byte for the end of the input: a scene followed by one and anything
// (here, or a scene piped with /dev/zero after it) was accepted, the rest never read.
TEST(SceneBadInput, NulByteAfterTheScene) {
  const std::string scene = valid().dump() + "\n";
  const std::string path = temp_file("scene.json", scene + std::string(1, '\0') + "garbage}");
  EXPECT_EQ(file_error_of(path), path + ":2:1: invalid JSON: a NUL byte after the scene");
  // a complete scene ending the file, or followed by whitespace, reads as before
  EXPECT_EQ(load_scene(temp_file("ok.json", scene + " \t\r\n")).bodies.size(), 4u);
}

// A read error (EIO: /proc/self/mem at offset 0 is not mapped) was swallowed by the stream copy
// and reported as "1:1: invalid JSON: unexpected end of input".
TEST(SceneBadInput, ReadErrorIsNamed) {
  ASSERT_TRUE(std::filesystem::exists("/proc/self/mem")) << "no /proc/self/mem to read from";
  EXPECT_EQ(file_error_of("/proc/self/mem"), "/proc/self/mem: cannot read: read error");
}

// Read a chunk at a time, a file's line and column are still counted from its start, and a
// number out of range is still found where it is.
TEST(SceneBadInput, ErrorPositionsBeyondTheFirstChunk) {
  const std::string blank(200000, '\n');
  const std::string syntax = temp_file("far.json", "{" + blank + "  \"name\": \"x\",\n  \"timestep\": },\n}\n");
  const std::string where = syntax + ":200002:15: invalid JSON";
  EXPECT_EQ(file_error_of(syntax).substr(0, where.size()), where);
  const std::string range = temp_file("range.json", "{" + blank + "  \"name\": \"x\", \"timestep\": 1e400}");
  EXPECT_EQ(file_error_of(range), range + ":200001:28: number 1e400 is out of the range of a double");
}

// Deeply nested JSON: the parser survives it, but the message dumped the
// offending value recursively and overflowed the stack at 4000 levels (70k in Release). Now
// one short line whatever the depth.
TEST(Scene, DeeplyNestedValueGivesAShortMessage) {
  for (const int depth : {4000, 200000}) {
    const std::string nested = std::string(depth, '[') + std::string(depth, ']');
    const std::string path = temp_file("deep.json", "{\"name\": \"deep\", \"bodies\": [" + nested + "]}");
    const std::string message = file_error_of(path);
    EXPECT_LT(message.size(), 300u) << message;
    EXPECT_NE(message.find("[[[["), std::string::npos) << message;
    EXPECT_NE(message.find("..."), std::string::npos) << message;
  }
}

// A syntax error's message quotes at most a few hundred printable characters of the input.
TEST(Scene, SyntaxErrorMessageIsBoundedAndPrintable) {
  std::string token(100000, 'y');
  token[10] = '\n';
  const std::string message = file_error_of(temp_file("bad.json", "{\"name\": tru" + token));
  EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);
}

// Readers, numerics and messages
// Found by fuzz/scene_fuzz.cpp: names and keys were quoted as JSON without ensure_ascii, so DEL,
// UTF-8 and invalid bytes (replaced by a raw U+FFFD) went into the message unescaped.
TEST(SceneBadInput, NamesAndKeysAreQuotedInPrintableAscii) {
  for (const std::string& key : {std::string("positi\x7fn"), std::string("pos\xc3\xa9"), std::string("p\xff\xfe")}) {
    const std::string path = temp_file("key.json", "{\"name\": \"k\", \"bodies\": [{\"name\": \"g\", \"static\": true, \"" + key +
                                                       "\": [0, 0, 0]}], \"constraints\": []}");
    const std::string message = file_error_of(path);
    EXPECT_NE(message.find(key.find('\xff') != std::string::npos ? "invalid JSON" : "unknown key \"pos"), std::string::npos) << message;
    for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c) << " in " << message;
  }
  const std::string message = error_of(json::parse(R"({"name": "u", "bodies": [{"name": "\u00e9\u007f", "mass": 0}]})"));
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c) << " in " << message;
}

// Found by fuzz/scene_fuzz.cpp: a quoted key or name was not bounded (a 100 KB unknown key, a
// 100 KB message; escaped DEL bytes take six characters each).
TEST(SceneBadInput, LongKeysAndNamesAreQuotedBounded) {
  const std::string key(100000, '\x7f'), name(100000, 'n');
  std::string message = file_error_of(temp_file("long_key.json", "{\"name\": \"k\", \"gra" + key + "\": 1}"));
  EXPECT_LT(message.size(), 500u) << message.substr(0, 500);
  EXPECT_NE(message.find("unknown key \"gra\\u007f"), std::string::npos) << message.substr(0, 500);
  EXPECT_NE(message.find("\"... ("), std::string::npos) << message.substr(0, 500);
  message = error_of(json::parse("{\"name\": \"u\", \"bodies\": [{\"name\": \"" + name + "\", \"mass\": 0}]}"));
  EXPECT_LT(message.size(), 300u) << message.substr(0, 500);
}

// Found by fuzz/scene_fuzz.cpp: a duplicate key's location copied the keys on its way raw (a DEL
// byte went into the message) and without bound (4000 levels of nesting, a 12 KB location).
TEST(SceneBadInput, DuplicateKeyLocationIsBoundedAndPrintable) {
  std::string message = file_error_of(temp_file("dup.json", "{\"b\x7f\": [{\"static\": 1, \"static\": 2}]}"));
  EXPECT_NE(message.find("b\\x7f[0]: duplicate key \"static\""), std::string::npos) << message;
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c) << " in " << message;
  const std::string deep = std::string(4000, '[') + "{\"a\": 1, \"a\": 2}" + std::string(4000, ']');
  message = file_error_of(temp_file("dup_deep.json", "{\"bodies\": " + deep + "}"));
  EXPECT_LT(message.size(), 400u) << message.substr(0, 400);
  EXPECT_NE(message.find("duplicate key \"a\""), std::string::npos) << message.substr(0, 400);
}

// ---- values whose products overflow ----

// "Finite and positive" let through a mass of 1e-320 (1/m = inf), an anchor at 1e155 (|r|^2 =
// inf) and a coordinate of 1e308, and export wrote NaN and inf with exit 0. Now every value must
// lie in MechanismRanges (physics/mechanism.h), named in the message; and at the ranges' corners
// J, W and H are finite.
TEST(LdlpgsRobust, SceneValuesWhoseProductsOverflowAreRefused) {
  struct Case {
    std::vector<std::string> keys;  // a path into valid()
    json value;
    std::string words;
  };
  const std::vector<Case> cases = {
      {{"bodies", "2", "mass"}, 1e-320, "body \"b2\": mass 1e-320 outside [1e-50, 1e+50] kg"},
      {{"bodies", "2", "mass"}, 1e60, "body \"b2\": mass 1e+60"},
      {{"bodies", "1", "inertia"}, {1, 1e-300, 1}, "body \"b1\": inertia 1e-300"},
      {{"bodies", "1", "position"}, {1e308, 0, 0}, "body \"b1\": position 1e+308 beyond +-1e+09 m"},
      {{"bodies", "0", "position"}, {0, -1e155, 0}, "body \"ground\": position -1e+155"},
      {{"bodies", "2", "linear_velocity"}, {0, 1e200, 0}, "body \"b2\": linear velocity 1e+200"},
      {{"bodies", "2", "angular_velocity"}, {0, 0, -1e10}, "body \"b2\": angular velocity -1e+10"},
      {{"constraints", "0", "anchor"}, {1e155, 0, 0}, "constraint 0 (ball between body \"ground\" and body \"b1\"): anchor 1e+155"},
      {{"constraints", "2", "length"}, 1e300, "constraint 2 (rope between body \"b2\" and body \"wall\"): length 1e+300"},
      {{"constraints", "3", "min"}, -1e300, "constraint 3 (angular_limit between body \"b1\" and body \"b2\"): min -1e+300"},
      {{"gravity"}, {0, -1e200, 0}, "gravity: component -1e+200"},
      {{"timestep"}, 1e-300, "timestep: timestep 1e-300 outside [1e-12, 1000] s"},
      {{"timestep"}, 1e300, "timestep: timestep 1e+300"}};
  for (const Case& c : cases) {
    json s = valid();
    json* v = &s;
    for (const std::string& key : c.keys) v = std::isdigit(key[0]) ? &(*v)[std::stoul(key)] : &(*v)[key];
    *v = c.value;
    SCOPED_TRACE(c.words);
    expect_error(s, c.words.substr(0, c.words.find(':')), {c.words, "MechanismRanges"});
  }
  // A force of 1e300 N on the body of 1e-50 kg would be W F dt = 1e348 m/s.
  json s = valid();
  s["bodies"][1]["force"] = {0, 1e300, 0};
  expect_error(s, "body \"b1\"", {"force 1e+300"});

  // The corners: the lightest and heaviest bodies, the farthest anchors, loads and speeds.
  using R = MechanismRanges;
  for (double light : {R::mass_min, R::mass_max}) {
    json corner = valid();
    corner["bodies"][1]["mass"] = light;
    corner["bodies"][1]["inertia"] = {light, light, light};
    corner["bodies"][2]["mass"] = R::mass_max;
    corner["bodies"][2]["inertia"] = {R::mass_min, R::mass_max, R::mass_min};
    corner["bodies"][2]["position"] = {R::coordinate_max, -R::coordinate_max, R::coordinate_max};
    corner["bodies"][2]["linear_velocity"] = {R::velocity_max, 0, 0};
    corner["bodies"][2]["force"] = {0, R::load_max, 0};
    corner["bodies"][1]["torque"] = {R::load_max, 0, 0};
    corner["constraints"][0]["anchor"] = {-R::coordinate_max, R::coordinate_max, -R::coordinate_max};
    const Mechanism m = parse_scene(corner, "corner.json");
    const System system = build_system(m, StepOptions{});
    std::vector<int> sizes;
    const SymmetricCsc h = equality_matrix(system, &sizes);
    auto finite = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
    EXPECT_TRUE(finite(system.jacobian));
    EXPECT_TRUE(finite(system.inverse_mass));
    EXPECT_TRUE(finite(system.rhs));
    EXPECT_TRUE(finite(h.values));
  }
}
}  // namespace
}  // namespace ldlpgs
