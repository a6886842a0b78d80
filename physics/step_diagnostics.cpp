// The step's diagnostics: constraint errors, energy, the mechanism's size and a run's failure.
#include "ldlpgs/physics/step_stages.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "ldlpgs/physics/chain_fits.h"

namespace ldlpgs {

ConstraintError constraint_error(const Mechanism& m, ChainFits* fits) {
  ConstraintError e;
  double sum_p = 0, sum_a = 0;
  int n_p = 0, n_a = 0;
  for (int k = 0; k < static_cast<int>(m.constraints.size()); ++k) {
    const Constraint& c = m.constraints[k];
    const ConstraintRows rows = evaluate(c, m.bodies[c.body_a], m.bodies[c.body_b], fits ? fits->constraint(m, k) : nullptr);
    for (int r = 0; r < rows.rows; ++r) {
      const double v = is_equality(c.type) ? std::abs(rows.c[r]) : std::max(0.0, -rows.c[r]);
      if (rows.angular[r]) {
        e.angular_max = std::max(e.angular_max, v);
        sum_a += v * v;
        ++n_a;
      } else {
        e.position_max = std::max(e.position_max, v);
        sum_p += v * v;
        ++n_p;
      }
    }
  }
  e.position_rms = n_p ? std::sqrt(sum_p / n_p) : 0;
  e.angular_rms = n_a ? std::sqrt(sum_a / n_a) : 0;
  return e;
}

double total_energy(const Mechanism& m) {
  double e = 0;
  for (const RigidBody& b : m.bodies)
    if (!b.is_static) e += b.kinetic_energy() - b.mass * m.gravity.dot(b.position);
  return e;
}

double mechanism_size(const Mechanism& m) {
  Eigen::AlignedBox3d box;
  for (const RigidBody& b : m.bodies) box.extend(b.position);
  for (const Constraint& c : m.constraints) {
    box.extend(m.bodies[c.body_a].to_world(c.anchor_a));
    box.extend(m.bodies[c.body_b].to_world(c.anchor_b));
  }
  return box.isEmpty() ? 0 : box.diagonal().norm();
}

std::string run_failure(const StepReport& r, double size) {
  if (!std::isfinite(r.energy) || !std::isfinite(r.error.position_max) || !std::isfinite(r.error.angular_max))
    return "non-finite state";
  if (size > 0 && r.error.position_max > kApartFraction * size) {
    char line[200];
    std::snprintf(line, sizeof line, "position error %.3g m, beyond %g of the mechanism's size %.3g m: it came apart",
                  r.error.position_max, kApartFraction, size);
    return line;
  }
  return "";
}

// StepOptions::diagnostics: the errors, energy and deepest contact after the step.
void Simulation::diagnose(StepReport* report) {
  report->error = constraint_error(mechanism_, &chain_fits_);
  report->energy = total_energy(mechanism_);
  report->penetration_max_m = penetration_max();
}
}  // namespace ldlpgs
