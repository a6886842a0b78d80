// The peer engines (peers/) against independent references: the small-angle pendulum's
// analytic motion, zero joint separation at the initial pose, a scene an engine cannot express
// skipped with a message, a cube at rest on the ground in every engine, the penetration metric,
// and the peers command's exit code on bad input.
#include "peers/peer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/io/scenes.h"
#include "tests/support/bodies.h"
#include "tests/support/program.h"

namespace ldlpgs::peers {
namespace {

using Eigen::Vector3d;
using ldlpgs::testing::grounded;
using ldlpgs::testing::run;

// An engine that is not installed, or cannot express a scene, is reported as "not run:", never
// with gtest's "[  SKIPPED ]": ctest (gtest_discover_tests) takes that text in a test's output
// as the whole test skipped, hiding its other checks and failures.
std::vector<const PeerEngine*> available_engines() {
  std::vector<const PeerEngine*> out;
  for (const PeerEngine& e : peer_engines()) {
    if (e.available)
      out.push_back(&e);
    else
      std::printf("not run: %s: %s is not installed\n", e.name.c_str(), e.library.c_str());
  }
  return out;
}

// Every joint type the engines share, on bodies turned off the world axes (so a frame taken in
// the wrong convention shows as a separation): ground -ball- b1 -hinge- b2 -weld- b3, laid out
// along a diagonal so gravity swings it; `with_sliding` adds b3 -prismatic- b4 -cylindrical- b5.
Mechanism mixed_chain(bool with_sliding) {
  Mechanism m = grounded("mixed");
  const Vector3d step(0.4, -0.3, 0.1);
  for (int i = 0; i < (with_sliding ? 5 : 3); ++i) {
    RigidBody b;
    b.name = "b";
    b.name += std::to_string(i);
    b.mass = 1 + i;
    b.inertia = Vector3d(0.02, 0.03, 0.04) * (1 + i);
    b.position = (i + 0.5) * step;
    b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 + 0.4 * i, Vector3d(1, 2, 3 - i).normalized()));
    m.add_body(b);
  }
  const auto& B = m.bodies;
  m.add_constraint(make_ball(0, B[0], 1, B[1], Vector3d::Zero()));
  m.add_constraint(make_axial(ConstraintType::hinge, 1, B[1], 2, B[2], step, Vector3d(0.2, 0.1, 1)));
  m.add_constraint(make_axial(ConstraintType::weld, 2, B[2], 3, B[3], 2 * step, Vector3d(0, 1, 0)));
  if (with_sliding) {
    m.add_constraint(make_axial(ConstraintType::prismatic, 3, B[3], 4, B[4], 3 * step, step));
    m.add_constraint(make_axial(ConstraintType::cylindrical, 4, B[4], 5, B[5], 4 * step, Vector3d(1, 0, 0)));
  }
  return m;
}

// The built-in pendulum (a 1 kg sphere of radius 5 cm on a 1 m ball joint, released 0.1 rad off
// the vertical): theta(t) = 0.1 cos(omega t), omega^2 = m g l / (I + m l^2). At 0.1 rad the
// small-angle error of the phase is theta0^2 / 16 of it (Landau), 2e-4 m of the bob's position
// at t = 1 s; semi-implicit Euler lags by half a step, v dt / 2 = 1.6e-4 m at dt = 1 ms. 1 mm
// is 1% of the swing.
TEST(Peers, PendulumFollowsTheSmallAngleSolution) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("pendulum", &m));
  const double g = 9.81, l = 1, inertia = 2.0 / 5 * 0.05 * 0.05, omega = std::sqrt(g * l / (inertia + l * l));
  const double seconds = 1;
  m.timestep = 0.001;
  for (const PeerEngine* e : available_engines()) {
    const PeerResult r = e->run(m, seconds);
    ASSERT_TRUE(r.ran()) << e->name << ": " << r.skipped;
    ASSERT_EQ(r.steps, 1000) << e->name;
    for (int s : {250, 500, 750, 1000}) {
      const double theta = 0.1 * std::cos(omega * s * m.timestep);
      const Vector3d expected(l * std::sin(theta), -l * std::cos(theta), 0);
      EXPECT_LT((r.positions[s * 2 + 1] - expected).norm(), 1e-3) << e->name << " at step " << s;
    }
  }
}

TEST(Peers, SeparationIsZeroAtTheInitialPose) {
  for (bool sliding : {false, true}) {
    const Mechanism m = mixed_chain(sliding);
    EXPECT_LT(joint_separation(m), 1e-14);
    for (const PeerEngine* e : available_engines()) {
      const PeerResult r = e->run(m, 0);
      if (!r.ran()) {
        std::printf("not run: %s: %s\n", e->name.c_str(), r.skipped.c_str());
        EXPECT_TRUE(sliding && (r.skipped.find("prismatic") != std::string::npos ||
                                r.skipped.find("cylindrical") != std::string::npos))
            << e->name << ": " << r.skipped;
        continue;
      }
      EXPECT_EQ(r.steps, 0);
      EXPECT_LT(r.separation, 1e-12) << e->name;
    }
  }
}

// Every engine builds the joints in the same places and the bodies with the same inertia: after
// 0.5 s of swinging, the mixed chain holds together in each (separation under 1 cm: ERP and
// MuJoCo's soft constraints let the joints give by millimetres; an anchor in the wrong frame, by
// decimetres) and moves as our direct solver at the same timestep does (the same semi-implicit
// Euler discretization, so the first-order error of the step, 1.5 cm here, cancels), to 2 mm
// (a wrong inertia frame or gravity moves the bodies by decimetres in 0.5 s). Not bullet-si-10
// (nor -2f, the same without contacts): 10 sequential-impulse iterations leave this chain's
// velocity rows unconverged (9 mm off);
// bullet-si-100 checks Bullet's construction. Nor mujoco-reduced: semi-implicit Euler on the
// joint coordinates is another discretization (6 mm off here); the pendulum checks it. Nor our
// post-stabilized solvers: projecting positions changes the discretization too (3 mm off here).
TEST(Peers, MixedChainMovesAsOurDirectSolver) {
  const Mechanism m = mixed_chain(false);
  const PeerResult reference = find_peer("ldlpgs-direct-baumgarte")->run(m, 0.5);
  ASSERT_TRUE(reference.ran());
  for (const PeerEngine* e : available_engines()) {
    PeerResult r = e->run(m, 0.5);
    ASSERT_TRUE(r.ran()) << e->name << ": " << r.skipped;
    compare_to(reference, &r);
    std::printf("%-18s separation %.3e m, against ldlpgs-direct-baumgarte %.3e m\n", e->name.c_str(), r.separation,
                r.trajectory_error);
    EXPECT_LT(r.separation, 1e-2) << e->name;
    const bool post_stabilized = e->name == "ldlpgs-ldl-pgs" || e->name == "ldlpgs-direct";
    const bool ten_iterations = e->name == "bullet-si-10" || e->name == "bullet-si-10-2f";
    if (!ten_iterations && e->name != "mujoco-reduced" && !post_stabilized) {
      EXPECT_LT(r.trajectory_error, 2e-3) << e->name;
    }
  }
}

TEST(Peers, SceneAnEngineCannotExpressIsSkippedWithAMessage) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("rope-bridge", &m));  // ropes and rods
  for (const PeerEngine* e : available_engines()) {
    if (e->name.rfind("ldlpgs-", 0) == 0 && e->name != "ldlpgs-direct") continue;  // ours take every type
    const PeerResult r = e->run(m, 0.1);
    EXPECT_FALSE(r.ran()) << e->name;
    EXPECT_TRUE(r.skipped.find("rod") != std::string::npos || r.skipped.find("rope") != std::string::npos)
        << e->name << ": " << r.skipped;
  }
}

// A 1 kg unit cube (friction 0.6) resting on a ground plane at y = 0, y up, 1/60 s steps.
Mechanism cube_on_ground() {
  Mechanism m = grounded("cube-on-ground");
  m.timestep = 1.0 / 60;
  m.gravity = Vector3d(0, -9.81, 0);
  Shape plane;
  plane.type = ShapeType::plane;
  plane.normal = Vector3d::UnitY();
  plane.friction = 0.6;
  m.bodies[0].shapes.push_back(plane);
  RigidBody cube;
  cube.name = "cube";
  cube.mass = 1;
  cube.inertia = Vector3d::Constant(1.0 / 6);  // m (1^2 + 1^2) / 12
  cube.position = Vector3d(0, 0.5, 0);
  Shape box;
  box.type = ShapeType::box;
  box.half_extents = Vector3d::Constant(0.5);
  box.friction = 0.6;
  cube.shapes.push_back(box);
  m.add_body(cube);
  return m;
}

// The metric against hand-placed poses: the cube 3 cm into the ground, then tilted 0.1 rad
// about z at centre height 0.5, its lowest corner 0.5 (cos 0.1 + sin 0.1) - 0.5 below the plane.
TEST(Peers, PenetrationOfRecordedPoses) {
  const Mechanism m = cube_on_ground();
  PeerResult r;
  r.steps = 2;
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.1, Vector3d::UnitZ()));
  for (const auto& [y, q] : {std::pair{0.6, Eigen::Quaterniond::Identity()}, std::pair{0.47, Eigen::Quaterniond::Identity()},
                             std::pair{0.5, tilt}}) {
    r.positions.insert(r.positions.end(), {Vector3d::Zero(), Vector3d(0, y, 0)});
    r.orientations.insert(r.orientations.end(), {Eigen::Quaterniond::Identity(), q});
  }
  EXPECT_NEAR(penetration_max(m, r), 0.5 * (std::cos(0.1) + std::sin(0.1)) - 0.5, 1e-12);
  r.orientations.back() = Eigen::Quaterniond::Identity();
  EXPECT_NEAR(penetration_max(m, r), 0.03, 1e-12);
  r.finite = false;
  EXPECT_EQ(penetration_max(m, r), std::numeric_limits<double>::infinity());
}

// cube_on_ground with a 1 kg ball (radius 0.25 m) at x = -2 and a 1 kg capsule (radius 0.05 m,
// half length 0.2 m) standing on its end at x = 2, its shape turned from z to y and 0.1 m below
// the body's centre: each at rest, the centres at the heights 0.5, 0.25 and 0.35 m.
Mechanism shapes_on_ground() {
  Mechanism m = cube_on_ground();
  RigidBody ball;
  ball.name = "ball";
  ball.inertia = Vector3d::Constant(0.4 * 0.25 * 0.25);
  ball.position = Vector3d(-2, 0.25, 0);
  Shape sphere;
  sphere.type = ShapeType::sphere;
  sphere.radius = 0.25;
  ball.shapes.push_back(sphere);
  m.add_body(ball);
  RigidBody stick;
  stick.name = "stick";
  stick.inertia = Vector3d(0.02, 0.001, 0.02);
  stick.position = Vector3d(2, 0.35, 0);
  Shape capsule;
  capsule.type = ShapeType::capsule;
  capsule.radius = 0.05;
  capsule.half_length = 0.2;
  capsule.position = Vector3d(0, -0.1, 0);
  capsule.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitX()));
  stick.shapes.push_back(capsule);
  m.add_body(stick);
  return m;
}

// Every engine's contacts hold a cube, a ball and a standing capsule on the ground for 0.5 s:
// their centres at the analytic rest heights to 1 cm (a missing plane falls 1.2 m; a geom off
// its body, turned the wrong way, or of the wrong size rests elsewhere; the capsule lying down,
// 25 cm lower), not moved sideways by 1 cm (Bullet's contact manifold
// gains one point per step, so its cube rocks at first and slides 1.3 mm; with its shape off
// centre it would tip over), the penetration under 1 cm (without speculative contacts, ODE's
// QuickStep at 20 iterations and Bullet let gravity's first steps in by 2 to 4 mm, MuJoCo's soft
// contacts 3 mm) and at least the sinking of the centre (the metric sees what the poses show).
// Not our direct solvers (equalities only).
TEST(Peers, ShapesRestOnTheGround) {
  const Mechanism m = shapes_on_ground();
  const double rest[] = {0, 0.5, 0.25, 0.35};  // centre heights (m)
  for (const PeerEngine* e : available_engines()) {
    const PeerResult r = e->run(m, 0.5);
    if (e->name.rfind("ldlpgs-direct", 0) == 0) {
      EXPECT_FALSE(r.ran()) << e->name;
      continue;
    }
    ASSERT_TRUE(r.ran()) << e->name << ": " << r.skipped;
    ASSERT_TRUE(r.finite) << e->name;
    std::printf("%-18s penetration %.3e m, rest heights", e->name.c_str(), r.penetration_max);
    for (size_t b = 1; b < m.bodies.size(); ++b) {
      const Vector3d end = r.positions[r.steps * m.bodies.size() + b], start = m.bodies[b].position;
      std::printf(" %.6f", end.y());
      EXPECT_NEAR(end.y(), rest[b], 1e-2) << e->name << ": " << m.bodies[b].name;
      EXPECT_LT(std::hypot(end.x() - start.x(), end.z() - start.z()), 1e-2) << e->name << ": " << m.bodies[b].name;
      EXPECT_GE(r.penetration_max, rest[b] - end.y() - 1e-9) << e->name << ": " << m.bodies[b].name;
    }
    std::printf(" m\n");
    EXPECT_LT(r.penetration_max, 1e-2) << e->name;
  }
}

// The metric sees failure: ODE's QuickStep at its default 20 iterations cannot hold a 1000 kg
// cube on a 1 kg one (the mass ratio PGS does not converge on), and the stack sinks; ODE's dense
// LCP (dWorldStep) holds it. No contact scene has a reference trajectory.
TEST(Peers, HeavyStackSinksUnderQuickStep) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("box-stack-1000", &m));
  EXPECT_FALSE(reference_run(m, 1).ran());
  EXPECT_FALSE(rk4_reference_run(m, 1).ran());
  for (const char* name : {"ode-quickstep-20", "ode-step"}) {
    const PeerEngine* e = find_peer(name);
    if (!e->available) {
      std::printf("not run: %s: %s is not installed\n", name, e->library.c_str());
      continue;
    }
    const PeerResult r = e->run(m, 2);
    ASSERT_TRUE(r.ran()) << name << ": " << r.skipped;
    std::printf("%s: penetration %.3e m\n", name, r.penetration_max);
    if (e->name == "ode-step")
      EXPECT_LT(r.penetration_max, 1e-2);
    else
      EXPECT_GT(r.penetration_max, 0.1);
  }
}

#ifdef LDLPGS_HAVE_MUJOCO  // MuJoCo's RK4 and MJCF files (build.sh requires MuJoCo)

// The two references of peer.h (our direct solver and MuJoCo's reduced-coordinate RK4, each at
// timestep / 16) on chain-10 swinging (gravity turned 45 degrees off the chain, so every link
// moves by decimetres in 1 s): RK4's error is negligible, so their distance is direct's
// discretization error at timestep / 16, first order; at the scene's own timestep it is 16x
// larger. Measured (Release, GCC 12, MuJoCo 2.2.2): 2.555e-3 m at timestep / 16, 3.769e-2 m at
// the timestep (14.8x); the bound is that measurement rounded up, 3e-3 m.
TEST(Peers, ReferencesAgreeOnASwingingChain) {
  Mechanism m;
  ASSERT_TRUE(builtin_scene("chain-10", &m));
  m.gravity = 9.81 * Vector3d(std::sqrt(0.5), -std::sqrt(0.5), 0);
  const double seconds = 1;
  const PeerResult rk4 = rk4_reference_run(m, seconds);
  ASSERT_TRUE(rk4.ran()) << rk4.skipped;
  PeerResult direct16 = reference_run(m, seconds);
  ASSERT_TRUE(direct16.ran()) << direct16.skipped;
  ASSERT_EQ(rk4.steps, 16 * peer_steps(m, seconds));
  ASSERT_EQ(direct16.steps, rk4.steps);
  const size_t last = rk4.positions.size() - 1;
  EXPECT_GT((rk4.positions[last] - rk4.positions[m.bodies.size() - 1]).norm(), 0.1);  // it swings
  compare_to(rk4, &direct16);
  PeerResult direct = find_peer("ldlpgs-direct")->run(m, seconds);
  compare_to(rk4, &direct);
  std::printf("direct at timestep / 16 against RK4: %.3e m; direct at timestep: %.3e m\n", direct16.trajectory_error,
              direct.trajectory_error);
  EXPECT_LT(direct16.trajectory_error, 3e-3);
  EXPECT_GT(direct.trajectory_error, 8 * direct16.trajectory_error);  // first order: about 16x
}

// An MJCF scene's own file in MuJoCo (mujoco-mjcf) against the analytic motion: the humanoid
// without contacts falls freely (gravity is uniform, so no joint is loaded). Semi-implicit Euler
// places every body at p0 + g dt^2 n (n + 1) / 2 after n steps; RK4 (the second reference) at
// p0 + g t^2 / 2, exactly for a quadratic. A body in MuJoCo's order other than ours, or its
// body origin in place of the centre of mass, is off by centimetres.
TEST(Peers, MjcfPeerFallsFreely) {
  const std::string path = "/usr/share/mujoco/model/humanoid/humanoid.xml";
  Mechanism m = load_mjcf(path);
  for (RigidBody& b : m.bodies) b.shapes.clear();  // a free fall: no floor (MuJoCo's peer has contacts off)
  const double seconds = 1, dt = m.timestep;
  const PeerResult rk4 = rk4_reference_run(m, seconds, path);
  ASSERT_TRUE(rk4.ran()) << rk4.skipped;
  const size_t nb = m.bodies.size();
  for (int s = 0; s <= rk4.steps; s += rk4.steps / 4)
    for (size_t b = 1; b < nb; ++b) {
      const double t = s * dt / 16;
      EXPECT_LT((rk4.positions[s * nb + b] - (m.bodies[b].position + 0.5 * t * t * m.gravity)).norm(), 1e-9)
          << "body " << b << " at step " << s;
    }
  for (const PeerEngine& e : {mjcf_peer(path), *find_peer("ldlpgs-ldl-pgs")}) {
    const PeerResult r = e.run(m, seconds);
    ASSERT_TRUE(r.ran()) << e.name << ": " << r.skipped;
    EXPECT_LT(r.separation, 1e-6) << e.name;
    for (int s = 0; s <= r.steps; s += r.steps / 4)
      for (size_t b = 1; b < nb; ++b)
        EXPECT_LT((r.positions[s * nb + b] - (m.bodies[b].position + 0.5 * dt * dt * s * (s + 1) * m.gravity)).norm(),
                  1e-9)
            << e.name << ": body " << b << " at step " << s;
  }
}

#endif

TEST(Peers, FindPeerByName) {
  ASSERT_NE(find_peer("ode-quickstep-20"), nullptr);
  EXPECT_EQ(find_peer("ode-quickstep-20")->name, "ode-quickstep-20");
  EXPECT_EQ(find_peer("no-such-engine"), nullptr);
}

TEST(PeersCommand, UnknownSceneExitsTwo) { EXPECT_EQ(run("peers no-such-scene").code, 2); }
TEST(PeersCommand, UnknownEngineExitsTwo) { EXPECT_EQ(run("peers pendulum --engines no-such-engine").code, 2); }
TEST(PeersCommand, PendulumRuns) { EXPECT_EQ(run("peers pendulum --seconds 0.1 --json").code, 0); }
#ifdef LDLPGS_HAVE_MUJOCO
TEST(PeersCommand, MjcfSceneRuns) {
  // its actuator's slider-crank transmission is not modelled: refused unless allowed
  const std::string command = "peers /usr/share/mujoco/model/slider_crank/slider_crank.xml --seconds 0.1 --engines mujoco-mjcf";
  EXPECT_EQ(run(command).code, 2);
  EXPECT_EQ(run(command + " --allow-dropped").code, 0);
}
#endif

}  // namespace
}  // namespace ldlpgs::peers
