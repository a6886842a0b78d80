// view/recording.cpp: what the viewer's page draws, against the mechanism it came from and the
// steps' own reports.
#include "view/recording.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ldlpgs/physics/io/scenes.h"

namespace ldlpgs::view {
namespace {

Mechanism scene(const char* name) {
  Mechanism m;
  EXPECT_TRUE(builtin_scene(name, &m)) << name;
  return m;
}

// What shatter() returns for a mechanism left whole: every body its own shard.
ShatterResult whole(const Mechanism& m) {
  ShatterResult r;
  r.mechanism = m;
  for (size_t i = 0; i < m.bodies.size(); ++i) r.shards.push_back({static_cast<int>(i)});
  return r;
}

StepOptions options() {
  StepOptions o;
  o.diagnostics = true;  // the separation and penetration the frames keep
  return o;
}

// A uniform box's principal moments, I_x = m (b^2 + c^2) / 3 with half extents a, b, c.
Eigen::Vector3d moments(double m, const Eigen::Vector3d& h) {
  return {m * (h.y() * h.y() + h.z() * h.z()) / 3, m * (h.x() * h.x() + h.z() * h.z()) / 3,
          m * (h.x() * h.x() + h.y() * h.y()) / 3};
}

TEST(BoxFromInertia, GivesBackTheBoxOfThoseMoments) {
  for (const Eigen::Vector3d& h : {Eigen::Vector3d(0.5, 0.2, 0.1), Eigen::Vector3d(1.1, 0.25, 0.5), Eigen::Vector3d(3, 3, 3)})
    for (double mass : {0.1, 8.0, 800.0}) {
      const Eigen::Vector3d got = box_from_inertia(mass, moments(mass, h));
      EXPECT_LT((got - h).norm(), 1e-12 * h.norm()) << got.transpose() << " for " << h.transpose();
    }
}

// A thin rod's moments (I_x = 0, I_y = I_z) belong to a box of no thickness: it gets a hundredth
// of its length; moments no box has (I_x > I_y + I_z) too.
TEST(BoxFromInertia, MomentsOfNoSolidBoxGiveAThinSide) {
  const Eigen::Vector3d rod = box_from_inertia(2, moments(2, Eigen::Vector3d(0, 0, 1)));
  EXPECT_NEAR(rod.z(), 1, 1e-12);
  EXPECT_NEAR(rod.x(), 0.01, 1e-12);
  EXPECT_NEAR(rod.y(), 0.01, 1e-12);
  const Eigen::Vector3d impossible = box_from_inertia(1, Eigen::Vector3d(5, 1, 1));
  EXPECT_TRUE(impossible.allFinite());
  EXPECT_NEAR(impossible.x(), 0.01 * impossible.maxCoeff(), 1e-12);
}

// Frames come at most frame_rate times per simulated second, the first the initial pose and the
// last the run's end, each holding the poses the simulation had then.
TEST(Recording, FramesAreTheSimulationsPosesAtTheFrameRate) {
  const Mechanism m = scene("chain-10");
  Recording recording(m, whole(m));
  Simulation sim(m, options());
  std::vector<std::vector<double>> expected{{}};  // the poses at each frame's time (positions)
  expected[0].resize(3 * m.bodies.size());
  for (size_t b = 0; b < m.bodies.size(); ++b)
    for (int d = 0; d < 3; ++d) expected[0][3 * b + d] = m.bodies[b].position[d];
  std::vector<double> p(3 * m.bodies.size());
  for (int s = 0; s < 205; ++s) {
    const int before = recording.frames();
    recording.add(sim, sim.step());
    if (recording.frames() > before) {
      sim.get_positions(p);
      expected.push_back(p);
    }
  }
  recording.finish(sim);
  sim.get_positions(p);
  if (expected.size() < static_cast<size_t>(recording.frames())) expected.push_back(p);
  ASSERT_EQ(recording.frames(), static_cast<int>(expected.size()));
  // 2.05 s of 0.01 s steps, at most 30 frames per second: every 4th step (0.04 s), the start and the end
  EXPECT_EQ(recording.frames(), 53);
  EXPECT_EQ(recording.steps(), 205);
  const std::vector<float>& t = recording.time();
  EXPECT_EQ(t.front(), 0.0f);
  EXPECT_FLOAT_EQ(t.back(), static_cast<float>(sim.time()));
  for (size_t f = 1; f + 1 < t.size(); ++f) EXPECT_NEAR(t[f] - t[f - 1], 0.04, 0.0051) << f;  // every 4th step of 0.01 s
  const size_t n = m.bodies.size();
  for (size_t f = 0; f < expected.size(); ++f)
    for (size_t i = 0; i < 3 * n; ++i)
      ASSERT_NEAR(recording.positions()[3 * n * f + i], expected[f][i], 1e-6) << "frame " << f;
  // orientations: unit quaternions to 1/32767
  std::vector<double> q(4 * n);
  sim.get_orientations(q);
  for (size_t i = 0; i < 4 * n; ++i)
    EXPECT_NEAR(recording.orientations()[4 * n * (expected.size() - 1) + i] / 32767.0, q[i], 1.0 / 32767);
}

// Past max_frames every other frame goes and the period doubles: the run still ends on a frame,
// times keep increasing, and each frame's separation is the largest of the steps since the
// previous one, so the largest over the frames is the largest over all steps.
TEST(Recording, DecimationKeepsTheEndAndEveryStepsPeak) {
  const Mechanism m = scene("four-bar");
  RecordOptions o;
  o.max_frames = 20;
  Recording recording(m, whole(m), o);
  StepOptions stepping = options();
  stepping.post_stabilize = 0;  // a separation of millimetres to record (papers/physics.md)
  Simulation sim(m, stepping);
  float peak = 0;
  for (int s = 0; s < 1000; ++s) {
    const StepReport r = sim.step();
    peak = std::max(peak, static_cast<float>(r.error.position_max));
    recording.add(sim, r);
  }
  recording.finish(sim);
  EXPECT_LE(recording.frames(), 21);
  EXPECT_GE(recording.frames(), 10);
  EXPECT_FLOAT_EQ(recording.time().back(), static_cast<float>(sim.time()));
  for (int f = 1; f < recording.frames(); ++f) EXPECT_LT(recording.time()[f - 1], recording.time()[f]);
  EXPECT_GT(peak, 1e-4f);
  EXPECT_EQ(*std::max_element(recording.separation().begin(), recording.separation().end()), peak);
  EXPECT_EQ(recording.positions().size(), 3 * m.bodies.size() * recording.frames());
  EXPECT_EQ(recording.orientations().size(), 4 * m.bodies.size() * recording.frames());
  EXPECT_EQ(recording.contact_start().size(), static_cast<size_t>(recording.frames()) + 1);
}

// A shattered body without shapes is drawn as its shards, each a box of its own inertia, in the
// body's colour; a shattered body's shapes ride on its first shard where the body had them.
TEST(Recording, ShardsShareTheirBodysColourAndShapesStayWhereTheyWere) {
  Mechanism m = scene("multi-wheeled-vehicle");
  const int chassis = m.find_body("chassis");
  ASSERT_GE(chassis, 0);
  const ShatterResult plain = shatter(m);
  ASSERT_GT(plain.shards[chassis].size(), 1u);
  Recording boxes(m, plain);
  int chassis_solids = 0;
  for (const Solid& s : boxes.solids()) {
    if (s.group != chassis) continue;
    ++chassis_solids;
    EXPECT_TRUE(s.from_inertia);
    const RigidBody& shard = plain.mechanism.bodies[s.body];
    EXPECT_EQ(s.size, box_from_inertia(shard.mass, shard.inertia));
  }
  EXPECT_EQ(chassis_solids, static_cast<int>(plain.shards[chassis].size()));

  Shape box;
  box.type = ShapeType::box;
  box.half_extents = {1.0, 0.2, 0.4};
  box.position = {0.3, -0.1, 0.2};
  box.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()));
  m.bodies[chassis].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  m.bodies[chassis].shapes = {box};
  const ShatterResult shattered = shatter(m);
  Recording shaped(m, shattered);
  const Solid* solid = nullptr;
  for (const Solid& s : shaped.solids())
    if (s.group == chassis) {
      EXPECT_EQ(solid, nullptr) << "one shape, one solid";
      solid = &s;
    }
  ASSERT_NE(solid, nullptr);
  EXPECT_FALSE(solid->from_inertia);
  EXPECT_EQ(solid->size, box.half_extents);
  const RigidBody& on = shattered.mechanism.bodies[solid->body];
  const RigidBody& was = m.bodies[chassis];
  EXPECT_LT((on.to_world(solid->position) - was.to_world(box.position)).norm(), 1e-12);
  EXPECT_LT(((on.orientation * solid->orientation).coeffs() - (was.orientation * box.orientation).coeffs()).norm(), 1e-12);
  EXPECT_EQ(shaped.joints().size(), m.constraints.size());  // the scene's joints, not the welds
}

// A contact's recorded impulse is the step's impulse on body b in the world (on a against a
// static b): its part along the detected normal (a to b) is the normal impulse (its negative),
// and its length that of (normal, t1, t2). The box stack has the ground as body a of its
// contacts, the wheeled vehicle as body b: either way the ground's impulse pushes up.
TEST(Recording, ContactsCarryTheirImpulsesInTheWorld) {
  int static_a = 0, static_b = 0;  // contacts with the ground as body a, as body b
  for (const char* name : {"box-stack-1000", "multi-wheeled-vehicle-on-ground"}) {
    SCOPED_TRACE(name);
    const Mechanism m = scene(name);
    RecordOptions o;
    o.frame_rate = 1e6;  // every step a frame
    Recording recording(m, whole(m), o);
    Simulation sim(m, options());
    for (int s = 0; s < 30; ++s) recording.add(sim, sim.step());
    const int f = recording.frames() - 1;
    const uint32_t first = recording.contact_start()[f], last = recording.contact_start()[f + 1];
    ASSERT_EQ(last - first, sim.contacts().size());
    ASSERT_GT(last - first, 0u);
    double up = 0;  // the ground's impulses on the dynamic bodies along -gravity
    for (uint32_t k = first; k < last; ++k) {
      const Contact& c = sim.contacts()[k - first];
      const float* x = &recording.contacts()[6 * k];
      const Eigen::Vector3d point(x[0], x[1], x[2]), impulse(x[3], x[4], x[5]);
      EXPECT_LT((point - c.point.position).norm(), 1e-6);
      const bool a_static = m.bodies[c.body_a].is_static, b_static = m.bodies[c.body_b].is_static;
      static_a += a_static;
      static_b += b_static;
      EXPECT_NEAR(impulse.dot(c.point.normal), (b_static ? -1 : 1) * c.impulse[0], 1e-5 * (1 + std::abs(c.impulse[0])));
      EXPECT_NEAR(impulse.norm(), Eigen::Vector3d(c.impulse[0], c.impulse[1], c.impulse[2]).norm(), 1e-5 * (1 + impulse.norm()));
      if (a_static || b_static) up += impulse.dot(-m.gravity.normalized());
    }
    EXPECT_GT(up, 0) << "the ground holds the bodies up";
  }
  EXPECT_GT(static_a, 0);
  EXPECT_GT(static_b, 0);
}

}  // namespace
}  // namespace ldlpgs::view
