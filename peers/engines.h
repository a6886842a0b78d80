#pragma once
// The engines' entry points, each in its own file and compiled only with its library
// (LDLPGS_HAVE_ODE, LDLPGS_HAVE_BULLET, LDLPGS_HAVE_MUJOCO); peer.cpp puts them in the table.
#include <string>

#include "peers/peer.h"

namespace ldlpgs::peers {

// quickstep_iterations 0: dWorldStep (dense LCP), else dWorldQuickStep with that many iterations.
PeerResult run_ode(const Mechanism& m, double seconds, int quickstep_iterations);
// two_friction: SOLVER_USE_2_FRICTION_DIRECTIONS, two friction rows a contact point as ours
// (Bullet's default solves one, along the sliding direction).
PeerResult run_bullet(const Mechanism& m, double seconds, int iterations, bool two_friction = false);
PeerResult run_mujoco(const Mechanism& m, double seconds);
// Reduced coordinates; forests only. rk4: MuJoCo's RK4 at timestep / 16 (the tree reference).
PeerResult run_mujoco_tree(const Mechanism& m, double seconds, bool rk4 = false);
// The MJCF file `path` that `m` was loaded from (physics/io/mjcf.h), stepped by MuJoCo itself with
// springs, damping, armature, friction loss and actuators off, and contacts off unless `m` has
// shapes; rk4 as above.
PeerResult run_mujoco_mjcf(const std::string& path, const Mechanism& m, double seconds, bool rk4 = false);

}  // namespace ldlpgs::peers
