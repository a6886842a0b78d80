// The table of peer engines, our own solvers as entries of it, and what all engines share: the
// joint separation from our anchors, the penetration metric, the reference run and the
// trajectory comparison.
#include "peers/peer.h"

#include <algorithm>
#include <cmath>

#include "peers/engines.h"
#include "ldlpgs/physics/collision.h"
#include "ldlpgs/physics/step.h"

namespace ldlpgs::peers {

// Without a library, its engine is listed but unavailable (peer_engines) and never run.
#ifndef LDLPGS_HAVE_ODE
PeerResult run_ode(const Mechanism&, double, int) { return {}; }
#endif
#ifndef LDLPGS_HAVE_BULLET
PeerResult run_bullet(const Mechanism&, double, int, bool) { return {}; }
#endif
#ifndef LDLPGS_HAVE_MUJOCO
PeerResult run_mujoco(const Mechanism&, double) { return {}; }
PeerResult run_mujoco_tree(const Mechanism&, double, bool) { return {}; }
PeerResult run_mujoco_mjcf(const std::string&, const Mechanism&, double, bool) { return {}; }
#endif

namespace {

// An engine's result under its name in the table, with the penetration of its poses.
PeerResult named(PeerResult r, const Mechanism& m, const std::string& name) {
  r.engine = name;
  r.penetration_max = penetration_max(m, r);
  return r;
}

// One of our solvers as a peer: Simulation::step timed whole (J, W, H, the solve, integration,
// post-stabilization as StepOptions defaults it, or as `post_stabilize` says).
PeerResult run_ours(const Mechanism& m, double seconds, SolverKind kind, const std::string& engine,
                    int post_stabilize = StepOptions::kAutoPostStabilize) {
  PeerResult r;
  r.engine = engine;
  if (const int i = m.first_inequality(); kind == SolverKind::direct && i >= 0) {
    r.skipped = engine + " solves equality constraints only; constraint " + std::to_string(i) + " is of type " +
                to_string(m.constraints[i].type);
    return r;
  }
  if (kind == SolverKind::direct && has_shapes(m)) {
    r.skipped = engine + " solves equality constraints only; bodies have shapes (contacts)";
    return r;
  }
  StepOptions options;
  options.solver.kind = kind;
  options.post_stabilize = post_stabilize;
  Simulation sim(m, options);
  const size_t nb = m.bodies.size();
  timed_steps(m, seconds, [&] { sim.step(); }, [&] { record_poses(sim.mechanism(), &r); }, &r);
  r.separation = joint_separation(sim.mechanism());
  for (size_t i = r.positions.size() - nb; i < r.positions.size(); ++i) r.finite = r.finite && r.positions[i].allFinite();
  if (!r.finite) r.separation = std::numeric_limits<double>::infinity();
  return r;
}

// "-baumgarte": without post-stabilization, positions left to Baumgarte's feedback alone (the
// semi-implicit Euler step the other engines take).
PeerEngine ours(const char* solver, SolverKind kind, bool baumgarte_only = false) {
  std::string name = "ldlpgs-";
  name += solver;
  if (baumgarte_only) name += "-baumgarte";
  const int post = baumgarte_only ? 0 : StepOptions::kAutoPostStabilize;
  return {name, "ldlpgs", true,
          [kind, name, post](const Mechanism& m, double s) { return named(run_ours(m, s, kind, name, post), m, name); }};
}

#ifdef LDLPGS_HAVE_ODE
constexpr bool kOde = true;
#else
constexpr bool kOde = false;
#endif
#ifdef LDLPGS_HAVE_BULLET
constexpr bool kBullet = true;
#else
constexpr bool kBullet = false;
#endif
#ifdef LDLPGS_HAVE_MUJOCO
constexpr bool kMujoco = true;
#else
constexpr bool kMujoco = false;
#endif

PeerEngine ode(int quickstep_iterations) {
  std::string name = quickstep_iterations ? "ode-quickstep-" : "ode-step";
  if (quickstep_iterations) name += std::to_string(quickstep_iterations);
  return {name, "ODE (libode-dev)", kOde, [quickstep_iterations, name](const Mechanism& m, double s) {
            return named(run_ode(m, s, quickstep_iterations), m, name);
          }};
}
PeerEngine bullet(int iterations, bool two_friction = false) {
  std::string name = "bullet-si-";
  name += std::to_string(iterations);
  if (two_friction) name += "-2f";
  return {name, "Bullet float64 (libbullet-dev)", kBullet, [iterations, two_friction, name](const Mechanism& m, double s) {
            return named(run_bullet(m, s, iterations, two_friction), m, name);
          }};
}

}  // namespace

const std::vector<PeerEngine>& peer_engines() {
  static const std::vector<PeerEngine> table = {
      ours("pgs", SolverKind::pgs),
      ours("block-gs", SolverKind::block_gs),
      ours("ldl-pgs", SolverKind::ldl_pgs),
      ours("direct", SolverKind::direct),
      ours("ldl-pgs", SolverKind::ldl_pgs, true),
      ours("direct", SolverKind::direct, true),
      ode(0),  // ODE's default QuickStep count is 20; 200 is 10x that
      ode(20),
      ode(200),
      bullet(10),  // Bullet's default m_numIterations is 10
      bullet(100),
      bullet(10, true),  // our rows a contact point: a normal and two friction directions
      {"mujoco-maximal", "MuJoCo (libmujoco-dev)", kMujoco,
       [](const Mechanism& m, double s) { return named(run_mujoco(m, s), m, "mujoco-maximal"); }},
      {"mujoco-reduced", "MuJoCo (libmujoco-dev)", kMujoco,
       [](const Mechanism& m, double s) { return named(run_mujoco_tree(m, s), m, "mujoco-reduced"); }},
  };
  return table;
}

const PeerEngine* find_peer(std::string_view name) {
  for (const PeerEngine& e : peer_engines())
    if (e.name == name) return &e;
  return nullptr;
}

PeerEngine mjcf_peer(const std::string& path) {
  return {"mujoco-mjcf", "MuJoCo (libmujoco-dev)", kMujoco, [path](const Mechanism& m, double s) {
            return named(run_mujoco_mjcf(path, m, s), m, "mujoco-mjcf");
          }};
}

int peer_steps(const Mechanism& m, double seconds) {
  return static_cast<int>(std::lround(seconds / m.timestep));
}

std::string unsupported(const Mechanism& m, std::initializer_list<ConstraintType> supported, std::string_view engine) {
  for (size_t i = 0; i < m.constraints.size(); ++i) {
    const ConstraintType t = m.constraints[i].type;
    if (std::find(supported.begin(), supported.end(), t) == supported.end()) {
      std::string why(engine);
      why += " cannot express ";
      why += to_string(t);
      why += " (constraint ";
      why += std::to_string(i);
      why += ")";
      return why;
    }
  }
  return "";
}

std::string unsupported(const Mechanism& m, std::initializer_list<ShapeType> supported, std::string_view engine) {
  for (const RigidBody& b : m.bodies)
    for (const Shape& s : b.shapes)
      if (std::find(supported.begin(), supported.end(), s.type) == supported.end()) {
        std::string why(engine);
        why += " cannot express a ";
        why += to_string(s.type);
        why += " shape (body ";
        why += b.name;
        why += ")";
        return why;
      }
  return "";
}

void record_poses(const Mechanism& state, PeerResult* r) {
  for (const RigidBody& b : state.bodies) {
    r->positions.push_back(b.position);
    r->orientations.push_back(b.orientation);
  }
}

double penetration_max(const Mechanism& m, const PeerResult& r) {
  if (!r.ran() || !has_shapes(m)) return 0;
  if (!r.finite) return std::numeric_limits<double>::infinity();
  const size_t nb = m.bodies.size();
  Mechanism at = m;
  for (RigidBody& b : at.bodies) b.linear_velocity = b.angular_velocity = Eigen::Vector3d::Zero();  // no speculative reach
  CollisionWorld world(at);
  std::vector<ContactPoint> points;
  double deepest = 0;
  for (int s = r.steps > 0 ? 1 : 0; s <= r.steps; ++s) {
    for (size_t b = 0; b < nb; ++b) {
      at.bodies[b].position = r.positions[s * nb + b];
      at.bodies[b].orientation = r.orientations[s * nb + b];
    }
    world.detect(at, 0, 0, &points);
    for (const ContactPoint& p : points) deepest = std::max(deepest, p.depth);
  }
  return deepest;
}

double joint_separation(const Constraint& c, const RigidBody& a, const RigidBody& b) {
  const Eigen::Vector3d d = b.to_world(c.anchor_b) - a.to_world(c.anchor_a);
  switch (c.type) {
    case ConstraintType::ball:
    case ConstraintType::hinge:
    case ConstraintType::weld:
      return d.norm();
    case ConstraintType::prismatic:
    case ConstraintType::cylindrical: {
      const Eigen::Vector3d n = a.orientation * c.frame_a.col(2);
      return (d - d.dot(n) * n).norm();
    }
    case ConstraintType::rod:
      return std::abs(d.norm() - c.length);
    case ConstraintType::joint_set: {  // the largest of its translational rows
      const ConstraintRows rows = evaluate(c, a, b);
      double worst = 0;
      for (int r = 0; r < rows.rows; ++r)
        if (!rows.angular[r]) worst = std::max(worst, std::abs(rows.c[r]));
      return worst;
    }
    case ConstraintType::rope:
    case ConstraintType::angular_limit:
    case ConstraintType::positional_limit:
    case ConstraintType::coordinate_limit:
    case ConstraintType::dof_drive:
    case ConstraintType::dof_motor:
      return 0;
  }
  return 0;
}

double joint_separation(const Mechanism& m) {
  double worst = 0;
  for (const Constraint& c : m.constraints)
    worst = std::max(worst, joint_separation(c, m.bodies[c.body_a], m.bodies[c.body_b]));
  return worst;
}

PeerResult reference_run(const Mechanism& m, double seconds) {
  Mechanism fine = m;
  fine.timestep = m.timestep / 16;
  PeerResult r = run_ours(fine, seconds, SolverKind::direct, "reference (ldlpgs-direct, timestep / 16)");
  return r;
}

PeerResult rk4_reference_run(const Mechanism& m, double seconds, const std::string& mjcf_path) {
  PeerResult r;
  if (!kMujoco) {
    r.skipped = "MuJoCo (libmujoco-dev) is not installed";
  } else if (has_shapes(m)) {
    r.skipped = "bodies have shapes: a contact scene has no reference trajectory (its motion is the contact solver's)";
  } else if (!mjcf_path.empty()) {
    r = run_mujoco_mjcf(mjcf_path, m, seconds, true);
    r.engine = "MuJoCo RK4 on the MJCF file, timestep / 16";
  } else {
    r = run_mujoco_tree(m, seconds, true);
    r.engine = "MuJoCo RK4 in reduced coordinates, timestep / 16";
  }
  return r;
}

void compare_to(const PeerResult& reference, PeerResult* result) {
  result->trajectory_error = std::numeric_limits<double>::quiet_NaN();
  if (!reference.ran() || !result->ran() || result->steps == 0) return;
  if (!result->finite) {
    result->trajectory_error = std::numeric_limits<double>::infinity();
    return;
  }
  const size_t nb = result->positions.size() / (result->steps + 1);
  const int stride = reference.steps / result->steps;  // 16: the same simulated time
  double worst = 0;
  for (int s = 0; s <= result->steps; ++s)
    for (size_t b = 0; b < nb; ++b)
      worst = std::max(worst, (result->positions[s * nb + b] - reference.positions[s * stride * nb + b]).norm());
  result->trajectory_error = std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
}

}  // namespace ldlpgs::peers
