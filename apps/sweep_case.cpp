// One run of speed against error (apps/sweep_case.h).
#include "apps/sweep_case.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "peers/median.h"
#include "ldlpgs/physics/step.h"

namespace ldlpgs::cli {

double blow_up_energy(const Mechanism& m) {
  double mass = 0, kinetic = 0;
  Eigen::AlignedBox3d box;
  for (const RigidBody& b : m.bodies) {
    box.extend(b.position);
    if (b.is_static) continue;
    mass += b.mass;
    kinetic += b.kinetic_energy();
  }
  const double size = box.isEmpty() ? 0 : box.diagonal().norm();
  return std::max(1.0, kinetic + mass * m.gravity.norm() * std::max(1.0, size));
}

SweepPoint run_case(const Mechanism& m, const std::string& scene, const std::string& solver, int iterations,
                    double seconds) {
  SweepPoint p;
  p.scene = scene;
  p.solver = solver;
  p.iterations = solver == "direct" ? 1 : iterations;
  StepOptions options;
  const bool known = solver_kind_from_string(solver, &options.solver.kind);
  assert(known && "sweep solvers are the program's own names");
  (void)known;
  options.solver.iterations = p.iterations;
  options.diagnostics = true;
  const double energy0 = total_energy(m), limit = blow_up_energy(m);
  Simulation sim(m, options);
  const int steps = std::max(1, static_cast<int>(std::lround(seconds / m.timestep)));
  std::vector<double> us;
  double work = 0;  // by the bodies' constant loads, J
  StepReport r;
  for (int s = 0; s < steps; ++s) {
    r = sim.step();
    us.push_back(r.solve_us);
    p.error_max = std::max(p.error_max, r.error.position_max);
    p.angular_error_max = std::max(p.angular_error_max, r.error.angular_max);
    p.penetration_max = std::max(p.penetration_max, r.penetration_max_m);
    if (!std::isfinite(r.energy) || !std::isfinite(r.error.position_max) || !std::isfinite(r.error.angular_max)) {
      p.failure = "non-finite";
      break;
    }
    // the constant loads' work (a driven scene gains what its torque puts in): F . v + T . w per step
    for (const RigidBody& b : sim.mechanism().bodies)
      work += (b.applied_force.dot(b.linear_velocity) + b.applied_torque.dot(b.angular_velocity)) * m.timestep;
    if (r.energy - energy0 - work > limit) {
      p.failure = "energy";
      break;
    }
    if (!r.result.ok() && p.failure.empty()) p.failure = "singular";  // the run goes on, as Simulation's does
  }
  p.solve_us = median(us);
  p.error = r.error.position_max;
  p.angular_error = r.error.angular_max;
  return p;
}

Mechanism with_heavier_load(const Mechanism& m, double factor) {
  Mechanism out = m;
  int heaviest = -1;
  for (int b = 0; b < static_cast<int>(out.bodies.size()); ++b)
    if (!out.bodies[b].is_static && (heaviest < 0 || out.bodies[b].mass >= out.bodies[heaviest].mass)) heaviest = b;
  if (heaviest >= 0) {
    out.bodies[heaviest].mass *= factor;
    out.bodies[heaviest].inertia *= factor;
  }
  return out;
}

double mass_ratio(const Mechanism& m) {
  double lightest = std::numeric_limits<double>::infinity(), heaviest = 0;
  for (const RigidBody& b : m.bodies) {
    if (b.is_static) continue;
    lightest = std::min(lightest, b.mass);
    heaviest = std::max(heaviest, b.mass);
  }
  return heaviest > 0 ? heaviest / lightest : 0;
}

nlohmann::json to_json(const SweepPoint& p) {
  const bool blown = p.failure == "non-finite" || p.failure == "energy";  // its errors mean nothing
  return {{"scene", p.scene},
          {"solver", p.solver},
          {"iterations", p.iterations},
          {"solve_us", p.solve_us},
          {"position_error_m", blown ? nlohmann::json(nullptr) : nlohmann::json(p.error)},
          {"position_error_max_m", blown ? nlohmann::json(nullptr) : nlohmann::json(p.error_max)},
          {"angular_error_rad", blown ? nlohmann::json(nullptr) : nlohmann::json(p.angular_error)},
          {"angular_error_max_rad", blown ? nlohmann::json(nullptr) : nlohmann::json(p.angular_error_max)},
          {"penetration_max_m", blown ? nlohmann::json(nullptr) : nlohmann::json(p.penetration_max)},
          {"failed", p.failed()},
          {"failure", p.failure}};
}

}  // namespace ldlpgs::cli
