#pragma once
// MJCF models (MuJoCo's XML) as mechanisms in maximal coordinates. MuJoCo's own parser and
// compiler (libmujoco-dev: mj_loadXML, then mj_kinematics at qpos0) read the file; the compiled
// model is converted:
//   bodies      every MuJoCo body is one RigidBody, with the same index (0 = the world, static):
//               its mass, principal moments (body_inertia) and the pose of its inertial frame at
//               qpos0 (xipos, ximat). A body welded to the world (no joint on its path,
//               body_weldid = 0; mocap bodies too) is static: MuJoCo never moves it either, and a
//               static body costs no rows and cannot drift.
//   joints      the joints between a body and its parent become the rows removing exactly the
//               degrees of freedom they do not allow (xanchor, xaxis at qpos0):
//                 none                          weld
//                 free (alone or not)           nothing
//                 hinge                         hinge           (range: angular_limit)
//                 slide                         prismatic       (range: positional_limit)
//                 ball                          ball            (range: coordinate_limit, the cone)
//                 any other set                 joint_set       (ranges: coordinate_limit)
//               A joint_set (physics/joint_set.h) composes the body's hinges, slides and balls in
//               MuJoCo's order and removes what they do not span: planar roots (slide, slide,
//               hinge), two or three slides, universal joints, three hinges whose axes need not
//               meet, a ball beside other joints. Each range is an inequality row in MuJoCo's own
//               coordinate, measured from qpos0 (a ball's: the angle of its rotation).
//               Constraints: the joints' body by body, then the equalities in MuJoCo's order.
//   equality    connect -> ball, weld -> weld (at the relative pose of qpos0, which must be the
//               weld's relpose); joint, tendon and distance equalities are refused.
//   geoms       every geom becomes a Shape (physics/shape.h) on its body, placed in our body
//               frame (the inertial frame: iquat^-1 (geom_pos - ipos), iquat^-1 geom_quat): a
//               sphere's radius size[0], a capsule's and a cylinder's radius size[0] and half
//               length size[1] along the geom's z (mjmodel.h), a box's half extents and an
//               ellipsoid's semi-axes size, a mesh as the convex hull MuJoCo compiled for it
//               (mesh_graph; a mesh without one is refused, unless contype = conaffinity = 0:
//               then it touches nothing and is left out), an hfield as a heightfield (its grid
//               scaled by hfield_size; a moving one is refused), a plane's normal the geom's +z
//               (infinite, as in MuJoCo's contacts: its size only draws it);
//               friction = the sliding coefficient geom_friction[0]; contype and conaffinity
//               copied. A shape that fails shape_problem (a plane on a moving body) is refused.
//               Each constraint collides (Constraint::collide) as MuJoCo's body-pair filter
//               says: never within one weld group, nor between a weld group and its parent's
//               unless one is the world or filterparent is disabled. (Pairs of such bodies not
//               joined by a constraint, e.g. a welded child and its grandparent, are not
//               filtered here.)
//   dynamics    each dof's armature, damping, stiffness (springref) and friction loss, and the
//               actuators (motor, position, velocity, and <general> ones with no activation
//               dynamics, fixed gain and affine bias) on hinges and slides: Mechanism::dofs and
//               ::actuators (physics/actuation.h), measured on the body's joint chain; the dof_drive
//               and dof_motor rows they need. An actuator we do not model is kept with no effect,
//               so that the controls keep MuJoCo's order.
//   fluid       option density, viscosity and wind: MuJoCo's inertia-box model (physics/fluid.h).
//   options     gravity = opt.gravity, timestep = opt.timestep; MuJoCo's <flag>s are honoured:
//               gravity (0), contact (shapes kept, touching nothing), limit, equality,
//               constraint (all three), filterparent (the body-pair filter above); actuation
//               (Mechanism::actuation), passive (springs, damping, fluid) and frictionloss switch
//               off what they name.
// Dropped, and counted in MjcfDropped: explicit contact pairs and excludes, tendons with a range,
// spring, damper or friction loss (a bare fixed tendon does nothing and is not counted), actuators
// of other kinds, the dynamics of free joints (and of joints beside one), the ranges of joints
// beside a free joint, geoms' ellipsoid fluid model, sensors, inactive equalities, keyframes (the
// mechanism starts at qpos0, at rest), MuJoCo's soft-constraint parameters (solref, solimp: our
// rows are hard) and the geoms' other contact parameters (condim, torsional and rolling friction,
// margin, gap, priority, solmix). Of these, what changes the dynamics and has no conversion is
// refused by default, naming the first element (MjcfDropped::unmodelled).
//
// Errors: a file MuJoCo cannot parse, and every construct above that we refuse, are an
// InputError naming the file and the construct ("humanoid.xml: body \"x\": joints a (slide),
// b (slide): ..."); so is any MJCF file when the library was built without MuJoCo. Before
// MuJoCo reads the file, every number in its numeric attributes (and its includes') must be a
// finite double ("m.xml:3: <joint> axis=\"nan 0 0\": not a finite number": a nan axis made
// mj_loadXML hang); after it compiles, the timestep must be finite and > 0 and what we read of
// the model (masses, inertias, poses, anchors, axes, ranges) finite; then the mechanism must lie
// in MechanismRanges (mechanism.h). Names and MuJoCo's own messages are quoted with printable().
#include <string>
#include <vector>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

// What the conversion left out (counts over the model).
struct MjcfDropped {
  int geoms = 0;             // of types without a shape (none of MuJoCo 2.2.2's: every type converts)
  int contact_pairs = 0;     // explicit <contact> pairs and excludes
  int tendons = 0, actuators = 0, sensors = 0, keyframes = 0;
  int joint_dynamics = 0;    // free joints (or joints beside one) with stiffness, damping, armature or friction loss
  int ranges = 0;            // joint ranges not converted (joints beside a free joint)
  int fluid = 0;             // geoms with fluidshape="ellipsoid" (MuJoCo's other fluid model)
  int inactive_equalities = 0;
  int static_equalities = 0; // equalities between two static bodies (nothing to hold)
  // What of the above changes the dynamics (all but sensors, keyframes, inactive and static
  // equalities), one line per element: "tendon \"t\": its range ... is not modelled ...".
  std::vector<std::string> unmodelled;
};
// One line: "dropped: 3 geoms of types without a shape (...), 21 actuators, ..." (empty if
// nothing was dropped).
std::string describe(const MjcfDropped& dropped);

// True if built with MuJoCo (LDLPGS_HAVE_MUJOCO); otherwise load_mjcf always throws.
bool mjcf_supported();
// True if `path` names an MJCF file (it ends in .xml).
bool is_mjcf_path(const std::string& path);

// The model at qpos0, at rest. The mechanism's name is the file's stem. `dropped` (optional)
// receives what was left out. Unless `allow_dropped`, a model with something unmodelled that
// changes its dynamics is refused: an InputError naming the first ("m.xml: tendon \"t\": its
// range ... is not modelled (allow_dropped, --allow-dropped, steps without it)").
Mechanism load_mjcf(const std::string& path, MjcfDropped* dropped = nullptr, bool allow_dropped = false);

}  // namespace ldlpgs
