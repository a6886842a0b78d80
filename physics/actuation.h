#pragma once
// MuJoCo's joint dynamics and actuators on a mechanism in maximal coordinates (mjModel's
// dof_armature, dof_damping, dof_frictionloss, jnt_stiffness, qpos_spring and actuator_*). Each
// acts on one dof of a joint chain (joint_set.h), whose coordinate q and rate q_dot = z . V_rel the
// chain gives (chain_dof).
//
// MuJoCo's Euler step solves (M + A + dt B) q_dot1 = (M + A) q_dot0 + dt f: the armature A (a
// rotor's inertia, added to the dof's mass) and the damping B implicitly, every other force f
// explicitly. In maximal coordinates that is one soft row per dof (dof_drive) with the impulse
//   lambda = a q_dot0 - (a + dt b) q_dot1 = -(q_dot1 - target) / C,
//   compliance C = 1 / (a + dt b),  target = a q_dot0 / (a + dt b):
// V1 minimises 1/2 |V1 - V*|_M^2 + 1/2 (a + dt b) (q_dot1 - target)^2, which where the joints
// leave only the dofs free is MuJoCo's equation (mjcf_test checks the motion against MuJoCo's).
// Explicit, as in MuJoCo: the spring -k (q - springref), and an actuator's force
//   F = gain ctrl + bias0 + bias1 L + bias2 L_dot,  L = gear q (MuJoCo's coordinate: ours + q0),
// clamped to its forcerange, applied as the generalized force tau = gear F on the dof: through
// its drive row where it has one (the target moves by dt tau C), else as the load z^T tau on
// the two bodies. A velocity term (bias2 < 0: a velocity servo, kv) is taken
// implicitly, a motor row with target speed and softness,
//   lambda = dt gear (c + bias2 gear q_dot1),  c = gain ctrl + bias0 + bias1 L,
//   1/C = -bias2 gear^2 dt,  target q_dot = c / (-bias2 gear),
// in the dof's drive row if its force is unlimited, else a dof_motor row of its own whose impulse
// is bounded by dt gear forcerange. Friction loss is a dof_motor row with target 0 and
// |lambda| <= frictionloss dt. (MuJoCo 2.2.2 takes bias2 explicitly: the implicit row is the
// stable form of the same force, equal to first order in dt.)
#include <array>
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/physics/body.h"
#include "ldlpgs/physics/constraint.h"
#include "ldlpgs/solver/system.h"

namespace ldlpgs {

// One dof's passive dynamics (zero: none).
struct DofDynamics {
  Constraint coordinate;  // a dof_drive on the dof, never stepped: measures q and q_dot
  double offset = 0;      // MuJoCo's coordinate where ours is 0 (qpos0: hinges, slides; a ball's dofs 0)
  double armature = 0;    // kg m^2 or kg, added to the dof's mass
  double damping = 0;     // N m s/rad or N s/m
  double stiffness = 0;   // N m/rad or N/m
  double springref = 0;   // the spring's rest coordinate, MuJoCo's coordinate
  double frictionloss = 0;  // N m or N: a dry friction bound on the dof
  int drive = -1;         // the constraint holding its dof_drive row (armature, damping, servos), -1 none
  int friction = -1;      // ... its friction loss's dof_motor row, -1 none
};

// A MuJoCo actuator on a joint dof (transmission "joint", no activation dynamics, fixed gain,
// affine bias): the three kinds of MJCF's shortcuts are
//   motor     gain 1,  bias (0, 0, 0)
//   position  gain kp, bias (0, -kp, 0)
//   velocity  gain kv, bias (0, 0, -kv)
struct Actuator {
  std::string name;
  int dof = -1;  // index into Mechanism::dofs; -1: no effect (kept so controls keep the model's order)
  double gear = 1, gain = 1;
  std::array<double, 3> bias{};  // bias0, bias1 (times L), bias2 (times L_dot)
  bool ctrl_limited = false;     // controls outside [ctrl_min, ctrl_max] are refused
  double ctrl_min = 0, ctrl_max = 0;
  bool force_limited = false;    // F clamped to [force_min, force_max]
  double force_min = 0, force_max = 0;
  int motor = -1;  // the constraint holding its velocity term as a bounded dof_motor row, -1 none
};

// A dof's coordinate (MuJoCo's) and its rate covector over [v_a w_a v_b w_b] (world), at the
// bodies' current pose (the fit warm-starts from the last: coordinate.coordinates).
struct DofState {
  double q = 0;                    // MuJoCo's coordinate
  double rate = 0;                 // q_dot at the bodies' current velocities
  std::array<double, 12> row{};    // q_dot = row . V
  double force = 0;                // the explicit generalized force this step (joint_dynamics)
};
// `fit`: the chain's fit at this pose where the caller shares one (chain_fits.h), else null.
DofState dof_state(const DofDynamics& dof, const std::vector<RigidBody>& bodies, const ChainFit* fit = nullptr);

// What a step asks of a dof_drive or dof_motor row: lambda = -(J V1 - target) / C within [lower,
// upper] (C = 0: a rigid row; infinite: an inert one, a drive nothing softens).
struct DofRow {
  double target = 0;      // rate (rad/s or m/s)
  double compliance = 0;  // C (absolute: s/(kg m^2) or s/kg)
  double lower = -kUnbounded, upper = kUnbounded;
};

// The controls' check, in every build: one per actuator, finite, inside ctrlrange where
// ctrl_limited. Throws an InputError naming the actuator ("controls: actuator \"hip\" (2): 1.5
// outside its ctrlrange [-1, 1]").
void check_controls(std::span<const Actuator> actuators, std::span<const double> controls);

// One step's joint dynamics at the current state, timestep dt: the explicit generalized forces
// (springs, actuators without their velocity term) added to `load` (6 per body: force then
// torque, world), and each dof_drive and dof_motor row's target, compliance and bounds into `rows`
// (indexed by constraint). `states` (size dofs) is scratch.
// The armature's q_dot0 is `last_rates` (size dofs, or empty; NaN: none yet): each dof's rate as
// the last step's solve left it, measured along that step's rows. The bodies' velocities carried
// into this pose measure more: the frame of a slide on a swinging arm has turned under them,
// which is the centrifugal change of q_dot, and a rotor's inertia must resist that change too
// (measured from the pose's own rates, a slide with armature on the humanoid-like arm of
// mjcf_test swung 0.35 m off MuJoCo in a second, at any timestep).
// `fits`: the step's shared chain fits (chain_fits.h), or null.
struct Mechanism;
class ChainFits;
void joint_dynamics(const Mechanism& mechanism, std::span<const double> controls, double dt,
                    std::span<const double> last_rates, std::span<DofState> states, std::span<double> load,
                    std::span<DofRow> rows, ChainFits* fits = nullptr);

}  // namespace ldlpgs
