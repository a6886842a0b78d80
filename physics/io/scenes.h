#pragma once
// Built-in scenes: the mechanisms the talk shows and the hard cases of an iterative solver (long
// chains, heavy loads, closed loops). Each is also written out under physics/scenes/ as a file.
//
//   pendulum                 one body on a ball joint to the ground
//   chain-N                  N links hanging from the ground by ball joints (default 10)
//   heavy-chain-N-R          chain-N whose last link carries a load R times a link's mass
//   ragdoll                  torso, head, arms, legs: ball, hinge joints with angular limits
//   four-bar                 a closed four-bar linkage of hinges (redundant constraints)
//   rope-bridge              planks joined by ropes and rods between two static posts
//   tracked-vehicle          the talk's: a main body and two closed tracks of hinged links
//   multi-wheeled-vehicle    the talk's: every wheel constraint on one heavy chassis (H dense)
//   mechanism-50             a Strandbeest on a stand: 50 joints, the talk's mechanism in size
//   driven-crank             a slider-crank from rest, its crank driven by a constant torque
//                            (gravity off: the torque's work is the kinetic energy)
// With contacts (a ground plane, 1/60 s steps, friction 0.6):
//   box-stack-R              a unit cube of R kg on one of 1 kg on the ground (default 1000)
//   pyramid-L                L layers of unit cubes, L down to 1 (default 10: 55 cubes)
//   ball-chain-N-R           N capsule links held horizontal from a pivot, a ball of R times a
//                            link's mass on the end, released onto the ground (default 20-1000)
//   tracked-vehicle-on-ground, multi-wheeled-vehicle-on-ground
//                            the two vehicles at rest on the ground, a torque on every wheel
//                            (its reaction on the chassis) driving them forward (+x)
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/physics/mechanism.h"

namespace ldlpgs {

// The names above with their default parameters (chain-10, heavy-chain-10-1000, ...).
std::vector<std::string> builtin_scene_names();
// false if `name` is not a built-in scene (parameterised names: chain-N, heavy-chain-N-R).
bool builtin_scene(std::string_view name, Mechanism* mechanism);

struct MjcfDropped;
// What the program, the Python module and a user's code accept as a mechanism: an MJCF model by
// its .xml extension (physics/io/mjcf.h; `dropped`, if given, receives what it left out, and
// `allow_dropped` steps a model with unmodelled dynamics), a scene file (physics/io/scene.h), or a
// built-in scene's name. InputError otherwise, listing the names.
Mechanism load_mechanism(const std::string& spec, MjcfDropped* dropped = nullptr, bool allow_dropped = false);

}  // namespace ldlpgs
