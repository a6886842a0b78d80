// The velocity step of the talk (semi-implicit Euler) around the constraint solver: the step as
// its stages (step_stages.h), the options, and the Simulation's construction.
#include "ldlpgs/physics/step.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>

#include "ldlpgs/physics/step_stages.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

using namespace step_stages;

bool equality_only(const Mechanism& m) { return m.first_inequality() < 0 && !has_shapes(m); }

void use_own_factor_projection(StepOptions* options) {
  options->post_stabilize_refactor_on_stall = false;
  options->contacts.refactor_projection = false;
}

int post_stabilize_iterations(const StepOptions& options) {
  if (options.post_stabilize != StepOptions::kAutoPostStabilize) return options.post_stabilize;
  const bool factors = options.solver.kind == SolverKind::ldl_pgs || options.solver.kind == SolverKind::direct;
  return factors ? 30 : 0;
}

Simulation::Simulation(Mechanism mechanism, const StepOptions& options)
    : mechanism_(std::move(mechanism)),
      options_(options),
      column_(body_columns(mechanism_)),
      system_(system_structure(mechanism_, column_)),
      solver_(system_, options.solver),
      lambda_(mechanism_.num_rows(), 0.0),
      dv_(6 * static_cast<size_t>(mechanism_.num_dynamic_bodies()), 0.0),
      v0_(dv_.size(), 0.0),
      mu_(lambda_.size(), 0.0),
      predicted_(lambda_.size(), 0.0),
      evaluated_(mechanism_.constraints.size()),
      load_(6 * mechanism_.bodies.size(), 0.0),
      saved_position_(mechanism_.bodies.size()),
      saved_orientation_(mechanism_.bodies.size()),
      joint_blocks_(static_cast<int>(mechanism_.constraints.size())),
      jointed_(mechanism_.bodies.size(), 0),
      carrying_(mechanism_.bodies.size(), 0),
      controls_(mechanism_.actuators.size(), 0.0),
      dof_states_(mechanism_.dofs.size()),
      dof_rows_(mechanism_.constraints.size()),
      dof_rates_(mechanism_.dofs.size(), std::numeric_limits<double>::quiet_NaN()),
      chain_fits_(mechanism_) {
  for (const Constraint& c : mechanism_.constraints)
    if (is_equality(c.type)) jointed_[c.body_a] = jointed_[c.body_b] = 1;
  if (has_shapes(mechanism_)) {
    if (options.solver.kind == SolverKind::direct) {
      const auto shaped = std::find_if(mechanism_.bodies.begin(), mechanism_.bodies.end(),
                                       [](const RigidBody& b) { return !b.shapes.empty(); });
      throw InputError("the direct solver takes no contacts: " +
                       body_label(mechanism_, static_cast<int>(shaped - mechanism_.bodies.begin())) +
                       " has shapes (use ldl-pgs)");
    }
    collision_ = std::make_unique<CollisionWorld>(mechanism_);
  }
  options_.post_stabilize = post_stabilize_iterations(options);
  if (options_.post_stabilize < 0 || options.post_stabilize_sweeps < 1 || !(options.post_stabilize_tolerance >= 0))
    throw InputError("post-stabilization: iterations >= 0, sweeps >= 1 and a tolerance >= 0 are required");
  if (!(options.contacts.margin >= 0 && options.contacts.margin <= 1))
    throw InputError("contacts: the margin must be in [0, 1] m, not " + std::to_string(options.contacts.margin));
  make_projector();
}

void Simulation::make_projector() {
  if (options_.post_stabilize > 0 && !solver_.symbolic()) {
    // pgs and block-gs have no factor: the projection gets one of its own, the hybrid on
    // inequality rows (contacts among them), exact otherwise.
    SolverOptions o = options_.solver;
    o.kind = equality_only(mechanism_) ? SolverKind::direct : SolverKind::ldl_pgs;
    projector_ = std::make_unique<Solver>(system_, o);
  }
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

// One step as its stages in order (MuJoCo's mj_step, Box2D's solver stages; step_stages.h):
//   collide             detect_contacts         step_contacts.cpp
//   prepare             prepare_velocity_step   step_system.cpp
//   solve velocities    solver_.solve
//   store impulses      keep_contact_impulses, keep_dof_rates
//   integrate           integrate               step_integrate.cpp
//   project positions   post_stabilize          step_projection.cpp
//   diagnostics         diagnose                step_diagnostics.cpp
StepReport Simulation::step() {
  using Clock = std::chrono::steady_clock;
  const auto us = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::micro>(b - a).count();
  };
  StepReport report;
  const auto start = Clock::now();
  if (collision_) {
    detect_contacts();
    report.contacts = static_cast<int>(contacts_.size());
  }
  const auto collided = Clock::now();
  prepare_velocity_step();
  const auto prepared = Clock::now();
  report.result = solver_.solve(system_, lambda_, dv_,
                                contacts_.empty() ? std::nullopt : std::optional(options_.contacts.schedule));
  const auto solved = Clock::now();
  keep_contact_impulses();
  keep_dof_rates();
  const auto stored = Clock::now();
  if (options_.diagnostics) report.velocity_residual = velocity_residual(system_, lambda_, dv_);
  const auto residual = Clock::now();  // (a diagnostic: in the step's time, in no stage's)
  integrate();
  std::fill(load_.begin(), load_.end(), 0.0);  // (applied for this step only)
  const auto integrated = Clock::now();
  if (options_.post_stabilize > 0) {
    // A failed factorization (report.result) leaves nothing to project with: skipped, counted.
    if (!report.result.ok() || !post_stabilize(&report)) ++post_stabilize_skipped_;
  }
  const auto end = Clock::now();
  time_ += mechanism_.timestep;
  report.contact_us = us(start, collided);
  report.prepare_us = us(collided, prepared);
  report.solve_us = us(prepared, solved);
  report.integrate_us = us(solved, stored) + us(residual, integrated);
  report.post_stabilize_us = us(integrated, end);
  report.step_us = us(start, end);
  if (options_.diagnostics) diagnose(&report);
  return report;
}
}  // namespace ldlpgs
