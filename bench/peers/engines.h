#pragma once
// The engines' entry points, each in its own file and compiled only with its library
// (LDLPGS_HAVE_ODE, LDLPGS_HAVE_BULLET, LDLPGS_HAVE_MUJOCO); peer.cpp puts them in the table.
#include "bench/peers/peer.h"

namespace ldlpgs::peers {

// quickstep_iterations 0: dWorldStep (dense LCP), else dWorldQuickStep with that many iterations.
PeerResult run_ode(const Mechanism& m, double seconds, int quickstep_iterations);
PeerResult run_bullet(const Mechanism& m, double seconds, int iterations);
PeerResult run_mujoco(const Mechanism& m, double seconds);
PeerResult run_mujoco_tree(const Mechanism& m, double seconds);  // reduced coordinates; forests only

}  // namespace ldlpgs::peers
