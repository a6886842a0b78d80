// The physics side of the module: a Simulation of a scene (a JSON file, a dict in the scene
// format, an MJCF model or a built-in name) stepped by one of the solvers (physics/step.h), its
// state as NumPy arrays in the layout of Simulation's flat getters (MuJoCo's xpos, xquat); and
// sweep_run, one point of `ldlpgs sweep` (apps/sweep_case.h), what ldlpgs.study's sweep runs.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>

#include "apps/sweep_case.h"
#include "bindings.h"
#include "convert.h"
#include "ldlpgs/physics/io/mjcf.h"
#include "ldlpgs/physics/io/scene.h"
#include "ldlpgs/physics/io/scenes.h"
#include "ldlpgs/physics/step.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"
#include "view/recording.h"

namespace ldlpgs::python {

namespace {

// What `ldlpgs step SCENE` accepts (apps/step_command.cpp's load_mechanism, which is not in the
// library), and a dict in the scene file format.
Mechanism load_mechanism(py::handle scene, bool allow_dropped = false) {
  if (py::isinstance<py::dict>(scene)) {
    // JSON has no NaN or infinity: Python's dumps would write NaN, which nlohmann's parser
    // refused with its own parse_error (a RuntimeError). What dumps cannot write (a NaN, a value
    // of no JSON type) is bad input, in one line.
    // NumPy scalars (np.float64 is a float, np.int64 is not) are written as the numbers they hold.
    const py::cpp_function plain([](py::handle value) -> py::object {
      if (py::hasattr(value, "item")) return value.attr("item")();
      throw py::type_error("a " + std::string(py::str(py::type::handle_of(value).attr("__name__"))) +
                           " is not a JSON value");
    });
    std::string text;
    try {
      text = py::module_::import("json")
                 .attr("dumps")(scene, py::arg("allow_nan") = false, py::arg("default") = plain)
                 .cast<std::string>();
    } catch (py::error_already_set& e) {
      // (e.what() carries the traceback: the exception's own message only)
      const bool not_finite = e.matches(PyExc_ValueError);
      throw InputError("<dict>: not a scene in JSON terms: " + printable(std::string(py::str(e.value())), 120) +
                       (not_finite ? " (numbers must be finite)" : ""));
    }
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // an integer of 400 digits, a lone surrogate
      throw InputError("<dict>: not a scene in JSON terms: " + printable(e.what(), 120));
    }
    return parse_scene(j, "<dict>");
  }
  if (!py::isinstance<py::str>(scene) && !py::hasattr(scene, "__fspath__"))
    throw InputError("scene must be a scene file, an MJCF file, a built-in scene's name or a dict");
  const std::string spec = py::str(scene).cast<std::string>();
  // What an MJCF conversion leaves out (contacts, actuators, ...) is a warning, as the program
  // prints it on stderr.
  MjcfDropped dropped;
  Mechanism m = ldlpgs::load_mechanism(spec, &dropped, allow_dropped);
  std::string lines = describe(dropped);
  for (const std::string& line : dropped.unmodelled) lines += "; " + line;
  if (!lines.empty())
    if (PyErr_WarnEx(PyExc_UserWarning, (spec + ": " + lines).c_str(), 1) < 0) throw py::error_already_set();
  return m;
}

template <class Parse, class Names>
void parse_name(const std::string& what, const std::string& name, Parse parse, Names names) {
  if (parse(name)) return;
  std::string known;
  for (const char* n : names()) known = known + " " + n;
  throw InputError(what + "=" + name + ": unknown (known:" + known + ")");
}

// A body by index or name.
int body_index(const Simulation& sim, py::handle body) {
  if (py::isinstance<py::str>(body)) {
    const std::string name = body.cast<std::string>();
    const int b = sim.mechanism().find_body(name);
    if (b < 0) throw InputError("no body named \"" + name + "\"");
    return b;
  }
  return body.cast<int>();  // out of range: Simulation refuses it
}

Eigen::Vector3d vector3(py::handle x, const char* name) {
  const auto a = dense_copy(x, name);
  if (a.ndim() != 1 || a.shape(0) != 3) throw ArgumentError(std::string(name) + " must have 3 entries");
  return {a.at(0), a.at(1), a.at(2)};
}

// The state arrays: per body `width` numbers, as Simulation's flat getters and setters lay them out.
using Getter = void (Simulation::*)(std::span<double>) const;
using Setter = void (Simulation::*)(std::span<const double>);

py::array_t<double> get_state(const Simulation& sim, Getter get, int width) {
  const auto bodies = static_cast<py::ssize_t>(sim.mechanism().bodies.size());
  py::array_t<double> out({bodies, static_cast<py::ssize_t>(width)});
  (sim.*get)({out.mutable_data(), static_cast<size_t>(out.size())});
  return out;
}

void set_state(Simulation& sim, Setter set, int width, py::handle x, const char* name) {
  const auto a = py::module_::import("numpy").attr("ascontiguousarray")(dense_copy(x, name))
                     .cast<py::array_t<double, py::array::c_style>>();
  const auto bodies = static_cast<py::ssize_t>(sim.mechanism().bodies.size());
  if (a.ndim() != 2 || a.shape(0) != bodies || a.shape(1) != width)
    throw ArgumentError(std::string(name) + " must have shape (" + std::to_string(bodies) + ", " +
                        std::to_string(width) + ")");
  (sim.*set)({a.data(), static_cast<size_t>(a.size())});
}

// The scene's timestep replaced (None: the scene's own).
void set_timestep(Mechanism& m, std::optional<double> timestep) {
  if (!timestep) return;
  if (!(*timestep > 0) || !std::isfinite(*timestep)) throw InputError("timestep must be finite and positive");
  m.timestep = *timestep;
}

// The direct solver asserts that it is given equality rows only.
void check_solver_fits(SolverKind kind, const Mechanism& m) {
  if (kind == SolverKind::direct && m.first_inequality() >= 0)
    throw InputError(m.name + ": solver direct solves equality constraints only, and the scene has a " +
                     to_string(m.constraints[m.first_inequality()].type) + " (use ldl-pgs)");
}

Simulation make_simulation(py::handle scene, const std::string& solver, int iterations, const std::string& ordering,
                           const std::string& schedule, double compliance, double baumgarte,
                           std::optional<int> post_stabilize, bool post_stabilize_refactor,
                           bool post_stabilize_own_factor, bool curvature_target,
                           std::optional<double> timestep, bool diagnostics, bool allow_dropped) {
  // The checks `ldlpgs step` makes of its options (apps/step_command.cpp), with the keywords' names.
  StepOptions o;
  parse_name("solver", solver, [&](const std::string& s) { return solver_kind_from_string(s, &o.solver.kind); },
             solver_names);
  parse_name("schedule", schedule,
             [&](const std::string& s) { return hybrid_schedule_from_string(s, &o.solver.schedule); },
             hybrid_schedule_names);
  if (iterations < 1) throw InputError("iterations must be at least 1");
  if (post_stabilize && *post_stabilize < 0) throw InputError("post_stabilize must be >= 0 iterations (None: the solver's default)");
  if (!(compliance >= 0) || !std::isfinite(compliance)) throw InputError("compliance must be finite and >= 0");
  if (!(baumgarte >= 0 && baumgarte <= 1)) throw InputError("baumgarte must be in [0, 1]");
  find_ordering(ordering);  // throws on an unknown name
  o.solver.iterations = iterations;
  o.solver.ordering = ordering;
  o.compliance = compliance;
  o.baumgarte = baumgarte;
  o.post_stabilize = post_stabilize.value_or(StepOptions::kAutoPostStabilize);
  o.post_stabilize_refactor = post_stabilize_refactor;
  if (post_stabilize_own_factor) {
    if (post_stabilize_refactor) throw InputError("post_stabilize_own_factor and post_stabilize_refactor exclude each other");
    use_own_factor_projection(&o);
  }
  o.curvature_target = curvature_target;
  o.diagnostics = diagnostics;
  Mechanism m = load_mechanism(scene, allow_dropped);
  set_timestep(m, timestep);
  check_solver_fits(o.solver.kind, m);
  return Simulation(std::move(m), o);
}

}  // namespace

void bind_physics(py::module_& m) {
  m.def("builtin_scenes", &builtin_scene_names, "The built-in scenes' names (physics/io/scenes.h).");
  m.def("solvers", [] { return std::vector<std::string>(solver_names().begin(), solver_names().end()); });

  m.def(
      "sweep_run",
      [](py::handle scene, const std::string& solver, int iterations, double seconds, std::optional<double> timestep,
         std::optional<double> ratio) {
        SolverKind kind{};
        parse_name("solver", solver, [&](const std::string& s) { return solver_kind_from_string(s, &kind); },
                   solver_names);
        if (iterations < 1) throw InputError("iterations must be at least 1");
        if (!(seconds > 0) || !std::isfinite(seconds)) throw InputError("seconds must be finite and positive");
        Mechanism m = load_mechanism(scene);
        set_timestep(m, timestep);
        check_solver_fits(kind, m);
        if (ratio) {
          // The heaviest body scaled, as `ldlpgs sweep --stability` loads a scene; the scaled body
          // stays the heaviest unless the ratio asked for is below the next heaviest body's.
          const double own = cli::mass_ratio(m);
          if (!(*ratio >= 1) || !std::isfinite(*ratio)) throw InputError("mass_ratio must be finite and at least 1");
          if (own == 0) throw InputError(m.name + ": no dynamic body to load (mass_ratio)");
          m = cli::with_heavier_load(m, *ratio / own);
          if (const double reached = cli::mass_ratio(m); std::abs(reached - *ratio) > 1e-9 * *ratio)
            throw InputError(m.name + ": mass_ratio=" + format_number(*ratio) +
                             " is below what scaling its heaviest body can reach (its own is " + format_number(own) +
                             ")");
        }
        // The point is named by the scene as given, as `ldlpgs sweep` names it.
        const std::string name = py::isinstance<py::dict>(scene) ? m.name : std::string(py::str(scene));
        cli::SweepPoint p;
        {
          py::gil_scoped_release release;  // the steps touch no Python object
          p = cli::run_case(m, name, solver, iterations, seconds);
        }
        nlohmann::json j = cli::to_json(p);
        j["timestep_s"] = m.timestep;
        j["simulated_s"] = seconds;
        j["mass_ratio"] = cli::mass_ratio(m);
        return py::module_::import("json").attr("loads")(j.dump());
      },
      py::arg("scene"), py::arg("solver") = "ldl-pgs", py::arg("iterations") = 10, py::arg("seconds") = 1.0,
      py::arg("timestep") = py::none(), py::arg("mass_ratio") = py::none(),
      "One point of `ldlpgs sweep` (the same code, apps/sweep_case.h): the scene (as Simulation takes it) "
      "stepped for `seconds` simulated with one solver (direct: iterations ignored) and the diagnostics, its "
      "point's fields of `ldlpgs sweep --json` (solve_us the median per step; position and angular errors "
      "after the run and largest during it, None after a blow-up; failed and failure: \"non-finite\", "
      "\"energy\", \"singular\" or \"\"), and timestep_s, simulated_s and mass_ratio (heaviest over "
      "lightest dynamic mass). timestep=None is the scene's; mass_ratio=R scales the heaviest body so that "
      "the ratio is R (as `ldlpgs sweep --stability` loads it).");

  const StepOptions defaults;
  py::class_<Simulation>(m, "Simulation", py::dynamic_attr(),  // (dynamic_attr: record()'s recording, view.cpp)
                         "A mechanism stepped by one of the solvers (physics/step.h), as `ldlpgs step SCENE "
                         "--no-shatter` steps it: the module does not shatter bodies.\n"
                         "scene: a scene file (JSON), an MJCF file (.xml), a built-in scene's name (builtin_scenes()) "
                         "or a dict in the scene file format. The other arguments are `ldlpgs step`'s options; "
                         "post_stabilize=None is the solver's default (30 with ldl-pgs and direct, 0 with pgs and "
                         "block-gs), timestep=None the scene's. diagnostics=False skips the per-step constraint "
                         "error and energy (step() then reports zeros for them).")
      .def(py::init(&make_simulation), py::arg("scene"), py::arg("solver") = to_string(defaults.solver.kind),
           py::arg("iterations") = defaults.solver.iterations, py::arg("ordering") = defaults.solver.ordering,
           py::arg("schedule") = to_string(defaults.solver.schedule), py::arg("compliance") = defaults.compliance,
           py::arg("baumgarte") = defaults.baumgarte, py::arg("post_stabilize") = py::none(),
           py::arg("post_stabilize_refactor") = defaults.post_stabilize_refactor,
           py::arg("post_stabilize_own_factor") = false,
           py::arg("curvature_target") = defaults.curvature_target, py::arg("timestep") = py::none(),
           py::arg("diagnostics") = true, py::arg("allow_dropped") = false)
      .def(
          "step",
          [](py::object self, int steps) {
            Simulation& sim = self.cast<Simulation&>();
            view::Recording* recording = recording_of(self);  // since record(), if it was called
            if (steps < 0) throw InputError("steps must be >= 0");
            StepReport worst;
            int failed = 0, post_iterations = 0;
            std::string failure;
            std::vector<double> solve_us(steps), step_us(steps), contact_us(steps);  // per step, for the medians
            {
              py::gil_scoped_release release;  // the steps touch no Python object
              for (int s = 0; s < steps; ++s) {
                const StepReport r = sim.step();
                worst.error.position_max = std::max(worst.error.position_max, r.error.position_max);
                worst.error.angular_max = std::max(worst.error.angular_max, r.error.angular_max);
                worst.velocity_residual = std::max(worst.velocity_residual, r.velocity_residual);
                solve_us[s] = r.solve_us;
                step_us[s] = r.step_us;
                post_iterations += r.post_stabilize_iterations;
                worst.contacts = std::max(worst.contacts, r.contacts);
                worst.penetration_max_m = std::max(worst.penetration_max_m, r.penetration_max_m);
                contact_us[s] = r.contact_us;
                if (!r.result.ok() && failed++ == 0) failure = r.result.factor.message();
                if (recording) recording->add(sim, r);
              }
            }
            // The names of the program's vocabulary (docs/cli.md): units in the names, times medians.
            auto median = [](std::vector<double> v) {
              if (v.empty()) return 0.0;
              std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
              return v[v.size() / 2];
            };
            py::dict d;
            d["steps"] = steps;
            d["simulated_s"] = sim.time();
            d["failed_steps"] = failed;
            d["first_failure"] = failed ? py::object(py::str(failure)) : py::object(py::none());
            d["position_error_max_m"] = worst.error.position_max;
            d["angular_error_max_rad"] = worst.error.angular_max;
            d["velocity_residual_max"] = worst.velocity_residual;
            d["post_stabilize_iterations"] = post_iterations;
            d["solve_us"] = median(solve_us);
            d["step_us"] = median(step_us);
            d["contact_us"] = median(contact_us);
            d["contacts_max"] = worst.contacts;
            d["penetration_max_m"] = worst.penetration_max_m;
            return d;
          },
          py::arg("n") = 1,
          "n steps; over them the failed steps (a factorization that failed: the PGS "
          "impulses were used) and the first failure's message, the largest position (m) and angular (rad) "
          "errors, velocity residual and deepest penetration after a step (m) (with diagnostics), "
          "post-stabilization iterations, the median solve, step and collision detection times (us) and the "
          "most contact points in a step, named as in the program's --json (docs/cli.md, Command-line vocabulary).")
      .def(
          "add_shape",
          [](Simulation& sim, py::handle body, const std::string& type, py::handle position, py::handle orientation,
             double radius, double half_length, py::handle half_extents, py::handle normal, double friction,
             double restitution, uint32_t contype, uint32_t conaffinity) {
            Shape s;
            if (!shape_type_from_string(type, &s.type))
              throw InputError("add_shape: unknown shape type \"" + type + "\" (plane, sphere, capsule, box, cylinder, ellipsoid)");
            if (!position.is_none()) s.position = vector3(position, "position");
            if (!orientation.is_none()) {
              const std::vector<double> q = orientation.cast<std::vector<double>>();
              if (q.size() != 4) throw InputError("add_shape: orientation must have 4 entries (w, x, y, z)");
              s.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
            }
            s.radius = radius;
            s.half_length = half_length;
            if (!half_extents.is_none()) s.half_extents = vector3(half_extents, "half_extents");
            if (!normal.is_none()) s.normal = vector3(normal, "normal");
            s.friction = friction;
            s.restitution = restitution;
            s.contype = contype;
            s.conaffinity = conaffinity;
            sim.add_shape(body_index(sim, body), s);
          },
          py::arg("body"), py::arg("type"), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
          py::arg("radius") = 0.0, py::arg("half_length") = 0.0, py::arg("half_extents") = py::none(),
          py::arg("normal") = py::none(), py::arg("friction") = Shape{}.friction,
          py::arg("restitution") = Shape{}.restitution, py::arg("contype") = 1u, py::arg("conaffinity") = 1u,
          "A collision shape on a body (by index or name), as a scene file's \"shapes\" entry: type plane, sphere, "
          "capsule, box, cylinder (radius, half_length) or ellipsoid (half_extents: its semi-axes); pose in the "
          "body frame; checked as scene files are (InputError).")
      .def_property_readonly(
          "contacts",
          [](const Simulation& sim) {
            const std::span<const Contact> cs = sim.contacts();
            std::vector<int> a, b;
            std::vector<double> position, normal, depth, impulse;
            std::vector<uint8_t> factored;
            for (const Contact& c : cs) {
              a.push_back(c.body_a);
              b.push_back(c.body_b);
              for (int k = 0; k < 3; ++k) {
                position.push_back(c.point.position[k]);
                normal.push_back(c.point.normal[k]);
                impulse.push_back(c.impulse[k]);
              }
              depth.push_back(c.point.depth);
              factored.push_back(c.factored);
            }
            const py::ssize_t n = static_cast<py::ssize_t>(cs.size());
            py::dict d;
            d["body_a"] = numpy_copy<int>(a);
            d["body_b"] = numpy_copy<int>(b);
            d["position"] = numpy_copy<double>(position).attr("reshape")(n, 3);
            d["normal"] = numpy_copy<double>(normal).attr("reshape")(n, 3);
            d["depth_m"] = numpy_copy<double>(depth);
            d["impulse"] = numpy_copy<double>(impulse).attr("reshape")(n, 3);
            d["factored"] = numpy_copy<uint8_t>(factored).attr("astype")("bool");
            return d;
          },
          "The last step's contact points: body_a, body_b (n,), position and normal (n, 3; world, the normal "
          "from body a into b), depth_m (n,; > 0 penetrating, < 0 a speculative gap), impulse (n, 3: normal, two "
          "friction; N s) and factored (n,: the normal row was in the LDL^T).")
      .def_property("positions", [](const Simulation& s) { return get_state(s, &Simulation::get_positions, 3); },
                    [](Simulation& s, py::handle x) { set_state(s, &Simulation::set_positions, 3, x, "positions"); },
                    "(bodies, 3): centres of mass, world frame (m).")
      .def_property("orientations", [](const Simulation& s) { return get_state(s, &Simulation::get_orientations, 4); },
                    [](Simulation& s, py::handle x) { set_state(s, &Simulation::set_orientations, 4, x, "orientations"); },
                    "(bodies, 4): unit quaternions body -> world as (w, x, y, z).")
      .def_property("velocities", [](const Simulation& s) { return get_state(s, &Simulation::get_velocities, 6); },
                    [](Simulation& s, py::handle x) { set_state(s, &Simulation::set_velocities, 6, x, "velocities"); },
                    "(bodies, 6): linear (m/s) then angular (rad/s) velocity, world frame; static bodies' are 0.")
      .def(
          "constraint_errors",
          [](const Simulation& sim) {
            // Per row, what constraint_error (physics/step.h) summarizes: |c| on equality rows,
            // max(0, -c) on inequality rows (only violation counts).
            const Mechanism& mech = sim.mechanism();
            std::vector<double> error;
            std::vector<int> constraint;
            std::vector<uint8_t> angular;
            for (size_t k = 0; k < mech.constraints.size(); ++k) {
              const Constraint& c = mech.constraints[k];
              const ConstraintRows rows = evaluate(c, mech.bodies[c.body_a], mech.bodies[c.body_b]);
              for (int r = 0; r < rows.rows; ++r) {
                error.push_back(is_equality(c.type) ? std::abs(rows.c[r]) : std::max(0.0, -rows.c[r]));
                constraint.push_back(static_cast<int>(k));
                angular.push_back(rows.angular[r]);
              }
            }
            py::dict d;
            d["error"] = numpy_copy<double>(error);
            d["constraint"] = numpy_copy<int>(constraint);
            d["angular"] = numpy_copy<uint8_t>(angular).attr("astype")("bool");
            const ConstraintError e = constraint_error(mech);
            d["position_max"] = e.position_max;
            d["position_rms"] = e.position_rms;
            d["angular_max"] = e.angular_max;
            d["angular_rms"] = e.angular_rms;
            return d;
          },
          "Per constraint row at the current pose, error (|c| on equality rows, "
          "max(0, -c) on inequality rows: m or rad), constraint (its constraint's index) and angular (rad rows); "
          "and position_max, position_rms, angular_max, angular_rms over the rows (constraint_error).")
      .def(
          "apply_force",
          [](Simulation& sim, py::handle body, py::handle force, py::handle torque) {
            const Eigen::Vector3d t = torque.is_none() ? Eigen::Vector3d::Zero() : vector3(torque, "torque");
            sim.apply_force(body_index(sim, body), vector3(force, "force"), t);
          },
          py::arg("body"), py::arg("force"), py::arg("torque") = py::none(),
          "A force (N) through the centre of mass and a torque (N m), "
          "world frame, for the next step only; body by index or name.")
      .def_property_readonly("body_names",
                             [](const Simulation& s) {
                               std::vector<std::string> names;
                               for (const RigidBody& b : s.mechanism().bodies) names.push_back(b.name);
                               return names;
                             })
      .def_property_readonly("static", [](const Simulation& s) {
        std::vector<uint8_t> is_static;
        for (const RigidBody& b : s.mechanism().bodies) is_static.push_back(b.is_static);
        return numpy_copy<uint8_t>(is_static).attr("astype")("bool");
      }, "(bodies,): True for static bodies (never move).")
      .def_property(
          "controls", [](const Simulation& s) { return numpy_copy<double>(s.controls()); },
          [](Simulation& s, py::handle x) {
            const auto a = dense_copy(x, "controls");
            if (a.ndim() != 1) throw ArgumentError("controls must be one-dimensional (one per actuator)");
            s.set_controls({a.data(), static_cast<size_t>(a.size())});
          },
          "(actuators,): the actuators' controls (MuJoCo's ctrl, in actuator_names' order), applied from the next "
          "step on; zero at the start. The wrong count, a non-finite value or one outside a limited ctrlrange "
          "raises, naming the actuator.")
      .def_property_readonly("actuator_names",
                             [](const Simulation& s) {
                               std::vector<std::string> names;
                               for (const Actuator& a : s.mechanism().actuators) names.push_back(a.name);
                               return names;
                             },
                             "The actuators' names, in the model's order (an MJCF model's; others have none).")
      .def_property_readonly("name", [](const Simulation& s) { return s.mechanism().name; })
      .def_property_readonly("time", &Simulation::time, "Simulated time (s).")
      .def_property_readonly("num_rows", [](const Simulation& s) { return s.mechanism().num_rows(); })
      .def_property_readonly("energy", [](const Simulation& s) { return total_energy(s.mechanism()); },
                             "Kinetic plus gravitational potential energy (J).")
      .def_property_readonly("impulses", [](const Simulation& s) { return numpy_copy<double>(s.impulses()); },
                             "The last step's lambda, one per constraint row.")
      .def_property("timestep", [](const Simulation& s) { return s.mechanism().timestep; }, &Simulation::set_timestep)
      .def_property(
          "gravity", [](const Simulation& s) { return numpy_copy<double>({s.mechanism().gravity.data(), 3}); },
          [](Simulation& s, py::handle g) { s.set_gravity(vector3(g, "gravity")); })
      .def("__repr__", [](const Simulation& s) {
        return "<ldlpgs.Simulation " + s.mechanism().name + ": " + std::to_string(s.mechanism().bodies.size()) +
               " bodies, " + std::to_string(s.mechanism().num_rows()) + " rows, " + to_string(s.options().solver.kind) +
               ", t = " + std::to_string(s.time()) + " s>";
      });
}

}  // namespace ldlpgs::python
