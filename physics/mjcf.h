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
//                 free                          nothing
//                 ball                          ball
//                 hinge                         hinge           (range: angular_limit)
//                 slide                         prismatic       (range: positional_limit)
//                 hinge + slide, one axis       cylindrical     (ranges: both limits)
//                 2 hinges                      universal joint (below): 4 rows  (ranges: 2 limits)
//                 3 hinges, axes meeting at P   ball at P (ranges dropped: they bound Euler angles)
//               Every other set (two or three slides, three hinges whose axes do not meet, ball
//               with other joints, a hinge and a slide on different axes) is refused:
//               constraint.h has no constraint with those rows.
//               Constraints: the joints' body by body, then the equalities in MuJoCo's order.
//   equality    connect -> ball, weld -> weld (at the relative pose of qpos0, which must be the
//               weld's relpose); joint, tendon and distance equalities are refused.
//   geoms       plane, sphere, capsule and box become Shapes (physics/shape.h) on their body, placed
//               in our body frame (the inertial frame: iquat^-1 (geom_pos - ipos), iquat^-1
//               geom_quat): a sphere's radius size[0], a capsule's radius size[0] and half length
//               size[1] along the geom's z (mjmodel.h), a box's half extents size, a plane's
//               normal the geom's +z (infinite, as in MuJoCo's contacts: its size only draws it);
//               friction = the sliding coefficient geom_friction[0]; contype and conaffinity
//               copied. A shape that fails shape_problem (a plane on a moving body) is refused.
//               Each constraint collides (Constraint::collide) as MuJoCo's body-pair filter
//               says: never within one weld group, nor between a weld group and its parent's
//               unless one is the world or filterparent is disabled. (Pairs of such bodies not
//               joined by a constraint, e.g. a welded child and its grandparent, are not
//               filtered here.)
//   options     gravity = opt.gravity (0 if disabled), timestep = opt.timestep.
// Dropped, and counted in MjcfDropped: geoms of the types without a shape (hfield, ellipsoid,
// cylinder, mesh: they touch nothing), explicit contact pairs and excludes, tendons, actuators,
// sensors, joint springs, damping, armature and friction loss, ball-joint and 3-hinge ranges,
// inactive equalities, keyframes (the mechanism starts at qpos0, at rest), MuJoCo's
// soft-constraint parameters (solref, solimp: our rows are hard) and the geoms' other contact
// parameters (condim, torsional and rolling friction, margin, gap, priority, solmix).
//
// The universal joint, MuJoCo's hinge n1 then hinge n2 on one body: n1's line is fixed in the
// parent, n2's in the child (it turns with q1), so the child keeps 2 rotational degrees of
// freedom and 4 rows must hold. Let P1 (on the parent) and P2 (on the child) be the closest
// points of the two lines at qpos0, D = P2 - P1, |D| = delta. Motion about either line keeps
// D . n1 = D . n2 = 0, |D| = delta and n1 . n2 (the angle between the axes); conversely these
// four conditions leave the child 2 degrees of freedom (its rotation, with n1 . n2 fixed, is 2-
// dimensional, and then D = delta n1 x n2 / |n1 x n2| near qpos0), so they are the joint. With
// constraint.h's rows:
//   axes that meet (delta = 0):  a ball at P = P1 = P2, and a rod of length L between P + L n1
//     on the parent and P + L n2 on the child: |L n2 - L n1| = L sqrt(2 - 2 n1.n2) holds n1.n2.
//   axes that do not meet (the humanoid's ankles: 0.018 m): four rods, each a function of the
//     four conditions: P1-P2 (|D| = delta); P1 + L n1 to P2 (|D - L n1|^2 = delta^2 + L^2 -
//     2 L D.n1); P1 to P2 + L n2 (likewise D.n2); P1 + L n1 to P2 + L n2 (then 2 L^2 (1 - n1.n2)).
// Regular while the axes are not parallel (which the rows themselves keep) and delta is not 0.
// L = 1 m (kUniversalRodLength), so a rod's error in metres reads as an angle error in radians.
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

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

constexpr double kUniversalRodLength = 1.0;  // m

// What the conversion left out (counts over the model).
struct MjcfDropped {
  int geoms = 0;             // of types without a shape: hfield, ellipsoid, cylinder, mesh
  int contact_pairs = 0;     // explicit <contact> pairs and excludes
  int tendons = 0, actuators = 0, sensors = 0, keyframes = 0;
  int joint_dynamics = 0;    // joints with stiffness, damping, armature or friction loss
  int ranges = 0;            // joint ranges not converted (ball joints, 3-hinge sets)
  int inactive_equalities = 0;
  int static_equalities = 0; // equalities between two static bodies (nothing to hold)
};
// One line: "dropped: 3 geoms of types without a shape (...), 21 actuators, ..." (empty if
// nothing was dropped).
std::string describe(const MjcfDropped& dropped);

// True if built with MuJoCo (LDLPGS_HAVE_MUJOCO); otherwise load_mjcf always throws.
bool mjcf_supported();
// True if `path` names an MJCF file (it ends in .xml).
bool is_mjcf_path(const std::string& path);

// The model at qpos0, at rest. The mechanism's name is the file's stem. `dropped` (optional)
// receives what was left out.
Mechanism load_mjcf(const std::string& path, MjcfDropped* dropped = nullptr);

}  // namespace ldlpgs
