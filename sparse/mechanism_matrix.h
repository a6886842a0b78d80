#pragma once
// Values for the generated mechanisms: the matrix H = J W J^T a physics step solves with (the
// talk), from a random rigid-body Jacobian J and random masses W^-1, so that orderings and
// factorizations are tested on the matrices they are meant for, not only on their patterns.
#include <cstdint>
#include <span>

#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/families.h"

namespace ldlpgs {

// H = J W J^T + regularization * diag(J W J^T) for a mechanism, lower triangle, rows in block
// order (block j = joint j, as constraint_graph numbers them).
//   W: each dynamic body has 6 velocity coordinates (v, w) and W_b = blockdiag(I3 / m,
//      R diag(1/I) R^T), mass m in [0.5, 2], principal inertia I in [0.05, 0.5]^3 in a random
//      orientation R. Static bodies have W = 0: they contribute no columns and couple nothing.
//   J: a joint of k rows on bodies a, b (anchor offsets r_a, r_b from the bodies' centres) has
//      min(k, 3) translational rows [u^T, (r_a x u)^T | -u^T, -(r_b x u)^T] and k - 3 rotational
//      rows [0, u^T | 0, -u^T], each kind with orthonormal directions u: ball 3 = 3 + 0,
//      hinge 5 = 3 + 2, weld 6 = 3 + 3. Row counts outside 1..6 are asserted.
// Every block that constraint_graph(mechanism) makes adjacent is stored dense (explicit zeros
// included) and no other off-diagonal entry is, so BlockPattern::from_scalar(H, row counts) has
// exactly the constraint graph. Closed loops (loop, ladder, grid) can have more rows than their
// bodies have freedoms, and then J W J^T is singular; the talk's compliance eps * diag(H) makes
// it positive definite. regularization = 0 gives J W J^T itself (positive semidefinite).
// The same seed gives the same values on every platform. mass_scale, if given, multiplies each
// body's mass and inertia (size num_bodies): mass ratios, as a heavy load on a light chain has.
SymmetricCsc mechanism_matrix(const BodyGraph& mechanism, uint32_t seed = 1, double regularization = 1e-6,
                              std::span<const double> mass_scale = {});

}  // namespace ldlpgs
