// Example 2: a mechanism built in code (a five-link pendulum chain hanging from the ground by
// ball joints), stepped for one second with the LDL-PGS solver; prints the tip's height and the
// largest constraint error every tenth of a second.
#include <cstdio>

#include <ldlpgs/physics/constraint.h>
#include <ldlpgs/physics/mechanism.h>
#include <ldlpgs/physics/step.h>

int main() {
  using Eigen::Vector3d;
  ldlpgs::Mechanism m;
  m.name = "five-link chain";
  ldlpgs::RigidBody ground;
  ground.name = "ground";
  ground.is_static = true;
  int previous = m.add_body(ground);
  const double length = 0.5, mass = 1.0;  // m, kg per link
  for (int i = 0; i < 5; ++i) {
    ldlpgs::RigidBody link;
    link.name = "link" + std::to_string(i);
    link.mass = mass;
    // A slender box of length `length` along x: I = m l^2 / 12 about y and z.
    link.inertia = Vector3d(1e-3, mass * length * length / 12, mass * length * length / 12);
    link.position = Vector3d((i + 0.5) * length, 0, 0);  // horizontal at first: it swings down
    const int current = m.add_body(link);
    // Each link hangs from the previous body at their shared end.
    m.add_constraint(m.ball(previous, current, Vector3d(i * length, 0, 0)));
    previous = current;
  }
  m.timestep = 1.0 / 100;

  ldlpgs::StepOptions options;  // ldl-pgs, compliance 1e-8, post-stabilization on
  options.diagnostics = true;   // fill StepReport::error
  ldlpgs::Simulation sim(std::move(m), options);
  const int tip = sim.mechanism().find_body("link4");
  for (int step = 1; step <= 100; ++step) {
    const ldlpgs::StepReport report = sim.step();
    if (!report.result.ok()) {
      std::fprintf(stderr, "step_chain: %s\n", report.result.factor.message().c_str());
      return 1;
    }
    if (step % 10 == 0)
      std::printf("t = %.2f s  tip y = %+.4f m  constraint error %.2e m\n", sim.time(),
                  sim.mechanism().bodies[tip].position.y(), report.error.position_max);
  }
  return 0;
}
