// ldlpgs step SCENE and ldlpgs export SCENE: a scene (a JSON file or a built-in name) stepped
// with one of the solvers, measuring solve time against constraint error; and the matrix
// H = J W J^T + eps diag(H) of its initial pose, for the orderings and factor commands.
// ldlpgs view SCENE is step that must write its run as a page that plays it (--html-file).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

#include "apps/commands.h"
#include "apps/controls.h"
#include "apps/options.h"
#include "apps/shatter_args.h"
#include "peers/median.h"
#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/text.h"
#include "view/html.h"
#include "view/recording.h"

namespace ldlpgs::cli {

Mechanism load_mechanism(const std::string& spec, bool allow_dropped) {
  MjcfDropped dropped;
  Mechanism m = ldlpgs::load_mechanism(spec, &dropped, allow_dropped);
  // What an MJCF conversion left out, on stderr (empty for scene files and built-ins), and what
  // of it changes the dynamics, one line each.
  if (const std::string line = describe(dropped); !line.empty()) std::fprintf(stderr, "%s: %s\n", spec.c_str(), line.c_str());
  for (const std::string& line : dropped.unmodelled) std::fprintf(stderr, "%s: %s\n", spec.c_str(), line.c_str());
  return m;
}

namespace {

struct StepArgs {
  std::string scene, solver = "ldl-pgs", ordering = "best", trace, contacts_file, html_file;
  std::string friction_cone = "disk", contact_schedule = to_string(ContactOptions{}.schedule);
  int factor_contacts_after = ContactOptions{}.factor_after;
  int position_schur_after = ContactOptions{}.position_schur_after;
  double factor_contacts_mass_ratio = ContactOptions{}.factor_mass_ratio;
  double contact_margin_m = ContactOptions{}.margin;
  std::string schedule = to_string(SolverOptions{}.schedule);
  int iterations = 10, steps = 200, post_stabilize = StepOptions{}.post_stabilize;
  bool post_stabilize_refactor = false, post_stabilize_own_factor = false, curvature_target = false;
  bool implicit_gyroscopic = false;
  double timestep = 0, compliance = StepOptions{}.compliance, baumgarte = StepOptions{}.baumgarte;
  bool json = false, allow_dropped = false;
  ShatterArgs shatter;
  ControlArgs controls;
};

StepOptions step_options(const StepArgs& a) {
  StepOptions o;
  if (!solver_kind_from_string(a.solver, &o.solver.kind)) {
    std::string known;
    for (const char* name : solver_names()) known = known + " " + name;
    throw InputError("--solver " + a.solver + ": unknown solver (known:" + known + ")");
  }
  o.solver.schedule = schedule_option("--schedule", a.schedule);
  if (a.iterations < 1) throw InputError("--iterations must be at least 1");
  if (a.post_stabilize < 0 && a.post_stabilize != StepOptions::kAutoPostStabilize)
    throw InputError("--post-stabilize must be >= 0 iterations (0: off; default: 30 with ldl-pgs and direct, 0 with pgs and block-gs)");
  if (!(a.compliance >= 0) || !std::isfinite(a.compliance)) throw InputError("--compliance must be finite and >= 0");
  if (!(a.baumgarte >= 0 && a.baumgarte <= 1)) throw InputError("--baumgarte must be in [0, 1]");
  find_ordering(a.ordering);  // throws on an unknown name
  o.solver.iterations = a.iterations;
  o.solver.ordering = a.ordering;
  o.compliance = a.compliance;
  o.baumgarte = a.baumgarte;
  o.post_stabilize = a.post_stabilize;
  o.post_stabilize_refactor = a.post_stabilize_refactor;
  if (a.post_stabilize_own_factor) {
    if (a.post_stabilize_refactor) throw InputError("--post-stabilize-own-factor and --post-stabilize-refactor exclude each other");
    use_own_factor_projection(&o);
  }
  o.curvature_target = a.curvature_target;
  if (a.friction_cone != "disk" && a.friction_cone != "pyramid")
    throw InputError("--friction-cone " + a.friction_cone + ": unknown (known: disk pyramid)");
  o.contacts.friction_pyramid = a.friction_cone == "pyramid";
  o.contacts.factor_after = a.factor_contacts_after;
  o.contacts.factor_mass_ratio = a.factor_contacts_mass_ratio;
  o.contacts.margin = a.contact_margin_m;
  o.contacts.position_schur_after = a.position_schur_after;
  o.contacts.implicit_gyroscopic = a.implicit_gyroscopic;
  o.contacts.schedule = schedule_option("--contact-schedule", a.contact_schedule);
  o.diagnostics = true;
  return o;
}

// The scene's own bodies, each as its shards move (physics/shatter.h: whole_body).
// A CSV file the run writes into, with its header (none when `path` is empty).
void open_csv(const std::string& path, const char* what, const char* header, std::ofstream* out) {
  if (path.empty()) return;
  out->open(path);
  if (!*out) throw InputError(path + ": cannot write " + what);
  *out << header << '\n';
  out->precision(17);
}

// The last step's contact points, one CSV row each.
void write_contact_rows(std::ofstream& out, int step, const Simulation& sim) {
  const Mechanism& m = sim.mechanism();
  for (const Contact& c : sim.contacts()) {
    const ContactPoint& p = c.point;
    out << step << ',' << sim.time() << ',' << m.bodies[c.body_a].name << ',' << m.bodies[c.body_b].name << ','
        << p.position.x() << ',' << p.position.y() << ',' << p.position.z() << ',' << p.normal.x() << ','
        << p.normal.y() << ',' << p.normal.z() << ',' << p.depth << ',' << c.impulse[0] << ',' << c.impulse[1] << ','
        << c.impulse[2] << ',' << (c.factored ? 1 : 0) << '\n';
  }
}

void write_trace_rows(std::ofstream& out, int step, const Simulation& sim, const Mechanism& original,
                      const ShatterResult& shattered) {
  for (size_t i = 0; i < original.bodies.size(); ++i) {
    const RigidBody b = whole_body(sim.mechanism(), shattered.shards[i], original.bodies[i]);
    const auto& p = b.position;
    const auto& q = b.orientation;
    const auto &f = b.applied_force, &t = b.applied_torque;  // the scene's constant load (world frame)
    out << step << ',' << sim.time() << ',' << b.name << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << q.w()
        << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << f.x() << ',' << f.y() << ',' << f.z() << ',' << t.x()
        << ',' << t.y() << ',' << t.z() << '\n';
  }
}

// The scene as --timestep, --steps, the solver and the shattering options make it.
struct SteppedScene {
  Mechanism original;       // as loaded (the trace and the viewer show its bodies)
  ShatterResult shattered;  // .mechanism: what is stepped
};
SteppedScene stepped_scene(const StepArgs& a, const StepOptions& options) {
  SteppedScene scene;
  scene.original = load_mechanism(a.scene, a.allow_dropped);
  if (a.timestep != 0) {
    if (!(a.timestep > 0) || !std::isfinite(a.timestep)) throw InputError("--timestep must be positive");
    scene.original.timestep = a.timestep;
    check_ranges(scene.original, "--timestep");  // MechanismRanges' timestep, as a scene file's
  }
  scene.shattered = shatter_as_told(scene.original, a.shatter, a.ordering);
  const Mechanism& m = scene.shattered.mechanism;
  if (a.steps < 1) throw InputError("--steps must be at least 1");
  if (options.solver.kind == SolverKind::direct && m.first_inequality() >= 0)
    throw InputError(a.scene + ": solver direct solves equality constraints only, and the scene has a " +
                     to_string(m.constraints[m.first_inequality()].type) + " (use ldl-pgs)");
  return scene;
}

// The files a run writes as it goes, all opened before it, so that an unwritable path is refused
// before any step: the trace, the contacts and the viewer's page.
struct StepFiles {
  std::ofstream trace, contacts, html;
  std::unique_ptr<view::Recording> recording;

  StepFiles(const StepArgs& a, const SteppedScene& scene) {
    open_csv(a.contacts_file, "the contacts file",
             "step,time,body_a,body_b,x,y,z,nx,ny,nz,depth_m,impulse_normal,impulse_t1,impulse_t2,factored", &contacts);
    open_csv(a.trace, "the trace file", "step,time,body,x,y,z,qw,qx,qy,qz,fx,fy,fz,tx,ty,tz", &trace);
    if (!a.html_file.empty()) {
      html.open(a.html_file, std::ios::binary);
      if (!html) throw InputError(a.html_file + ": cannot write the HTML file");
      recording = std::make_unique<view::Recording>(scene.original, scene.shattered);
    }
  }
  void add(int step, const Simulation& sim, const StepReport& r, const SteppedScene& scene) {
    if (contacts.is_open() && step > 0) write_contact_rows(contacts, step, sim);
    if (trace.is_open()) write_trace_rows(trace, step, sim, scene.original, scene.shattered);
    if (recording && step > 0) recording->add(sim, r);
  }
  void finish(const StepArgs& a, const Simulation& sim) {
    if (recording) {
      recording->finish(sim);
      view::write_html(*recording, html);
      finish_writing(html, a.html_file, "the HTML file");
    }
    if (trace.is_open()) finish_writing(trace, a.trace, "the trace file");
    if (contacts.is_open()) finish_writing(contacts, a.contacts_file, "the contacts file");
  }
};

// The scene's constant loads, printed so that a driven run says what drives it.
struct AppliedLoads {
  int bodies = 0;
  double force_max = 0, torque_max = 0;  // N, N m
  explicit AppliedLoads(const Mechanism& m) {
    for (const RigidBody& b : m.bodies) {
      if (b.applied_force.isZero(0) && b.applied_torque.isZero(0)) continue;
      ++bodies;
      force_max = std::max(force_max, b.applied_force.norm());
      torque_max = std::max(torque_max, b.applied_torque.norm());
    }
  }
};

// What a run's steps add up to: per-step times (their medians are reported), maxima, the first
// failed factorization and the first step run_failure refuses.
struct StepTotals {
  std::vector<double> solve_us, step_us, post_us, contact_us, prepare_us, integrate_us;
  StepReport worst;  // maxima over the steps
  int64_t post_iterations = 0;
  int failed = 0;
  std::string failure, came_apart;

  void add(int step, const StepReport& r, double size) {
    solve_us.push_back(r.solve_us);
    step_us.push_back(r.step_us);
    post_us.push_back(r.post_stabilize_us);
    contact_us.push_back(r.contact_us);
    prepare_us.push_back(r.prepare_us);
    integrate_us.push_back(r.integrate_us);
    post_iterations += r.post_stabilize_iterations;
    worst.contacts = std::max(worst.contacts, r.contacts);
    worst.penetration_max_m = std::max(worst.penetration_max_m, r.penetration_max_m);
    worst.solve_us = std::max(worst.solve_us, r.solve_us);
    worst.error.position_max = std::max(worst.error.position_max, r.error.position_max);
    worst.error.angular_max = std::max(worst.error.angular_max, r.error.angular_max);
    worst.error.position_rms = std::max(worst.error.position_rms, r.error.position_rms);
    worst.error.angular_rms = std::max(worst.error.angular_rms, r.error.angular_rms);
    worst.velocity_residual = std::max(worst.velocity_residual, r.velocity_residual);
    if (!r.result.ok() && failed++ == 0) failure = "step " + std::to_string(step) + ": " + r.result.factor.message();
    if (came_apart.empty())
      if (std::string why = run_failure(r, size); !why.empty()) came_apart = "step " + std::to_string(step) + ": " + why;
  }
};

// Everything a finished run reports, in --json or as the table.
struct StepSummary {
  const StepArgs& a;
  const SteppedScene& scene;
  const Simulation& sim;
  const StepTotals& totals;
  const AppliedLoads& loads;
  const StepFiles& files;
  double energy_initial, energy_final;
  double position_error_initial;
  bool finite;
  std::string chosen;  // the ordering of H_0's blocks the LDL^T uses (best's winner); none for pgs, block-gs

  void print_json(const char* command) const;
  void print_table() const;
};

void StepSummary::print_json(const char* command) const {
  const Mechanism& end = sim.mechanism();
  const StepReport& worst = totals.worst;
  const auto string_or_null = [](const std::string& s) { return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s); };
  nlohmann::json j = {{"scene", end.name},
                      {"bodies", end.bodies.size()},
                      {"constraints", end.constraints.size()},
                      {"rows", end.num_rows()},
                      {"actuators", end.actuators.size()},
                      {"shattered_bodies", scene.shattered.shattered_bodies},
                      {"loaded_bodies", loads.bodies},
                      {"applied_force_max_n", loads.force_max},
                      {"applied_torque_max_nm", loads.torque_max},
                      {"welds", scene.shattered.welds},
                      {"steps", a.steps},
                      {"timestep_s", end.timestep},
                      {"solver", a.solver},
                      {"ordering", a.ordering},
                      {"chosen", string_or_null(chosen)},
                      {"iterations", a.iterations},
                      {"compliance", a.compliance},
                      {"schedule", a.schedule},
                      {"post_stabilize", sim.options().post_stabilize},
                      {"post_stabilize_refactor", a.post_stabilize_refactor},
                      {"post_stabilize_own_factor", a.post_stabilize_own_factor},
                      {"curvature_target", a.curvature_target},
                      {"post_stabilize_iterations", totals.post_iterations},
                      {"post_stabilize_skipped", sim.post_stabilize_skipped()},
                      {"post_stabilize_rejected", sim.post_stabilize_rejected()},
                      {"solve_us", median(totals.solve_us)},
                      {"solve_us_max", worst.solve_us},
                      {"post_stabilize_us", median(totals.post_us)},
                      {"step_us", median(totals.step_us)},
                      {"contact_us", median(totals.contact_us)},
                      {"prepare_us", median(totals.prepare_us)},
                      {"integrate_us", median(totals.integrate_us)},
                      {"contacts_max", worst.contacts},
                      {"penetration_max_m", worst.penetration_max_m},
                      {"symbolic_analyses", sim.solver().symbolic_stats().analyses},
                      {"symbolic_us", sim.solver().symbolic_stats().analysis_us},
                      {"position_error_max_m", worst.error.position_max},
                      {"position_error_rms_max_m", worst.error.position_rms},
                      {"angular_error_max_rad", worst.error.angular_max},
                      {"angular_error_rms_max_rad", worst.error.angular_rms},
                      {"position_error_initial_m", position_error_initial},
                      {"velocity_residual_max", worst.velocity_residual},
                      {"energy_initial_j", energy_initial},
                      {"energy_final_j", finite ? nlohmann::json(energy_final) : nlohmann::json(nullptr)},
                      {"failed_steps", totals.failed},
                      {"failure", string_or_null(totals.came_apart)},
                      {"html_file", string_or_null(a.html_file)},
                      {"html_frames", files.recording ? nlohmann::json(files.recording->frames()) : nlohmann::json(nullptr)}};
  cli::print_json(json_header(command, std::move(j)));
}

void StepSummary::print_table() const {
  const Mechanism& end = sim.mechanism();
  const StepReport& worst = totals.worst;
  const ShatterResult& shattered = scene.shattered;
  std::printf("%s: %zu bodies, %zu constraints, %d rows; %s, %d iterations, %d steps of %g s\n", end.name.c_str(),
              end.bodies.size(), end.constraints.size(), end.num_rows(), a.solver.c_str(), a.iterations, a.steps,
              end.timestep);
  if (sim.solver().symbolic()) std::printf("ordering              %s\n", shown_name(a.ordering, chosen).c_str());
  if (loads.bodies)
    std::printf("applied loads         %d bodies, largest force %g N, largest torque %g N m (world frame, constant)\n",
                loads.bodies, loads.force_max, loads.torque_max);
  if (shattered.shattered_bodies)
    std::printf("shattering            %d split, %d welds added (block LDL^T flops %.0f -> %.0f)\n",
                shattered.shattered_bodies, shattered.welds, shattered.flops_before, shattered.flops_after);
  std::printf("solve time per step   median %10.1f us   max %10.1f us\n", median(totals.solve_us), worst.solve_us);
  std::printf("post-stabilization    median %10.1f us   (%d iterations per step%s, %lld in all, %d steps skipped)\n",
              median(totals.post_us), sim.options().post_stabilize, a.post_stabilize_refactor ? ", refactored" : "",
              static_cast<long long>(totals.post_iterations), sim.post_stabilize_skipped());
  std::printf("whole step            median %10.1f us\n", median(totals.step_us));
  if (worst.contacts)
    std::printf("contacts              at most %d points, deepest penetration %.3e m, detection median %.1f us, "
                "%lld symbolic phases\n",
                worst.contacts, worst.penetration_max_m, median(totals.contact_us),
                static_cast<long long>(sim.solver().symbolic_stats().analyses));
  std::printf("position error        max %12.3e m     (worst step rms %.3e m)\n", worst.error.position_max,
              worst.error.position_rms);
  std::printf("angular error         max %12.3e rad   (worst step rms %.3e rad)\n", worst.error.angular_max,
              worst.error.angular_rms);
  std::printf("velocity residual     max %12.3e\n", worst.velocity_residual);
  std::printf("energy                initial %.6g J, final %.6g J\n", energy_initial, energy_final);
  if (files.recording)
    std::printf("viewer page           %s: %d frames of %d bodies, %.1f MB\n", a.html_file.c_str(),
                files.recording->frames(), files.recording->bodies(),
                static_cast<double>(std::filesystem::file_size(a.html_file)) / 1e6);
}

// A run as step and view make it: the scene, the files opened before any step, the simulation
// and, once step_all() is done, its totals.
struct StepRun {
  const StepArgs& a;
  const StepOptions options;
  const SteppedScene scene;
  const ControlSchedule controls;
  StepFiles files;
  Simulation sim;
  StepTotals totals;

  explicit StepRun(const StepArgs& args)
      : a(args), options(step_options(a)), scene(stepped_scene(a, options)), controls(a.controls, scene.original),
        files(a, scene), sim(scene.shattered.mechanism, options) {}
  // The a.steps steps, each added to the totals and to the files, which are then finished.
  void step_all() {
    files.add(0, sim, StepReport{}, scene);
    const double size = mechanism_size(scene.original);
    for (int s = 1; s <= a.steps; ++s) {
      if (!controls.empty()) sim.set_controls(controls.at(sim.time()));
      const StepReport r = sim.step();
      totals.add(s, r, size);
      files.add(s, sim, r, scene);
    }
    files.finish(a, sim);
  }
};

// `command`: step or view (the --json object's "command").
int run_step(const StepArgs& a, const char* command) {
  StepRun run(a);
  const SteppedScene& scene = run.scene;
  const AppliedLoads loads(scene.original);
  const double energy_initial = total_energy(scene.shattered.mechanism);
  const double position_error_initial = constraint_error(scene.shattered.mechanism).position_max;
  run.step_all();
  const Simulation& sim = run.sim;
  const StepTotals& totals = run.totals;
  const double energy_final = total_energy(sim.mechanism());
  const bool finite = std::isfinite(energy_final) && std::isfinite(totals.worst.error.position_max);
  const Symbolic* symbolic = sim.solver().symbolic();
  const StepSummary summary{a,    scene,          sim, totals, loads, run.files, energy_initial, energy_final,
                            position_error_initial, finite, symbolic ? symbolic->ordering() : ""};
  if (a.json) summary.print_json(command);
  else summary.print_table();
  if (totals.failed)
    std::fprintf(stderr, "ldlpgs: %d steps failed to factor; first: %s\n", totals.failed, totals.failure.c_str());
  // A run that came apart or blew up exits 1 with the first step's reason (physics/step.h).
  std::string came_apart = totals.came_apart;
  if (!finite && came_apart.empty()) came_apart = "the final state is not finite";
  if (!came_apart.empty()) std::fprintf(stderr, "ldlpgs: the simulation blew up: %s\n", came_apart.c_str());
  return totals.failed || !came_apart.empty() ? 1 : 0;
}

// What export writes must be finite. check_ranges (physics/mechanism.h) keeps W, J and H finite
// for every mechanism the readers accept; this is the last check before writing, naming the
// body or constraint whose entries are not (InputError: the input made them).
void check_finite_export(const std::string& scene, const Mechanism& m, const System& s, const SymmetricCsc& h,
                         const std::vector<int>& sizes) {
  auto finite = [](const double* p, size_t n) { return std::all_of(p, p + n, [](double x) { return std::isfinite(x); }); };
  auto fail = [&](const std::string& what) {
    std::string message = printable(scene);
    message += ": ";
    message += what;
    message += ": not finite in the exported H = J W J^T (nothing written)";
    throw InputError(message);
  };
  for (size_t b = 0, column = 0; b < m.bodies.size(); ++b) {
    if (m.bodies[b].is_static) continue;
    if (!finite(s.inverse_mass.data() + 36 * column++, 36)) fail("W of " + body_label(m, static_cast<int>(b)));
  }
  for (size_t k = 0; k < s.blocks.size(); ++k)
    if (!finite(s.cell_a(static_cast<int>(k)), 12 * static_cast<size_t>(s.blocks[k].size))) fail("J of " + constraint_label(m, static_cast<int>(k)));
  // H's row -> its equality block -> the constraint (the equality constraints in order)
  std::vector<size_t> equality;  // (size equality constraints)
  for (size_t k = 0; k < m.constraints.size(); ++k)
    if (is_equality(m.constraints[k].type)) equality.push_back(k);
  for (int j = 0; j < h.n; ++j)
    for (int p = h.col_ptr[j]; p < h.col_ptr[j + 1]; ++p) {
      if (std::isfinite(h.values[p])) continue;
      int row = h.row_idx[p];
      size_t block = 0;
      while (row >= sizes[block]) row -= sizes[block++];
      fail("H on the rows of " + constraint_label(m, static_cast<int>(equality[block])));
    }
}

// The options step and view share: every one of step's.
void add_step_options(CLI::App* cmd, StepArgs* a) {
  cmd->add_option("scene", a->scene, "Scene file (JSON), MJCF model (.xml) or built-in scene name (e.g. chain-10, four-bar)")->required();
  cmd->add_option("--solver", a->solver, "pgs, block-gs, ldl-pgs or direct")->capture_default_str();
  cmd->add_option("--iterations", a->iterations, "Solver iterations per step")
      ->capture_default_str()
      ->check(integer_in(1, std::numeric_limits<int>::max()));
  cmd->add_option("--steps", a->steps, "Number of steps")
      ->capture_default_str()
      ->check(integer_in(1, std::numeric_limits<int>::max()));
  cmd->add_option("--timestep", a->timestep, "Time step in seconds (default: the scene's)")->check(finite_in(0, HUGE_VAL, true));
  add_ordering_option(cmd, &a->ordering, "Ordering of H's blocks (ldl-pgs, direct)");
  cmd->add_option("--compliance", a->compliance, "eps of the compliance eps diag(H)")->capture_default_str();
  cmd->add_option("--baumgarte", a->baumgarte, "Fraction of the position error corrected per step")->capture_default_str();
  cmd->add_option("--schedule", a->schedule,
                  "ldl-pgs with inequality rows, on steps without contacts: talk, inequality-pgs, block-gs or schur")
      ->capture_default_str();
  cmd->add_option("--post-stabilize", a->post_stabilize,
                  "At most this many position projection iterations per step on the step's own factor (0: off; "
                  "default 30 with ldl-pgs and direct, 0 with pgs and block-gs)")
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  cmd->add_flag("--post-stabilize-refactor", a->post_stabilize_refactor,
                "Refactor at the corrected pose in each post-stabilization iteration (Newton)");
  cmd->add_flag("--post-stabilize-own-factor", a->post_stabilize_own_factor,
                "Project with the step's own factor only (J_0), never refactoring: not when its corrections stall, "
                "nor on a mechanism with shapes");
  cmd->add_flag("--curvature-target", a->curvature_target,
                "Equality rows' velocity target includes the constraints' curvature along the motion (energy-consistent)");
  cmd->add_option("--trace-file", a->trace, "Write per step and body: step,time,body,x,y,z,qw,qx,qy,qz,fx,fy,fz,tx,ty,tz (CSV; f, t: the scene's constant load)");
  add_alias(cmd, "--trace", &a->trace);
  cmd->add_option("--contacts-file", a->contacts_file,
                  "Write per step and contact point: step,time,body_a,body_b,x,y,z,nx,ny,nz,depth_m,impulse_normal,"
                  "impulse_t1,impulse_t2,factored (CSV; the normal from body a into b, impulses in N s; factored: in the LDL^T)");
  cmd->add_option("--friction-cone", a->friction_cone, "Friction bound of contacts: disk (|lambda_t| <= mu lambda_n) or pyramid (per row)")
      ->capture_default_str();
  cmd->add_option("--contact-schedule", a->contact_schedule,
                  "ldl-pgs on steps with contacts, at the velocity and position levels: talk, inequality-pgs, block-gs or schur")
      ->capture_default_str();
  cmd->add_option("--factor-contacts-after", a->factor_contacts_after,
                  "ldl-pgs: contacts pushing this many steps in a row join the LDL^T with their normal rows (0: never, the talk's schedule)")
      ->capture_default_str()
      ->check(integer_in(0, 1000000));
  cmd->add_option("--factor-contacts-mass-ratio", a->factor_contacts_mass_ratio,
                  "ldl-pgs: ... only those of a body touching a body this many times heavier (0: every one)")
      ->capture_default_str()
      ->check(finite_in(0, 1e12));
  cmd->add_option("--contact-margin-m", a->contact_margin_m,
                  "Speculative contacts: each dynamic body's shapes reach this far (m) beyond what their points travel in "
                  "a step (0: their motion alone)")
      ->capture_default_str()
      ->check(finite_in(0, 1));
  cmd->add_option("--position-schur-after", a->position_schur_after,
                  "block-gs on steps with contacts: the post-stabilization's contact rows' Schur complement takes over "
                  "from block iterations that have not converged after this many, with at most 100 contact points (0: never)")
      ->capture_default_str()
      ->check(integer_in(0, 1000000));
  cmd->add_flag("--implicit-gyroscopic", a->implicit_gyroscopic,
                "On a mechanism with shapes, take the gyroscopic term implicitly instead of keeping each body's angular "
                "momentum through its rotation");
  add_json_flag(cmd, &a->json);
  add_shatter_options(cmd, &a->shatter);
  add_control_options(cmd, &a->controls);
  add_allow_dropped_flag(cmd, &a->allow_dropped);
}

// (--html-file is registered by each command: optional in step, required in view)
constexpr const char* kHtmlFileHelp =
    "Write the run as one self-contained HTML page that plays it (three.js inlined: opens offline)";

}  // namespace

ViewPage write_view_page(const std::string& scene_name, int steps, const std::string& html_file) {
  StepArgs a;
  a.scene = scene_name;
  a.steps = steps;
  a.html_file = html_file;
  StepRun run(a);
  run.step_all();
  ViewPage page;
  page.frames = run.files.recording->frames();
  page.bytes = static_cast<int64_t>(std::filesystem::file_size(html_file));
  page.simulated_s = run.sim.time();
  page.position_error_max_m = run.totals.worst.error.position_max;
  page.penetration_max_m = run.totals.worst.penetration_max_m;
  page.failure = run.totals.came_apart;
  return page;
}

Command add_step_command(CLI::App& app) {
  auto a = std::make_shared<StepArgs>();
  CLI::App* cmd = app.add_subcommand("step", "Step a scene and measure solve time against constraint error");
  add_step_options(cmd, a.get());
  cmd->add_option("--html-file", a->html_file, kHtmlFileHelp);
  return [a] { return run_step(*a, "step"); };
}

Command add_view_command(CLI::App& app) {
  auto a = std::make_shared<StepArgs>();
  CLI::App* cmd = app.add_subcommand("view", "Step a scene as step does and write a page that plays the run");
  add_step_options(cmd, a.get());
  cmd->add_option("--html-file", a->html_file, kHtmlFileHelp)->required();
  return [a] { return run_step(*a, "view"); };
}

Command add_export_command(CLI::App& app) {
  struct Args {
    std::string scene, matrix, blocks, ordering = "best";
    double compliance = StepOptions{}.compliance;
    bool json = false;
    ShatterArgs shatter;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("export", "Write H = J W J^T + eps diag(H) of a scene's initial pose and its block sizes");
  cmd->add_option("scene", a->scene, "Scene file (JSON) or built-in scene name")->required();
  cmd->add_option("--matrix-file", a->matrix, "Matrix Market file to write (H over the equality constraints)")->required();
  add_alias(cmd, "--matrix", &a->matrix);
  cmd->add_option("--blocks-file", a->blocks, "File of block sizes to write (one per line, what --blocks reads)")->required();
  add_renamed(cmd, "--blocks", "--blocks is now --blocks-file (it writes the file; --blocks reads a partition "
                               "in order, verify and bench)");
  cmd->add_option("--compliance", a->compliance, "eps of eps diag(H); 0 writes J W J^T itself")->capture_default_str();
  add_ordering_option(cmd, &a->ordering, "Ordering whose flops choose the shards");
  add_json_flag(cmd, &a->json);
  add_shatter_options(cmd, &a->shatter);
  return [a] {
    if (!(a->compliance >= 0) || !std::isfinite(a->compliance)) throw InputError("--compliance must be finite and >= 0");
    find_ordering(a->ordering);  // throws on an unknown name
    const Mechanism m = shatter_as_told(load_mechanism(a->scene), a->shatter, a->ordering).mechanism;
    StepOptions options;
    options.compliance = a->compliance;
    std::vector<int> sizes;
    const System system = build_system(m, options);
    const SymmetricCsc h = equality_matrix(system, &sizes);
    // (a 0 x 0 file is one that order, verify and bench refuse, as spy refuses the scene)
    if (h.n == 0) throw InputError(a->scene + ": no equality constraints, H_0 is empty: nothing to export");
    check_finite_export(a->scene, m, system, h, sizes);
    write_matrix_market(a->matrix, h);
    std::ofstream out(a->blocks);
    if (!out) throw InputError(a->blocks + ": cannot write the block sizes");
    out << "% block sizes of " << a->matrix << ": one equality constraint per block, in row order\n";
    for (int s : sizes) out << s << '\n';
    finish_writing(out, a->blocks, "the block sizes");
    // The ordering a factor of the written H would use (best's winner), on its blocks.
    const BlockPattern blocks = BlockPattern::from_scalar(h, sizes);
    const std::string chosen = blocks.num_blocks() ? compute_ordering(find_ordering(a->ordering), blocks, h).chosen : "";
    if (a->json) {
      print_json(json_header("export", {{"scene", m.name},
                                        {"n", h.n},
                                        {"blocks", sizes.size()},
                                        {"nnz_lower", h.nnz()},
                                        {"ordering", a->ordering},
                                        {"chosen", chosen.empty() ? nlohmann::json(nullptr) : nlohmann::json(chosen)},
                                        {"matrix_file", a->matrix},
                                        {"blocks_file", a->blocks}}));
    } else {
      std::printf("%s: n = %d, %zu blocks, nnz(lower) = %lld, ordering %s -> %s, %s\n", m.name.c_str(), h.n,
                  sizes.size(), static_cast<long long>(h.nnz()), shown_name(a->ordering, chosen).c_str(),
                  a->matrix.c_str(), a->blocks.c_str());
    }
    return 0;
  };
}

}  // namespace ldlpgs::cli
