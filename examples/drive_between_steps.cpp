// Example 3: driving a simulation between steps through its state API: a built-in pendulum is
// pushed by a force for half a second, then its velocity is set to zero (caught), then released.
// Usage: drive_between_steps [SCENE.json | built-in name]   (default: the pendulum)
#include <cstdio>
#include <string>

#include <ldlpgs/physics/io/scene.h>
#include <ldlpgs/physics/io/scenes.h>
#include <ldlpgs/physics/step.h>
#include <ldlpgs/sparse/error.h>

int main(int argc, char** argv) {
  const std::string spec = argc > 1 ? argv[1] : "pendulum";
  try {
    ldlpgs::Mechanism mechanism;
    if (!ldlpgs::builtin_scene(spec, &mechanism)) mechanism = ldlpgs::load_scene(spec);
    ldlpgs::Simulation sim(std::move(mechanism), ldlpgs::StepOptions{});
    const int body = static_cast<int>(sim.mechanism().bodies.size()) - 1;  // the last body: the bob
    std::printf("driving body %s of %s\n", sim.mechanism().bodies[body].name.c_str(), sim.mechanism().name.c_str());
    for (int step = 1; step <= 150; ++step) {
      if (step <= 50) sim.apply_force(body, Eigen::Vector3d(5, 0, 0));  // N, this step only
      if (step == 100) {  // caught: at rest where it is
        sim.set_linear_velocity(body, Eigen::Vector3d::Zero());
        sim.set_angular_velocity(body, Eigen::Vector3d::Zero());
      }
      sim.step();
      if (step % 25 == 0) {
        const ldlpgs::RigidBody& b = sim.mechanism().bodies[body];
        std::printf("t = %.2f s  position (%+.3f, %+.3f, %+.3f) m  speed %.3f m/s\n", sim.time(), b.position.x(),
                    b.position.y(), b.position.z(), b.linear_velocity.norm());
      }
    }
    return 0;
  } catch (const ldlpgs::InputError& e) {  // a scene file that cannot be read, a refused write
    std::fprintf(stderr, "drive_between_steps: %s\n", e.what());
    return 2;
  }
}
