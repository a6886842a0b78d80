#pragma once
// The block LDL^T against CHOLMOD's simplicial LDL^T under the same scalar permutation (ours,
// Symbolic::perm, already postordered; CHOLMOD told not to postorder it again): L and D are unique for a given order, so they must agree entry by entry up to
// rounding; and both solutions are checked by their backward errors. `ldlpgs verify` prints this.
#include <cstdint>
#include <string>

#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// Two backward-stable factorizations of A differ by up to about cond(A) times their backward
// errors (Higham, Accuracy and Stability, 7.1): L, D and x are compared against
// max(factor, per_condition * cond_1(A)), so that 1e-10 holds on well-conditioned matrices
// (cond_1 below 1e-10 / per_condition = 4.5e5) and an ill-conditioned one is not called wrong
// for the digits it cannot have. The backward error has no such excuse. Measured (papers/factor.md):
// the differences stay 10 to 1000 times below eps * cond_1.
struct VerifyTolerance {
  double factor = 1e-10;                 // L, D and x: max relative difference (see Verification)
  double per_condition = 2.2e-16;        // times the condition estimate: machine epsilon
  double backward = 1e-14;               // backward error of our solution
};

struct Verification {
  std::string ordering;
  std::string chosen;  // the ordering that gave the pivots (Ordering::chosen: best's winner)
  int64_t nnz_L = 0, nnz_L_cholmod = 0;  // entries of L with the diagonal; ours counts dense blocks
  double flops = 0, flops_cholmod = 0;   // sum over columns of (column count)^2, both
  // max |L - L_cholmod| / max |L_cholmod| over strictly lower entries (an entry missing from one
  // side is a zero there), the same for D, and ||x - x_cholmod||_inf / ||x_cholmod||_inf.
  double L_rel_diff = 0, D_rel_diff = 0, x_rel_diff = 0;
  double backward_error = 0, backward_error_cholmod = 0;
  double condition_estimate = 0;  // ||A||_1 times Hager's estimate of ||A^-1||_1
  double factor_tolerance = 0;    // the tolerance applied to L, D and x (VerifyTolerance)
  FactorInfo info;         // our factorization's status
  int cholmod_status = 0;  // CHOLMOD's Common->status
  int cholmod_row = -1;    // where CHOLMOD stopped (L->minor < n): that column's original row, else -1
  // CHOLMOD factored the matrix: status CHOLMOD_OK (0) and no column where it stopped.
  bool cholmod_factored() const { return cholmod_status == 0 && cholmod_row < 0; }
  VerifyTolerance tolerance;
  // The tolerance for L, D and x could be computed and verifies at least one digit: a finite
  // condition estimate and factor_tolerance < 1. Without it nothing is verified, and ok is false
  // (a condition estimate that overflowed once made the tolerance inf and everything "agree").
  bool verifiable = false;
  bool ok = false;  // verifiable, both factorizations usable and every difference within the tolerance
};

// Throws ArgumentError unless every tolerance is finite and >= 0.
// Factors a (with the partition `blocks`) in the ordering's pivot order with both libraries and
// solves A x = b for b = A * (1, -1, 1, ...)^T. `symbolic` chooses ours's supernodes.
Verification verify_against_cholmod(const SymmetricCsc& a, const BlockPattern& blocks, const Ordering& ordering,
                                    const VerifyTolerance& tolerance = {}, const SymbolicOptions& symbolic = {});

}  // namespace ldlpgs
