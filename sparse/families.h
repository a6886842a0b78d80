#pragma once
// Generated mechanisms for tests and benchmarks. A mechanism is a body graph (nodes = rigid
// bodies, edges = constraints with their row counts); its constraint graph (nodes = constraints,
// edges = dynamic bodies two constraints share) is the block pattern of H = J W J^T (the talk).
// Static bodies (the ground) have infinite mass and couple nothing.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/sparse/block_pattern.h"

namespace ldlpgs {

struct BodyGraph {
  struct Joint {
    int body_a, body_b;
    int rows;  // degrees of freedom removed: rod 1, ball 3, cylindrical 4, hinge 5, weld 6
  };
  std::vector<uint8_t> is_static;  // one flag per body (size num_bodies)
  std::vector<Joint> joints;       // the constraints, in block order
  int num_bodies() const { return static_cast<int>(is_static.size()); }
};

// The constraint graph of a mechanism: block j = joint j, with its row count as block size.
BlockPattern constraint_graph(const BodyGraph& mechanism);

// The families (shapes of mechanisms), by name:
//   chain   a pendulum chain hanging from the ground
//   tree    a random tree of bodies (branching 1 to 3) hanging from the ground
//   ladder  two rails joined by rungs: many small loops
//   loop    a closed track of bodies (one big loop), as a tank track
//   heavy   one heavy body that every constraint touches: a dense H
//   grid    a 2-D grid of bodies, a cloth, pinned at one edge
//   star    a hub body carrying about sqrt(m/2) chains (arms)
std::span<const std::string_view> family_names();
// About num_constraints constraints (exactly, except where the shape rounds it), row counts
// drawn from {1, 3, 4, 5, 6} by a fixed seed. Throws InputError on an unknown name.
BodyGraph make_family(std::string_view family, int num_constraints, uint32_t seed = 1);

}  // namespace ldlpgs
