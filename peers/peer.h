#pragma once
// Peer engines ("peers, same scenes, same run"): the same mechanism built in ODE, Bullet
// and MuJoCo, and stepped with each of our solvers, the scene's gravity and timestep, and the
// bodies' shapes (physics/shape.h) as each engine's collision geometry with our pair rules; for
// each, the median wall time of one whole step (collision detection included), the largest joint
// separation after a fixed simulated time (read back from the engine), the deepest penetration
// of the engine's poses (measured by our collision detector, the same for all), and every body's
// trajectory against a reference (our direct solver at a 16x smaller timestep; for trees also
// MuJoCo's reduced-coordinate RK4 at that timestep; neither for scenes with shapes).
//
// One interface, one file per engine, a table chosen by name (as the orderings are):
//   ldlpgs-pgs, ldlpgs-block-gs, ldlpgs-ldl-pgs, ldlpgs-direct   ours (peer.cpp), 10 iterations
//   ode-step, ode-quickstep-20, ode-quickstep-200               ode_peer.cpp (dWorldStep, dWorldQuickStep)
//   bullet-si-10, bullet-si-100                                  bullet_peer.cpp (sequential impulse)
//   mujoco-maximal, mujoco-reduced                               mujoco_peer.cpp (free bodies + equalities;
//                                                                the joints as coordinates, trees only)
//   mujoco-mjcf                                                  mujoco_peer.cpp: an MJCF scene's own file
//                                                                in MuJoCo (mjcf_peer; not in the table)
// An engine built without its library is listed but not available; a scene holding a constraint
// an engine cannot express is skipped by that engine, which says which constraint.
#include <chrono>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "peers/median.h"
#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs::peers {

struct PeerResult {
  std::string engine;
  std::string skipped;    // why the engine did not run the scene ("" if it ran)
  int steps = 0;          // of the scene's timestep
  double step_us = 0;     // median wall time of one whole step (us)
  double separation = 0;  // largest joint separation at the end (m), read back from the engine
  double trajectory_error = std::numeric_limits<double>::quiet_NaN();  // set by compare_to (m)
  // The deepest penetration of two shapes over the engine's poses after each step (the initial
  // pose where there are none), m: our CollisionWorld (margin 0) on the mechanism at those poses,
  // whatever the engine's own collision geometry; infinity if the run is not finite.
  double penetration_max = 0;
  bool finite = true;     // no NaN or infinity in the state
  // Centres of mass and orientations at every step, static bodies included: [step * bodies +
  // body] (each of size (steps + 1) x bodies; step 0 = the initial pose).
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Quaterniond> orientations;
  bool ran() const { return skipped.empty(); }
};

struct PeerEngine {
  std::string name;     // chosen by this name
  std::string library;  // "ODE 0.16 (double)": the library that must be installed
  bool available;       // built with that library
  // Steps the mechanism round(seconds / timestep) times (0 seconds: reads the initial pose).
  std::function<PeerResult(const Mechanism&, double seconds)> run;
};

const std::vector<PeerEngine>& peer_engines();
const PeerEngine* find_peer(std::string_view name);  // nullptr if none has that name
// For a scene loaded from the MJCF file `path` (physics/io/mjcf.h): "mujoco-mjcf", MuJoCo stepping
// that file in its own reduced coordinates with what the conversion drops turned off (springs,
// damping, armature, friction loss, actuators; contacts too unless the converted mechanism has
// shapes: then MuJoCo collides its own geoms); the natural MuJoCo peer of a real model.
PeerEngine mjcf_peer(const std::string& path);

// --- shared by the engines ---
int peer_steps(const Mechanism& m, double seconds);
// "" if every constraint's type is in `supported`, else "ENGINE cannot express TYPE (constraint I)".
std::string unsupported(const Mechanism& m, std::initializer_list<ConstraintType> supported, std::string_view engine);
// "" if every shape's type is in `supported`, else "ENGINE cannot express a TYPE shape (body NAME)".
std::string unsupported(const Mechanism& m, std::initializer_list<ShapeType> supported, std::string_view engine);
// The separation of one joint at the bodies' current pose, from our anchors: ball, hinge, weld:
// the distance between the anchor on a and the anchor on b; prismatic, cylindrical: that
// distance across the axis; rod: the change of length; inequalities: 0 (not joints).
double joint_separation(const Constraint& c, const RigidBody& a, const RigidBody& b);
double joint_separation(const Mechanism& m);  // the largest over the constraints

// Appends every body's pose in `state` to r->positions and r->orientations.
void record_poses(const Mechanism& state, PeerResult* r);
// PeerResult::penetration_max of r's recorded poses of `m`'s bodies.
double penetration_max(const Mechanism& m, const PeerResult& r);

// The measuring loop every engine shares: read_back() records the initial pose, then `steps`
// times step() (timed alone: whole steps, not the read-back) and read_back(); r->step_us is the
// median. read_back records each body's pose (record_poses).
template <class Step, class ReadBack>
void timed_steps(const Mechanism& m, double seconds, Step step, ReadBack read_back, PeerResult* r) {
  r->steps = peer_steps(m, seconds);
  r->positions.reserve((r->steps + 1) * m.bodies.size());
  r->orientations.reserve((r->steps + 1) * m.bodies.size());
  read_back();
  std::vector<double> us;  // size steps
  us.reserve(r->steps);
  for (int s = 0; s < r->steps; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    step();
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    read_back();
  }
  r->step_us = median(us);
}

// Our direct solver at timestep / 16 for the same simulated time (the reference trajectory);
// skipped when the scene has inequality constraints or shapes (direct solves equalities only).
PeerResult reference_run(const Mechanism& m, double seconds);
// The second reference, where the mechanism is a tree: MuJoCo's RK4 in reduced coordinates at
// timestep / 16, on the MJCF file itself if `mjcf_path` is not empty (mjcf_peer), else on the
// tree built from the mechanism (mujoco-reduced); skipped (with why) for a loop, a constraint
// reduced coordinates cannot express, shapes (a contact scene's motion is the contact solver's
// choice, not a discretization of one solution), or without MuJoCo. Direct at timestep / 16 is first order
// in the timestep; RK4 is fourth order: their difference is direct's discretization error.
PeerResult rk4_reference_run(const Mechanism& m, double seconds, const std::string& mjcf_path = "");
// Sets result->trajectory_error: the largest distance between a body's centre of mass and the
// reference's at the same simulated time, over every body and every step (NaN if either did not
// run, infinity if the result is not finite).
void compare_to(const PeerResult& reference, PeerResult* result);

}  // namespace ldlpgs::peers
