// physics/step: the velocity step against analytic solutions (pendulum period, rest, momentum),
// against a dense solve of the same step written independently here, and the claim of the talk
// (a heavy load on a chain holds under ldl-pgs, stretches under pgs at the same time budget).
#include "ldlpgs/physics/step.h"

#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/sparse/error.h"
#include "tests/support/allocation_counter.h"  // (replaces operator new: one per executable)
#include "tests/support/bodies.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <numbers>
#include <random>

namespace ldlpgs {
namespace {

using testing::dynamic_body;
using testing::numbered;
using testing::static_body;

// A cube of side `size`: moments m size^2 / 6.
RigidBody box(const std::string& name, double mass, const Eigen::Vector3d& position, double size = 0.1) {
  return dynamic_body(name, mass, Eigen::Vector3d::Constant(mass * size * size / 6), position);
}

StepOptions options(SolverKind kind, int iterations = 10) {
  StepOptions o;
  o.solver.kind = kind;
  o.solver.iterations = iterations;
  o.diagnostics = true;
  return o;
}

// The velocity step alone: tests of the solvers' impulses and of what the velocity step
// conserves (post-stabilization moves positions, so it changes r x p and the next step's pose).
StepOptions velocity_only(SolverKind kind, int iterations = 10) {
  StepOptions o = options(kind, iterations);
  o.post_stabilize = 0;
  return o;
}

// n links of length l (rods of 5 cm square section) hanging from the ground by ball joints at
// `angle` from the vertical, the last of `load` times the mass and inertia of a link.
Mechanism hanging_chain(int n, double load = 1, double angle = 0, double l = 0.5) {
  Mechanism m;
  m.name = "chain";
  m.add_body(static_body("ground"));
  const Eigen::Vector3d down(std::sin(angle), -std::cos(angle), 0);
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
  for (int i = 0; i < n; ++i) {
    const double mass = i == n - 1 ? load : 1.0, t = 0.05;
    RigidBody link = box(numbered("link", i), mass, l * (i + 0.5) * down);
    link.inertia = mass / 12 * Eigen::Vector3d(l * l + t * t, 2 * t * t, l * l + t * t);
    link.orientation = tilt;
    m.add_body(link);
    m.add_constraint(m.ball(i, i + 1, l * i * down));
  }
  return m;
}

// Complete elliptic integral via the arithmetic-geometric mean: the exact period of a pendulum
// of amplitude a is T = 2 pi sqrt(L / g) / AGM(1, cos(a / 2)).
double agm(double x, double y) {
  for (int i = 0; i < 40; ++i) std::tie(x, y) = std::pair(0.5 * (x + y), std::sqrt(x * y));
  return x;
}

TEST(Step, PendulumPeriodMatchesTheAnalyticValue) {
  const double l = 1, amplitude = 0.3, g = 9.81;
  for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs, SolverKind::block_gs}) {
    Mechanism m;
    m.timestep = 1e-3;
    m.add_body(static_body("ground"));
    RigidBody bob = box("bob", 1, Eigen::Vector3d(l * std::sin(amplitude), -l * std::cos(amplitude), 0));
    m.add_body(bob);
    m.add_constraint(m.ball(0, 1, Eigen::Vector3d::Zero()));
    // a compound pendulum: equivalent length (I + m l^2) / (m l)
    const double l_eq = (bob.inertia[2] + bob.mass * l * l) / (bob.mass * l);
    const double expected = 2 * std::numbers::pi * std::sqrt(l_eq / g) / agm(1, std::cos(amplitude / 2));
    Simulation sim(std::move(m), options(kind));
    std::vector<double> crossings;  // times x crosses 0 going left
    double x_prev = sim.mechanism().bodies[1].position.x();
    while (crossings.size() < 4) {
      ASSERT_TRUE(sim.step().result.ok());
      const double x = sim.mechanism().bodies[1].position.x();
      if (x_prev > 0 && x <= 0) crossings.push_back(sim.time() - sim.mechanism().timestep * x / (x - x_prev));
      x_prev = x;
      ASSERT_LT(sim.time(), 20.0);
    }
    const double period = (crossings[3] - crossings[0]) / 3;
    std::printf("%s: period %.6f s, analytic %.6f s, relative error %.2e\n", to_string(kind), period, expected,
                std::abs(period - expected) / expected);
    EXPECT_NEAR(period, expected, 1e-3 * expected) << to_string(kind);
  }
}

TEST(Step, ChainAtRestStaysAtRest) {
  for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs}) {
    const Mechanism start = hanging_chain(10);
    Simulation sim(start, options(kind));
    for (int s = 0; s < 500; ++s) ASSERT_TRUE(sim.step().result.ok());
    double moved = 0, speed = 0;
    for (size_t b = 0; b < start.bodies.size(); ++b) {
      moved = std::max(moved, (sim.mechanism().bodies[b].position - start.bodies[b].position).norm());
      speed = std::max(speed, sim.mechanism().bodies[b].linear_velocity.norm());
    }
    std::printf("%s: after 5 s at rest, largest displacement %.2e m, speed %.2e m/s\n", to_string(kind), moved, speed);
    EXPECT_LT(moved, 1e-6) << to_string(kind);
    EXPECT_LT(speed, 1e-6) << to_string(kind);
  }
}

Eigen::Vector3d linear_momentum(const Mechanism& m) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (const RigidBody& b : m.bodies)
    if (!b.is_static) p += b.mass * b.linear_velocity;
  return p;
}

Eigen::Vector3d angular_momentum(const Mechanism& m) {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (const RigidBody& b : m.bodies)
    if (!b.is_static) l += b.position.cross(b.mass * b.linear_velocity) + b.inertia_world() * b.angular_velocity;
  return l;
}

// Free bodies of different shapes joined by every equality type, spinning, no gravity.
Mechanism free_mechanism() {
  Mechanism m;
  m.gravity.setZero();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), pos(0.5, 2);
  const int n = 7;
  for (int i = 0; i < n; ++i) {
    RigidBody b = box(numbered("b", i), pos(rng), Eigen::Vector3d(0.6 * i, 0.1 * u(rng), 0.1 * u(rng)));
    b.inertia = Eigen::Vector3d(pos(rng), pos(rng), pos(rng)) * 0.05;
    b.orientation = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
    b.linear_velocity = Eigen::Vector3d(u(rng), u(rng), u(rng));
    b.angular_velocity = 3 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    m.add_body(b);
  }
  const Eigen::Vector3d axis(0.3, 1, -0.2);
  auto mid = [&](int i) { return 0.5 * (m.bodies[i].position + m.bodies[i + 1].position); };
  m.add_constraint(m.ball(0, 1, mid(0)));
  m.add_constraint(m.axial(ConstraintType::hinge, 1, 2, mid(1), axis));
  m.add_constraint(m.axial(ConstraintType::cylindrical, 2, 3, mid(2), axis));
  m.add_constraint(m.axial(ConstraintType::prismatic, 3, 4, mid(3), axis));
  m.add_constraint(m.distance(ConstraintType::rod, 4, 5, m.bodies[4].position,
                                 m.bodies[5].position + Eigen::Vector3d(0, 0.05, 0)));
  m.add_constraint(m.axial(ConstraintType::weld, 5, 6, mid(5), axis));
  return m;
}

TEST(Step, FreeMechanismConservesMomentum) {
  // Every constraint impulse is internal. Linear momentum is kept to rounding. Angular momentum
  // (about the origin) is kept exactly but for one term: a ball row's impulse lambda acts at
  // two points c apart (c its position error), a moment c x lambda. The test sums those moments
  // from the constraints and impulses and requires the drift to equal the sum to rounding.
  for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs}) {
    Simulation sim(free_mechanism(), velocity_only(kind));
    const Eigen::Vector3d p0 = linear_momentum(sim.mechanism()), l0 = angular_momentum(sim.mechanism());
    Eigen::Vector3d moments = Eigen::Vector3d::Zero();
    for (int s = 0; s < 300; ++s) {
      std::vector<Eigen::Vector3d> c;  // ball-row errors before the step, per constraint
      for (const Constraint& con : sim.mechanism().constraints) {
        const ConstraintRows r = evaluate(con, sim.mechanism().bodies[con.body_a], sim.mechanism().bodies[con.body_b]);
        c.emplace_back(r.c[0], r.c[1], r.c[2]);
      }
      ASSERT_TRUE(sim.step().result.ok());
      int row = 0;
      for (size_t k = 0; k < c.size(); ++k) {
        const ConstraintType type = sim.mechanism().constraints[k].type;
        if (type == ConstraintType::ball || type == ConstraintType::hinge || type == ConstraintType::weld)
          moments += c[k].cross(Eigen::Vector3d(sim.impulses()[row], sim.impulses()[row + 1], sim.impulses()[row + 2]));
        row += num_rows(type);
      }
    }
    const double dp = (linear_momentum(sim.mechanism()) - p0).norm() / p0.norm();
    const Eigen::Vector3d drift = angular_momentum(sim.mechanism()) - l0;
    const double unexplained = (drift - moments).norm() / l0.norm();
    std::printf("%s, 3 s: relative drift of momentum %.2e; of angular momentum %.2e, of which %.2e not explained "
                "by the ball rows' c x lambda\n", to_string(kind), dp, drift.norm() / l0.norm(), unexplained);
    EXPECT_LT(dp, 1e-12);
    EXPECT_LT(unexplained, 1e-12);
  }
}

// A four-bar linkage: crank A-B, coupler B-C, rocker C-D, hinges about z at A, B, C, D, A and D
// on the ground: 20 rows on 18 freedoms, 3 of them redundant (H singular without compliance).
Mechanism four_bar() {
  Mechanism m;
  m.add_body(static_body("ground"));
  const Eigen::Vector3d a(0, 0, 0), b(0, 1, 0), c(2, 1.2, 0), d(2, 0, 0), z(0, 0, 1);
  m.add_body(box("crank", 1, 0.5 * (a + b)));
  m.add_body(box("coupler", 2, 0.5 * (b + c)));
  m.add_body(box("rocker", 1, 0.5 * (c + d)));
  m.bodies[1].angular_velocity = Eigen::Vector3d(0, 0, 2);
  m.add_constraint(m.axial(ConstraintType::hinge, 0, 1, a, z));
  m.add_constraint(m.axial(ConstraintType::hinge, 1, 2, b, z));
  m.add_constraint(m.axial(ConstraintType::hinge, 2, 3, c, z));
  m.add_constraint(m.axial(ConstraintType::hinge, 3, 0, d, z));
  return m;
}

// The step written out densely from the bodies and the constraints' rows, independently of
// solver/: V1 = V0 + g dt + W J^T lambda, (H + eps diag H) lambda = -beta c / dt - J (V0 + g dt).
std::vector<Eigen::Vector3d> dense_step_velocities(const Mechanism& m, const StepOptions& o) {
  std::vector<int> column(m.bodies.size(), -1);
  int n = 0;
  for (size_t b = 0; b < m.bodies.size(); ++b)
    if (!m.bodies[b].is_static) column[b] = n++;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(6 * n, 6 * n);
  Eigen::VectorXd v0(6 * n);
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    if (column[b] < 0) continue;
    const RigidBody& body = m.bodies[b];
    w.block<3, 3>(6 * column[b], 6 * column[b]) = Eigen::Matrix3d::Identity() / body.mass;
    w.block<3, 3>(6 * column[b] + 3, 6 * column[b] + 3) = body.inertia_world().inverse();
    v0.segment<3>(6 * column[b]) = body.linear_velocity + m.gravity * m.timestep;
    v0.segment<3>(6 * column[b] + 3) = body.angular_velocity;
  }
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(m.num_rows(), 6 * n);
  Eigen::VectorXd target(m.num_rows());
  int row = 0;
  for (const Constraint& c : m.constraints) {
    const ConstraintRows r = evaluate(c, m.bodies[c.body_a], m.bodies[c.body_b]);
    for (int k = 0; k < r.rows; ++k, ++row) {
      for (int x = 0; x < 6; ++x) {
        if (column[c.body_a] >= 0) j(row, 6 * column[c.body_a] + x) = r.jacobian[12 * k + x];
        if (column[c.body_b] >= 0) j(row, 6 * column[c.body_b] + x) = r.jacobian[12 * k + 6 + x];
      }
      target(row) = -o.baumgarte * r.c[k] / m.timestep;
    }
  }
  Eigen::MatrixXd h = j * w * j.transpose();
  h.diagonal() *= 1 + o.compliance;
  const Eigen::VectorXd lambda = h.ldlt().solve(target - j * v0);
  const Eigen::VectorXd v1 = v0 + w * j.transpose() * lambda;
  std::vector<Eigen::Vector3d> out;
  for (int c = 0; c < n; ++c) {
    out.push_back(v1.segment<3>(6 * c));
    out.push_back(v1.segment<3>(6 * c + 3));
  }
  return out;
}

TEST(Step, DirectAndLdlPgsAgreeWithADenseSolveOfTheSameStep) {
  for (const Mechanism& start : {four_bar(), free_mechanism(), hanging_chain(6, 50)}) {
    // take the mechanism away from its initial pose, so c != 0 and the Baumgarte term counts
    Simulation warmup(start, velocity_only(SolverKind::pgs, 3));
    for (int s = 0; s < 5; ++s) warmup.step();
    const Mechanism& m = warmup.mechanism();
    for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs}) {
      const StepOptions o = velocity_only(kind);
      const std::vector<Eigen::Vector3d> expected = dense_step_velocities(m, o);
      Simulation sim(m, o);
      ASSERT_TRUE(sim.step().result.ok());
      double diff = 0, scale = 0;
      int k = 0;
      for (size_t i = 0; i < m.bodies.size(); ++i) {
        const RigidBody& b = sim.mechanism().bodies[i];
        if (b.is_static) continue;
        // the step carried w through the rotation keeping I w: undo that to compare with V1
        const Eigen::Vector3d w1 = m.bodies[i].inverse_inertia_world() * (b.inertia_world() * b.angular_velocity);
        diff = std::max({diff, (b.linear_velocity - expected[k]).norm(), (w1 - expected[k + 1]).norm()});
        scale = std::max({scale, expected[k].norm(), expected[k + 1].norm()});
        k += 2;
      }
      std::printf("%s, %s: largest velocity difference to the dense step %.2e (of %.2e)\n", start.name.c_str(),
                  to_string(kind), diff, scale);
      EXPECT_LT(diff, 1e-9 * std::max(1.0, scale)) << to_string(kind);
    }
  }
}

TEST(Step, RopesAndLimitsAreNeverViolated) {
  // (a) three bodies on ropes from the ground, released sideways: the ropes go taut and swing
  Mechanism ropes;
  ropes.name = "ropes";
  ropes.add_body(static_body("ground"));
  for (int i = 0; i < 3; ++i) {
    ropes.add_body(box(numbered("b", i), 1 + i, Eigen::Vector3d(0.6 * (i + 1), 0.2, 0)));
    ropes.add_constraint(ropes.distance(ConstraintType::rope, i, i + 1, ropes.bodies[i].position, ropes.bodies[i + 1].position, 0.7));
  }
  // (b) a door on a hinge about y, pushed towards its limit of +-0.5 rad, no gravity
  Mechanism door;
  door.name = "door";
  door.gravity.setZero();
  door.add_body(static_body("ground"));
  door.add_body(box("door", 5, Eigen::Vector3d(0.5, 0, 0), 1.0));
  door.bodies[1].angular_velocity = Eigen::Vector3d(0, 4, 0);
  door.bodies[1].linear_velocity = Eigen::Vector3d(0, 0, -2);
  const Eigen::Vector3d y(0, 1, 0);
  door.add_constraint(door.axial(ConstraintType::hinge, 0, 1, Eigen::Vector3d::Zero(), y));
  door.add_constraint(door.angular_limit(0, 1, y, -0.5, 0.5));
  // (c) a slider on a vertical prismatic joint falling onto its lower limit at -0.2 m
  Mechanism slider;
  slider.name = "slider";
  slider.add_body(static_body("ground"));
  slider.add_body(box("slider", 2, Eigen::Vector3d(0, 0, 0)));
  slider.add_constraint(slider.axial(ConstraintType::prismatic, 0, 1, Eigen::Vector3d::Zero(), y));
  slider.add_constraint(slider.positional_limit(0, 1, Eigen::Vector3d::Zero(), y, -0.2, 0.2));
  // A joint that turns drifts apart by O(dt^2 v^2 / r) per step whatever the solver (the
  // position follows the velocity only to first order), and Baumgarte removes a fraction beta
  // of it per step: at dt = 2 ms and these speeds that is below 1 mm (at 10 ms the ropes reach
  // 1.7 cm, the integrator's and not the solver's doing).
  for (Mechanism m : {ropes, door, slider}) {
    m.timestep = 0.002;
    Simulation sim(m, options(SolverKind::ldl_pgs));
    double violation = 0, closest = kUnbounded;  // closest: the limit was reached (not a vacuous pass)
    for (int s = 0; s < 1000; ++s) {
      const StepReport r = sim.step();
      ASSERT_TRUE(r.result.ok());
      for (const Constraint& c : sim.mechanism().constraints) {
        if (is_equality(c.type)) continue;
        const ConstraintRows rows = evaluate(c, sim.mechanism().bodies[c.body_a], sim.mechanism().bodies[c.body_b]);
        violation = std::max(violation, -rows.c[0]);
        closest = std::min(closest, rows.c[0]);
      }
    }
    // and the limit was reached: the test would pass vacuously otherwise
    std::printf("%s: largest violation %.2e, closest approach to a limit %.2e\n", m.name.c_str(), violation, closest);
    EXPECT_LT(violation, 1e-3) << m.name;
    EXPECT_LT(closest, 1e-3) << m.name;
  }
}

TEST(Step, HeavyLoadHoldsUnderLdlPgsWherePgsStretches) {
  // (a) hanging at rest, 10 ms steps; (b) released at 0.3 rad, 1 ms steps. A swinging 1:1000
  // chain at 10 ms blows apart under every solver, direct included: the light links under the
  // load's tension have transverse modes of sqrt(T / (m l)) ~ 140 rad/s and more, beyond what
  // an explicit treatment of the joints' changing directions follows (the geometric stiffness
  // of Andrews, Teichmann and Kry, 2017); papers/physics.md measures it.
  struct Case {
    const char* name;
    double angle, timestep;
    int steps;
  };
  for (const Case& c : {Case{"at rest, dt 10 ms", 0.0, 0.01, 200}, Case{"swinging, dt 1 ms", 0.3, 0.001, 2000}}) {
    Mechanism start = hanging_chain(10, 1000, c.angle);
    start.timestep = c.timestep;
    auto run = [&](SolverKind kind, int iterations, double* us_per_step) {
      Simulation sim(start, velocity_only(kind, iterations));
      std::vector<double> us;
      double error = 0;
      for (int s = 0; s < c.steps; ++s) {
        const StepReport r = sim.step();
        EXPECT_TRUE(r.result.ok());
        us.push_back(r.solve_us);
        error = std::max(error, r.error.position_max);
      }
      std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
      if (us_per_step) *us_per_step = us[us.size() / 2];
      return error;
    };
    double ldl_us = 0, pgs_us = 0;
    const double ldl_error = run(SolverKind::ldl_pgs, 10, &ldl_us);
    run(SolverKind::pgs, 10, &pgs_us);
    // The same budget, counted in flops so that the test does not depend on the machine: the
    // factorization and the solve of ldl-pgs buy extra PGS sweeps of ~50 flops per row (the
    // talk), and the budget is twice that, to be generous to pgs. (The time per step, printed,
    // gives pgs about as many sweeps.)
    const Simulation probe(start, options(SolverKind::ldl_pgs, 10));
    const Symbolic& symbolic = *probe.solver().symbolic();
    const double ldl_flops = symbolic.flops() + 4.0 * static_cast<double>(symbolic.nnz_l()) + symbolic.num_rows();
    const int budget = 2 * (10 + static_cast<int>(std::ceil(ldl_flops / (50.0 * start.num_rows()))));
    const double pgs_error = run(SolverKind::pgs, budget, nullptr);
    std::printf("1:1000 load on 10 links, %s: ldl-pgs (10 iterations, %.1f us/step) max joint error %.2e m; "
                "pgs (%d iterations, twice the flops; %.0f would take the same time) %.2e m\n", c.name, ldl_us,
                ldl_error, budget, 10 * ldl_us / pgs_us, pgs_error);
    EXPECT_LT(ldl_error, 1e-5) << c.name;
    EXPECT_GT(pgs_error, 1e-3) << c.name;
    EXPECT_GT(pgs_error, 1e3 * ldl_error) << c.name;
  }
}


// --- post-stabilization -----------------------------------------------------------------------

Mechanism scene(const char* name) {
  Mechanism m;
  EXPECT_TRUE(builtin_scene(name, &m)) << name;
  return m;
}

// The largest equality-row error (m) and limit violation (m or rad) after each of `steps` steps.
struct RunResult {
  double position = 0, angular = 0, energy_initial = 0, energy_final = 0;
  int skipped = 0;
};
RunResult run(const Mechanism& m, const StepOptions& o, int steps) {
  Simulation sim(m, o);
  RunResult r;
  r.energy_initial = total_energy(m);
  for (int s = 0; s < steps; ++s) {
    const StepReport report = sim.step();
    EXPECT_TRUE(report.result.ok()) << m.name << " step " << s;
    const ConstraintError e = constraint_error(sim.mechanism());
    r.position = std::max(r.position, e.position_max);
    r.angular = std::max(r.angular, e.angular_max);
    if (!std::isfinite(e.position_max)) r.position = kUnbounded;
  }
  r.energy_final = total_energy(sim.mechanism());
  r.skipped = sim.post_stabilize_skipped();
  return r;
}

// Semi-implicit Euler drifts along the constraint manifold's curvature by (1/2) dt^2 |w x (w x r)|
// per step and Baumgarte only feeds a fraction of it back: the four-bar separates by millimetres
// and the talk's tracked vehicle stretches its tracks by a centimetre, whatever the solver.
// Projecting the positions after each step on the step's own factor holds both below 1 um at the
// scene's own timestep.
TEST(PostStabilize, HoldsTheFourBarAndTheTrackedVehicleBelowAMicrometre) {
  for (const auto& [name, steps] : {std::pair{"four-bar", 10000}, std::pair{"tracked-vehicle", 2000}}) {
    const Mechanism m = scene(name);
    const RunResult off = run(m, velocity_only(SolverKind::ldl_pgs), steps);
    const RunResult on = run(m, options(SolverKind::ldl_pgs), steps);
    std::printf("%s, %d steps of %g s: separation %.2e m (Baumgarte only) -> %.2e m post-stabilized; energy %.6g -> "
                "%.6g J (Baumgarte only: %.6g J)\n", name, steps, m.timestep, off.position, on.position,
                on.energy_initial, on.energy_final, off.energy_final);
    EXPECT_GT(off.position, 1e-3) << name;  // the floor being removed is there
    EXPECT_LT(on.position, 1e-6) << name;
    EXPECT_LT(on.angular, 1e-6) << name;
    EXPECT_EQ(on.skipped, 0) << name;
    EXPECT_LE(on.energy_final, on.energy_initial) << name;  // no blow-up: the projection adds no energy here
  }
}

// The ground (body 0) and one body (body 1), gravity off: the tests' single-body scenes.
Mechanism ground_and(const char* name, const RigidBody& body) {
  Mechanism m;
  m.name = name;
  m.gravity.setZero();
  m.add_body(static_body("ground"));
  m.add_body(body);
  return m;
}

// The angular part of W J^T dmu is a world-frame rotation vector: q <- exp(dtheta) q. A body
// welded to the ground in a general orientation, then turned off its weld about a world axis:
// one correction removes the error to second order. Applied in the body frame (q exp(dtheta)),
// the same vector would turn it about another axis and leave an error of the order of the
// original (the two agree only where body and world axes coincide, as on planar scenes).
TEST(PostStabilize, RotatesAboutTheWorldFrameAxis) {
  RigidBody b = box("b", 2, Eigen::Vector3d(0.3, 0.2, 0.1));
  b.inertia = Eigen::Vector3d(0.02, 0.05, 0.09);
  b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()));
  Mechanism m = ground_and("welded", b);
  m.add_constraint(m.axial(ConstraintType::weld, 0, 1, Eigen::Vector3d(0.3, 0.2, 0.1),
                              Eigen::Vector3d(0, 0, 1)));
  StepOptions o = options(SolverKind::direct);
  o.post_stabilize = 1;
  o.baumgarte = 0;  // the velocity step leaves the pose where it is: the correction alone acts
  Simulation sim(m, o);
  const Eigen::Quaterniond turned =
      Eigen::Quaterniond(Eigen::AngleAxisd(1e-3, Eigen::Vector3d(0, 1, 1).normalized())) * b.orientation;
  sim.set_orientation(1, turned);
  const double before = constraint_error(sim.mechanism()).angular_max;
  sim.step();
  const double after = constraint_error(sim.mechanism()).angular_max;
  std::printf("weld turned by 1e-3 rad: angular error %.2e -> %.2e rad after one correction\n", before, after);
  EXPECT_GT(before, 5e-4);
  EXPECT_LT(after, 1e-6);  // second order: (1e-3)^2 / 4 (the body-frame order leaves ~1e-3)
}

// A 3D chain of 30 bodies joined by balls, hinges on tilted axes and cylindrical joints (with
// +-2 cm limits along their axes if `limits`), released from horizontal: the bodies turn about
// every axis, where a wrong rotation order would blow up.
Mechanism mixed_3d_chain(bool limits) {
  Mechanism m;
  m.name = "mixed-3d-chain";
  m.timestep = 0.01;
  m.add_body(static_body("ground"));
  const double l = 0.2;
  for (int i = 0; i < 30; ++i) {
    RigidBody link = box(numbered("link", i), 1 + 0.1 * (i % 4), Eigen::Vector3d(l * (i + 0.5), 0, 0), l);
    link.inertia = Eigen::Vector3d(0.002, 0.004, 0.005) * link.mass;
    m.add_body(link);
    const Eigen::Vector3d joint(l * i, 0, 0);
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3 * (i % 3), 1, 0.7 * ((i + 1) % 2)).normalized();
    switch (i % 3) {
      case 0: m.add_constraint(m.ball(i, i + 1, joint)); break;
      case 1: m.add_constraint(m.axial(ConstraintType::hinge, i, i + 1, joint, axis)); break;
      default:
        m.add_constraint(m.axial(ConstraintType::cylindrical, i, i + 1, joint, axis));
        if (limits)
          m.add_constraint(m.positional_limit(i, i + 1, joint, axis, -0.02, 0.02));
    }
  }
  return m;
}

TEST(PostStabilize, HoldsAThreeDimensionalChainOfMixedJoints) {
  const Mechanism m = mixed_3d_chain(false);
  const RunResult off = run(m, velocity_only(SolverKind::ldl_pgs), 300);
  const RunResult on = run(m, options(SolverKind::ldl_pgs), 300);
  std::printf("30-body 3D chain, 3 s at 10 ms: separation %.2e m / %.2e rad (Baumgarte only) -> %.2e m / %.2e rad\n",
              off.position, off.angular, on.position, on.angular);
  EXPECT_GT(off.position, 5e-3);
  EXPECT_LT(on.position, 1e-6);
  EXPECT_LT(on.angular, 1e-6);
}

// With tight limits on the cylindrical joints the velocity step itself leaves the limits far
// from converged (4 cm, 0.15 rad with Baumgarte alone), and the position-level hybrid does not
// converge either: without the guard that undoes a correction that raised the error, the
// projection blew this chain up (1e5 m). With it, no blow-up and no worse than Baumgarte alone.
// (Not solved: the limits stay centimetres off; papers/physics.md.)
TEST(PostStabilize, NeverMakesAnUnconvergedLimitChainWorse) {
  const Mechanism m = mixed_3d_chain(true);
  const RunResult off = run(m, velocity_only(SolverKind::ldl_pgs), 300);
  const RunResult on = run(m, options(SolverKind::ldl_pgs), 300);
  std::printf("30-body 3D chain with limits: separation %.2e m / %.2e rad (Baumgarte only) -> %.2e m / %.2e rad; "
              "energy %.3g -> %.3g J (Baumgarte only %.3g J)\n", off.position, off.angular, on.position, on.angular,
              on.energy_initial, on.energy_final, off.energy_final);
  EXPECT_LT(on.position, 1.5 * off.position);
  EXPECT_LT(on.angular, 1.5 * off.angular);
  EXPECT_LT(on.energy_final, on.energy_initial + 10);  // (a blow-up gained 1e7 J)
}

// The correction must use the factor's own J_0 and W_0: dq = W_0 J_0^T (J_0 W_0 J_0^T)^-1 (-c)
// is a projection (J_0 dq = -c). With the same factor but the Jacobian at the new pose, J_1 W_1
// J_1^T is not what was factored, and the "projection" is not one. Both are written here with
// the solver's own pieces (the factor of S_0; dq from S_0's or S_1's W J^T) on the tracked vehicle,
// one iteration per step, Baumgarte left on.
TEST(PostStabilize, TheFactorsOwnJacobianCorrectsWhereTheNewOneDoesNot) {
  const Mechanism start = scene("tracked-vehicle");
  StepOptions o = velocity_only(SolverKind::direct);
  const auto separation = [&](bool own_jacobian) {
    Simulation sim(start, o);
    Solver projector(build_system(start, o), o.solver);
    std::vector<double> mu(start.num_rows()), dq(6 * static_cast<size_t>(start.num_dynamic_bodies()));
    double worst = 0;
    for (int s = 0; s < 300; ++s) {
      System s0 = build_system(sim.mechanism(), o);  // J_0, W_0 of this step
      sim.step();
      const Mechanism& m = sim.mechanism();
      System s1 = build_system(m, o);                // J_1, W_1 at the integrated pose
      for (size_t k = 0; k < m.constraints.size(); ++k) {
        const Constraint& c = m.constraints[k];
        const ConstraintRows rows = evaluate(c, m.bodies[c.body_a], m.bodies[c.body_b]);
        for (int r = 0; r < rows.rows; ++r) s0.rhs[s0.blocks[k].position + r] = s1.rhs[s1.blocks[k].position + r] = -rows.c[r];
      }
      if (!projector.solve(s0, mu, dq).ok()) return kUnbounded;  // factors H_0
      if (!own_jacobian) {                                       // H_0's factor, J_1 and W_1
        std::fill(dq.begin(), dq.end(), 0.0);
        add_velocity_change(s1, mu, dq);
      }
      int col = 0;
      for (int b = 0; b < static_cast<int>(m.bodies.size()); ++b) {
        if (m.bodies[b].is_static) continue;
        const double* d = dq.data() + 6 * col++;
        const RigidBody& body = m.bodies[b];
        const Eigen::Vector3d dtheta(d[3], d[4], d[5]);
        Eigen::Quaterniond q = body.orientation;
        if (dtheta.norm() > 0) q = (Eigen::Quaterniond(Eigen::AngleAxisd(dtheta.norm(), dtheta.normalized())) * q).normalized();
        if (!std::isfinite(d[0]) || !q.coeffs().allFinite()) return kUnbounded;
        sim.set_position(b, body.position + Eigen::Vector3d(d[0], d[1], d[2]));
        sim.set_orientation(b, q);
      }
      worst = std::max(worst, constraint_error(sim.mechanism()).position_max);
    }
    return worst;
  };
  const double own = separation(true), other = separation(false);
  std::printf("tracked vehicle, 300 steps, one correction each: own J_0 %.2e m, new J_1 with H_0's factor %.2e m\n",
              own, other);
  EXPECT_LT(own, 1e-3);
  EXPECT_GT(other, 10 * own);
}

// Projecting positions removes Baumgarte's standing error and with it the energy Baumgarte fed
// back: the four-bar keeps a quarter of its energy over 100 s. The curvature target (the chord
// of each step tangent to the manifold at its midpoint) is the energy-consistent variant: most
// of the energy stays, the joints still hold. A spinning body on a rod in free space, whose
// exact motion keeps its energy, keeps it ten times better with it (no projection at all), and
// stays a thousand times closer to its rod (measured: 2.2e-4 against 4.2e-3 relative, separation 2e-6 m against 2.2e-3 m).
TEST(PostStabilize, TheCurvatureTargetKeepsTheEnergyThatProjectionLoses) {
  const Mechanism four_bar_scene = scene("four-bar");
  StepOptions curved = options(SolverKind::direct);
  curved.curvature_target = true;
  const RunResult plain = run(four_bar_scene, options(SolverKind::direct), 10000);
  const RunResult kept = run(four_bar_scene, curved, 10000);
  std::printf("four-bar, 10000 steps: energy %.4g -> %.4g J post-stabilized, %.4g J with the curvature target "
              "(separation %.2e m)\n", plain.energy_initial, plain.energy_final, kept.energy_final, kept.position);
  EXPECT_LT(plain.energy_final, 0.5 * plain.energy_initial);
  EXPECT_GT(kept.energy_final, 0.8 * kept.energy_initial);
  EXPECT_LT(kept.energy_final, 1.05 * kept.energy_initial);
  EXPECT_LT(kept.position, 1e-6);

  RigidBody bob = box("bob", 1, Eigen::Vector3d(1, 0, 0));
  bob.linear_velocity = Eigen::Vector3d(0, 3, 0);  // 3 rad/s about the anchor: 0.3 rad per step
  Mechanism spin = ground_and("spinning rod", bob);
  spin.add_constraint(spin.distance(ConstraintType::rod, 0, 1, Eigen::Vector3d::Zero(),
                                    bob.position));
  StepOptions no_post = velocity_only(SolverKind::direct);
  no_post.curvature_target = true;
  const RunResult without = run(spin, velocity_only(SolverKind::direct), 1000);
  const RunResult with = run(spin, no_post, 1000);
  std::printf("spinning rod, 1000 steps, no projection: energy %.6g -> %.6g J (Baumgarte), %.6g J (curvature "
              "target); separation %.2e m, %.2e m\n", with.energy_initial, without.energy_final, with.energy_final,
              without.position, with.position);
  EXPECT_LT(std::abs(with.energy_final - with.energy_initial), 0.1 * std::abs(without.energy_final - without.energy_initial));
  EXPECT_LT(with.position, 1e-3 * without.position);
}

// 1e4 steps of the ragdoll with its joint limits, post-stabilized by the step's own hybrid at
// position level (dmu >= 0 on the limits): joints and limits hold, nothing blows up.
TEST(PostStabilize, RagdollKeepsItsJointsAndLimitsFor10000Steps) {
  const Mechanism m = scene("ragdoll");
  ASSERT_GE(m.first_inequality(), 0);
  const RunResult on = run(m, options(SolverKind::ldl_pgs), 10000);
  std::printf("ragdoll, 10000 steps: separation %.2e m, angular error %.2e rad (limits included), energy %.6g -> %.6g J\n",
              on.position, on.angular, on.energy_initial, on.energy_final);
  EXPECT_LT(on.position, 1e-6);
  EXPECT_LT(on.angular, 1e-6);
  EXPECT_LE(on.energy_final, on.energy_initial + 1e-6 * std::abs(on.energy_initial));
}

// Without inequality rows ldl-pgs is one exact solve, as direct: the same trajectory to round-off.
TEST(PostStabilize, LdlPgsIsDirectOnEqualityOnlyScenes) {
  for (const char* name : {"chain-10", "four-bar", "tracked-vehicle", "heavy-chain-10-1000"}) {
    const Mechanism m = scene(name);
    ASSERT_LT(m.first_inequality(), 0);
    for (const StepOptions& base : {velocity_only(SolverKind::direct), options(SolverKind::direct)}) {
      StepOptions hybrid = base;
      hybrid.solver.kind = SolverKind::ldl_pgs;
      Simulation a(m, base), b(m, hybrid);
      for (int s = 0; s < 100; ++s) {
        a.step();
        b.step();
      }
      double diff = 0;
      for (size_t i = 0; i < m.bodies.size(); ++i)
        diff = std::max({diff, (a.mechanism().bodies[i].position - b.mechanism().bodies[i].position).norm(),
                         (a.mechanism().bodies[i].linear_velocity - b.mechanism().bodies[i].linear_velocity).norm()});
      EXPECT_LT(diff, 1e-12) << name << " post-stabilize " << base.post_stabilize;
    }
  }
}

// A walker's root and hip as joint sets (joint_set.h): a torso on the ground by slide x, slide y
// and a hinge about z (planar), and a thigh on it by two hinges whose axes do not meet, their
// ranges as coordinate limits; it falls, swinging.
Mechanism joint_set_walker() {
  Mechanism m;
  m.name = "joint-set-walker";
  m.gravity = Eigen::Vector3d(0, -9.81, 0);
  m.add_body(static_body("ground"));
  m.add_body(box("torso", 2, Eigen::Vector3d(0, 1, 0)));
  m.add_body(box("thigh", 1, Eigen::Vector3d(0.1, 0.6, 0)));
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d hip(0, 0.8, 0);
  m.add_constraint(m.joint_set(0, 1, {{ChainJointType::slide, x, hip}, {ChainJointType::slide, y, hip},
                                      {ChainJointType::hinge, z, hip}}));
  const Constraint thigh = m.joint_set(1, 2, {{ChainJointType::hinge, z, hip}, {ChainJointType::hinge, x, hip + 0.05 * z}});
  m.add_constraint(thigh);
  m.add_constraint(make_coordinate_limit(thigh, 0, -0.3, 0.3));
  m.add_constraint(make_coordinate_limit(thigh, 1, -0.2, 0.2));
  m.bodies[2].angular_velocity = Eigen::Vector3d(1, 0, 2);
  return m;
}

// After the first step, step() allocates nothing: the System, the solver's caches, the factor
// and the post-stabilization's work arrays are all sized once.
TEST(Step, AllocatesNothingAfterTheFirstStep) {
  struct Case {
    const char* scene;
    SolverKind kind;
    bool refactor;
  };
  for (const Case& c : {Case{"tracked-vehicle", SolverKind::direct, false}, Case{"tracked-vehicle", SolverKind::ldl_pgs, true},
                        Case{"ragdoll", SolverKind::ldl_pgs, false}, Case{"ragdoll", SolverKind::pgs, false},
                        Case{"four-bar", SolverKind::block_gs, false}}) {
    StepOptions o = options(c.kind);
    o.post_stabilize = 2;  // every solver, pgs and block-gs with a projector of their own
    o.post_stabilize_tolerance = 0;
    o.post_stabilize_refactor = c.refactor;
    Simulation sim(scene(c.scene), o);
    sim.step();
    sim.apply_force(1, Eigen::Vector3d(1, 2, 3));
    allocations = 0;
    counting = true;
    for (int s = 0; s < 5; ++s) sim.step();
    counting = false;
    EXPECT_EQ(allocations, 0) << c.scene << " " << to_string(c.kind);
  }
  Simulation sim(joint_set_walker(), options(SolverKind::ldl_pgs));
  sim.step();
  allocations = 0;
  counting = true;
  for (int s = 0; s < 20; ++s) sim.step();
  counting = false;
  EXPECT_EQ(allocations, 0) << "joint sets";
  EXPECT_LT(constraint_error(sim.mechanism()).position_max, 1e-6);
}

// --- the state and force API ------------------------------------------------------------------

TEST(SimulationState, ArraysReadWhatTheSettersWrite) {
  Simulation sim(hanging_chain(3), options(SolverKind::direct));
  const int n = static_cast<int>(sim.mechanism().bodies.size());
  std::vector<double> x(3 * n), q(4 * n), v(6 * n);
  sim.get_positions(x);
  sim.get_orientations(q);
  sim.get_velocities(v);
  x[3 * 2 + 1] += 0.01;
  v[6 * 2 + 4] = 0.5;  // body 2's angular velocity about y
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond q2 = turn * sim.mechanism().bodies[2].orientation;
  q[8] = q2.w(), q[9] = q2.x(), q[10] = q2.y(), q[11] = q2.z();
  sim.set_positions(x);
  sim.set_orientations(q);
  sim.set_velocities(v);
  const RigidBody& b = sim.mechanism().bodies[2];
  EXPECT_EQ(b.position[1], x[7]);
  EXPECT_EQ(b.angular_velocity[1], 0.5);
  EXPECT_LT(b.orientation.angularDistance(q2), 1e-15);
  std::vector<double> again(3 * n);
  sim.get_positions(again);
  EXPECT_EQ(again, x);
}

// Each kind of bad write is refused with a message, and changes nothing.
TEST(SimulationState, RefusesNonFiniteValues) {
  Simulation sim(hanging_chain(2), options(SolverKind::direct));
  const Eigen::Vector3d before = sim.mechanism().bodies[1].position;
  EXPECT_THROW(sim.set_position(1, Eigen::Vector3d(0, std::nan(""), 0)), InputError);
  EXPECT_THROW(sim.set_linear_velocity(1, Eigen::Vector3d(kUnbounded, 0, 0)), InputError);
  EXPECT_THROW(sim.apply_force(1, Eigen::Vector3d(0, 0, std::nan(""))), InputError);
  std::vector<double> x(9, 0.0);
  x[4] = std::nan("");
  EXPECT_THROW(sim.set_positions(x), InputError);
  EXPECT_EQ(sim.mechanism().bodies[1].position, before);
  EXPECT_THROW(sim.set_gravity(Eigen::Vector3d(0, kUnbounded, 0)), InputError);
  EXPECT_THROW(sim.set_timestep(-0.01), InputError);
  EXPECT_THROW(sim.set_timestep(0), InputError);
}

// The same for the API: a caller may set only what a scene file may hold
// (MechanismRanges), since what is computed from more overflows: a position of 1e300 squared in
// the inertia shift, a timestep of 1e-300 divided into the velocity terms. Before, only
// non-finite values were refused.
TEST(SimulationState, RefusesValuesBeyondTheMechanismRanges) {
  using R = MechanismRanges;
  Simulation sim(hanging_chain(2), options(SolverKind::direct));
  const Eigen::Vector3d before = sim.mechanism().bodies[1].position;
  EXPECT_THROW(sim.set_position(1, Eigen::Vector3d(0, 10 * R::coordinate_max, 0)), InputError);
  EXPECT_THROW(sim.set_linear_velocity(1, Eigen::Vector3d(-10 * R::velocity_max, 0, 0)), InputError);
  EXPECT_THROW(sim.set_angular_velocity(1, Eigen::Vector3d(0, 0, 10 * R::velocity_max)), InputError);
  EXPECT_THROW(sim.apply_force(1, Eigen::Vector3d(0, 0, 1e300)), InputError);
  EXPECT_THROW(sim.apply_force_at(1, Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1e300, 0, 0)), InputError);
  std::vector<double> x(9, 0.0);
  x[4] = 1e300;
  EXPECT_THROW(sim.set_positions(x), InputError);
  std::vector<double> v(18, 0.0);
  v[9] = 1e300;
  EXPECT_THROW(sim.set_velocities(v), InputError);
  EXPECT_EQ(sim.mechanism().bodies[1].position, before);
  EXPECT_THROW(sim.set_gravity(Eigen::Vector3d(0, -1e300, 0)), InputError);
  EXPECT_THROW(sim.set_timestep(1e-300), InputError);
  EXPECT_THROW(sim.set_timestep(1e300), InputError);
  // The bounds themselves are accepted.
  EXPECT_NO_THROW(sim.set_position(1, Eigen::Vector3d(0, R::coordinate_max, 0)));
  EXPECT_NO_THROW(sim.set_timestep(R::timestep_min));
  EXPECT_NO_THROW(sim.set_timestep(R::timestep_max));
  try {
    sim.set_timestep(1e300);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1e+300"), std::string::npos) << e.what();
  }
}

TEST(SimulationState, RefusesANonUnitQuaternion) {
  Simulation sim(hanging_chain(2), options(SolverKind::direct));
  EXPECT_THROW(sim.set_orientation(1, Eigen::Quaterniond(1.01, 0, 0, 0)), InputError);
  try {
    sim.set_orientation(1, Eigen::Quaterniond(2, 0, 0, 0));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 1"), std::string::npos) << e.what();
  }
  sim.set_orientation(1, Eigen::Quaterniond(1 + 1e-9, 0, 0, 0));  // within 1e-6: normalized
  EXPECT_DOUBLE_EQ(sim.mechanism().bodies[1].orientation.norm(), 1.0);
}

TEST(SimulationState, RefusesForcesAndVelocitiesOnStaticBodies) {
  Simulation sim(hanging_chain(2), options(SolverKind::direct));
  EXPECT_THROW(sim.apply_force(0, Eigen::Vector3d(1, 0, 0)), InputError);
  EXPECT_THROW(sim.set_angular_velocity(0, Eigen::Vector3d(1, 0, 0)), InputError);
  std::vector<double> v(18, 0.0);
  v[0] = 1;  // the ground's
  EXPECT_THROW(sim.set_velocities(v), InputError);
}

TEST(SimulationState, RefusesABodyOutOfRangeAndArraysOfTheWrongSize) {
  Simulation sim(hanging_chain(2), options(SolverKind::direct));
  EXPECT_THROW(sim.set_position(3, Eigen::Vector3d::Zero()), InputError);
  EXPECT_THROW(sim.apply_force(-1, Eigen::Vector3d::Zero()), InputError);
  std::vector<double> short_array(8);
  EXPECT_THROW(sim.get_positions(short_array), InputError);
  EXPECT_THROW(sim.set_velocities(short_array), InputError);
}

// A free body: a force applied for one step changes its velocity by F dt / m and no more (the
// load is cleared by the step); at a point off the centre it adds the torque (p - x) x F, the
// angular velocity changing by I^-1 ((p - x) x F) dt.
TEST(SimulationState, AppliedForcesActForOneStep) {
  RigidBody b = box("b", 2, Eigen::Vector3d(1, 0, 0));
  b.inertia = Eigen::Vector3d(0.1, 0.2, 0.3);
  const Mechanism m = ground_and("free", b);
  Simulation sim(m, options(SolverKind::pgs));
  const double dt = m.timestep;
  const Eigen::Vector3d f(4, 0, 0), point(1, 0.5, 0);
  sim.apply_force_at(1, f, point);
  sim.step();
  const RigidBody& after = sim.mechanism().bodies[1];
  EXPECT_LT((after.linear_velocity - f * dt / b.mass).norm(), 1e-15);
  // w = I^-1 ((p - x) x F) dt = (0, 0, -0.5 * 4 / 0.3) dt (identity orientation at the step's start;
  // the rotation by w dt keeps I w, which about a principal axis is w itself)
  EXPECT_NEAR(after.angular_velocity.z(), -0.5 * 4 / 0.3 * dt, 1e-12);
  const Eigen::Vector3d v1 = after.linear_velocity, w1 = after.angular_velocity;
  sim.step();
  EXPECT_EQ(sim.mechanism().bodies[1].linear_velocity, v1);
  EXPECT_LT((sim.mechanism().bodies[1].angular_velocity - w1).norm(), 1e-15);
  sim.set_gravity(Eigen::Vector3d(0, -1, 0));
  sim.step();
  EXPECT_NEAR(sim.mechanism().bodies[1].linear_velocity.y(), -dt, 1e-15);
}

// ---- runs that come apart ----

// The first step at which run_failure refuses a run of `steps` steps ("" if none), with the
// mechanism's size at the start.
std::string first_failure(const Mechanism& m, SolverKind kind, int steps, double* error_max = nullptr) {
  StepOptions options;
  options.solver.kind = kind;
  options.diagnostics = true;
  const double size = mechanism_size(m);
  Simulation sim(m, options);
  double worst = 0;
  for (int s = 1; s <= steps; ++s) {
    const StepReport r = sim.step();
    worst = std::max(worst, r.error.position_max);
    if (std::string why = run_failure(r, size); !why.empty()) return "step " + std::to_string(s) + ": " + why;
  }
  if (error_max) *error_max = worst;
  return "";
}

// Class 10: at a mass ratio of 1e12 every solver, direct included, ended the 5 m heavy chain
// 48.9 m off its constraints in 1000 steps (measured: `ldlpgs step heavy-chain-10-1e12
// --steps 1000 --solver S`), and nothing said so. run_failure says so at every solver; within
// the supported range (README, "Supported range": 1e6 here) the factoring solvers hold the
// chain to 1e-9 m and are never refused.
TEST(LdlpgsRobust, MassRatioBeyondTheSupportedRangeIsDetected) {
  Mechanism heavy, supported;
  ASSERT_TRUE(builtin_scene("heavy-chain-10-1e12", &heavy));
  ASSERT_TRUE(builtin_scene("heavy-chain-10-1e6", &supported));
  EXPECT_NEAR(mechanism_size(heavy), 4.75, 0.01);  // the chain (5 m) from its top anchor to the load's centre
  for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs, SolverKind::pgs, SolverKind::block_gs}) {
    SCOPED_TRACE(to_string(kind));
    const std::string why = first_failure(heavy, kind, 1000);
    EXPECT_NE(why.find("it came apart"), std::string::npos) << why;
  }
  for (SolverKind kind : {SolverKind::direct, SolverKind::ldl_pgs}) {
    double error = 0;
    EXPECT_EQ(first_failure(supported, kind, 1000, &error), "") << to_string(kind);
    EXPECT_LT(error, 1e-9) << to_string(kind);
  }
  StepReport nan;
  nan.energy = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(run_failure(nan, 1), "non-finite state");
}

// The long run: 1e4 steps of every built-in scene with every solver (direct only where it
// applies: no limits or ropes) end finite or refused by run_failure with its reason, and the
// factoring solvers are never refused. About 10 s in Release; under AddressSanitizer (CI's
// sanitizer build) 2000 steps, to stay within a few minutes.
#ifdef __SANITIZE_ADDRESS__
constexpr int kLongRunSteps = 2000;
#else
constexpr int kLongRunSteps = 10000;
#endif
TEST(LdlpgsRobust, LongRunOfEveryBuiltInSceneIsFiniteOrNamesItsFailure) {
  for (const std::string& name : builtin_scene_names()) {
    Mechanism m;
    ASSERT_TRUE(builtin_scene(name, &m));
    if (has_shapes(m)) continue;  // the contact scenes' long runs: contact_test.cpp
    for (SolverKind kind : {SolverKind::pgs, SolverKind::block_gs, SolverKind::ldl_pgs, SolverKind::direct}) {
      if (kind == SolverKind::direct && m.first_inequality() >= 0) continue;
      SCOPED_TRACE(name + " " + to_string(kind));
      StepOptions options;
      options.solver.kind = kind;
      options.diagnostics = true;
      const double size = mechanism_size(m);
      Simulation sim(m, options);
      std::string why;
      int s = 1;
      for (; s <= kLongRunSteps && why.empty(); ++s) why = run_failure(sim.step(), size);
      if (why.empty()) {
        for (const RigidBody& b : sim.mechanism().bodies)
          EXPECT_TRUE(b.position.allFinite() && b.linear_velocity.allFinite()) << b.name;
      }
      if (kind == SolverKind::ldl_pgs || kind == SolverKind::direct) {
        EXPECT_EQ(why, "") << "step " << s - 1;
      }
      std::printf("%-22s %-8s %s\n", name.c_str(), to_string(kind), why.empty() ? "finite" : why.c_str());
    }
  }
}

}  // namespace
}  // namespace ldlpgs

namespace ldlpgs {
namespace {

// Scale: a hub carrying n arms on ball joints, not shattered, makes H dense
// (every pair of joints shares the hub). The explicit elimination game spent O(n^3) on its
// clique (27 s for spy of 1000 arms) and the per-block kernels factored the dense front at a few
// GFlop/s. The causes, checked here without a clock: the default ordering finds the clique's
// zero-fill order, the symbolic phase makes the whole front one BLAS supernode, and the step
// stays on the joints.
TEST(LdlpgsRobust, UnshatteredStarIsOneDenseSupernodeAndSteps) {
  const int arms = 300;
  Mechanism m;
  m.name = "star";
  m.add_body(static_body("ground"));
  m.add_body(box("hub", 10, Eigen::Vector3d(0, 5, 0)));
  m.add_constraint(m.ball(0, 1, Eigen::Vector3d(0, 5, 0)));
  for (int i = 0; i < arms; ++i) {
    const double a = 2 * std::numbers::pi * i / arms;
    const Eigen::Vector3d at(2 * std::cos(a), 5 + 0.1 * (i % 3), 2 * std::sin(a));
    const int b = m.add_body(box(numbered("arm", i), 1, at));
    m.add_constraint(m.ball(1, b, 0.5 * (at + m.bodies[1].position)));
  }
  StepOptions options;
  options.solver.kind = SolverKind::direct;
  Simulation sim(m, options);
  const Symbolic* s = sim.solver().symbolic();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->num_fill_edges(), 0);
  ASSERT_EQ(s->num_supernodes(), 1);
  EXPECT_EQ(s->supernode_size(0), 3 * (arms + 1));
  EXPECT_TRUE(s->supernode_blas(0));
  const double size = mechanism_size(m);
  for (int step = 0; step < 3; ++step) EXPECT_EQ(run_failure(sim.step(), size), "") << "step " << step;
  for (const RigidBody& b : sim.mechanism().bodies) ASSERT_TRUE(b.position.allFinite()) << b.name;
}

}  // namespace
}  // namespace ldlpgs
