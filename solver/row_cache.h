#pragma once
// Internal to solver/: what the sweeps read, refreshed once per step.
#include <algorithm>
#include <span>
#include <vector>

#include "ldlpgs/solver/lanes.h"
#include "ldlpgs/solver/system.h"

namespace ldlpgs {

// The talk's impulse form of PGS reads, per row i, J_i and W J_i^T (to keep dV = W J^T lambda up
// to date without building H) and H_ii = J_i W J_i^T.
struct RowCache {
  std::vector<double> wjt;   // W J_i^T per row: 6 for column a then 6 for column b (size 12 num_rows)
  std::vector<double> diag;  // H_ii (size num_rows)
  std::vector<char> separable;  // W of the velocity block has zero coupling blocks (size num_columns)
  ContactLanes lanes;           // the contact points, four manifolds at a time (lanes.h)
  void update(const System& system);
};

// x . y over one velocity block, summed as a tree: each row of a sweep waits on the last row's
// dV, so the sum's latency, not its flops, sets a sweep's speed (papers/physics.md, "The
// solvers on the contact scenes").
inline double dot6(const double* x, const double* y) {
  return ((x[0] * y[0] + x[3] * y[3]) + (x[1] * y[1] + x[4] * y[4])) + (x[2] * y[2] + x[5] * y[5]);
}

// J_i dV for row r of block k.
inline double row_times(const System& system, int k, int r, std::span<const double> dv) {
  const RowBlock& b = system.blocks[k];
  const double sa = b.column_a >= 0 ? dot6(system.cell_a(k) + 6 * r, dv.data() + 6 * b.column_a) : 0.0;
  const double sb = b.column_b >= 0 ? dot6(system.cell_b(k) + 6 * r, dv.data() + 6 * b.column_b) : 0.0;
  return sa + sb;
}

// dV += W J_i^T dlambda for row r of block k.
inline void add_row_impulse(const System& system, const RowCache& cache, int k, int r, double dlambda,
                            std::span<double> dv) {
  const RowBlock& b = system.blocks[k];
  const double* w = cache.wjt.data() + 12 * static_cast<size_t>(b.position + r);
  if (b.column_a >= 0)
    for (int c = 0; c < 6; ++c) dv[6 * b.column_a + c] += w[c] * dlambda;
  if (b.column_b >= 0)
    for (int c = 0; c < 6; ++c) dv[6 * b.column_b + c] += w[6 + c] * dlambda;
}

// A friction block's bound now, mu max(0, lambda_n): the disk's radius, or each row's (pyramid).
inline double friction_radius(const RowBlock& b, std::span<const double> lambda) {
  return b.friction * std::max(0.0, lambda[b.friction_row]);
}

// Row i's bounds now: its own, or +-mu lambda_n on a friction row (pyramid; the disk is projected
// per block by pgs_block).
inline void row_bounds(const System& system, const RowBlock& b, int i, std::span<const double> lambda, double* lo,
                       double* hi) {
  if (b.friction_row < 0) {
    *lo = system.lower[i];
    *hi = system.upper[i];
    return;
  }
  *hi = friction_radius(b, lambda);
  *lo = -*hi;
}

// One projected Gauss-Seidel step on row i (row r of block k) of (H + diag(eps_i H_ii)) lambda = R:
//   lambda_i <- clamp(lambda_i + (R_i - J_i dV - eps_i H_ii lambda_i) / ((1 + eps_i + r_i) H_ii))
// (r_i: the block's regularization, which damps the step but leaves its fixed point)
//   dV_a += W_a J_ia^T dlambda,  dV_b += W_b J_ib^T dlambda
// About 50 flops (the talk). A row with H_ii = 0 touches no dynamic column and is skipped.
inline void pgs_row(const System& system, const RowCache& cache, int k, int r, std::span<double> lambda,
                    std::span<double> dv) {
  const int i = system.blocks[k].position + r;
  const double d = cache.diag[i];
  if (d <= 0) return;
  const double eps = system.compliance[i], reg = system.blocks[k].regularization;
  const double old = lambda[i];
  double lo, hi;
  row_bounds(system, system.blocks[k], i, lambda, &lo, &hi);
  const double inverse = 1 / ((1 + eps + reg) * d);  // (off the chain through dV: computed while J_i dV is)
  const double updated = std::clamp(old + (system.rhs[i] - row_times(system, k, r, dv) - eps * d * old) * inverse, lo, hi);
  lambda[i] = updated;
  add_row_impulse(system, cache, k, r, updated - old, dv);
}

// argmin over |x| <= r of (1/2) x^T K x + b^T x for a symmetric positive definite 2x2 K: the
// unconstrained -K^-1 b if it lies in the disk, else x(nu) = -(K + nu I)^-1 b with |x(nu)| = r,
// nu > 0 (the trust-region subproblem), by Newton's method on 1/|x(nu)| - 1/r in K's eigenbasis
// (Moré and Sorensen, 1983: that function is nearly linear in nu, so a few iterations do).
void disk_minimizer(double k11, double k12, double k22, const double b[2], double r, double x[2]);
// Whether K is positive definite enough for disk_minimizer (else a block is stepped row by row).
inline bool disk_solvable(double k11, double k12, double k22) {
  return k11 > 0 && k22 > 0 && k11 * k22 - k12 * k12 > 1e-14 * k11 * k22;
}

// The rows of a friction block with the disk bound, |lambda_block| <= mu lambda_n, solved
// together on the disk (pgs.cpp: the block's exact step, maximal dissipation on the rim).
void pgs_friction_disk(const System& system, const RowCache& cache, int k, std::span<double> lambda,
                       std::span<double> dv);

// One projected Gauss-Seidel step on every row of block k (friction disks as one).
inline void pgs_block(const System& system, const RowCache& cache, int k, std::span<double> lambda,
                      std::span<double> dv) {
  const RowBlock& b = system.blocks[k];
  if (b.friction_row >= 0 && !b.friction_pyramid) {
    pgs_friction_disk(system, cache, k, lambda, dv);
    return;
  }
  for (int r = 0; r < b.size; ++r) pgs_row(system, cache, k, r, lambda, dv);
}

// lambda clamped into its bounds (friction blocks onto their disk or box at the clamped normal
// impulse; normal rows come before their friction rows): a warm start's projection.
void project_onto_bounds(const System& system, std::span<double> lambda);

// pgs.cpp: one sweep over the rows of every block (inequality_only: of the bounded blocks), in the
// lanes' order (lanes.h): the blocks outside the lanes in block order, then the lanes' groups.
void pgs_sweep(const System& system, const RowCache& cache, std::span<double> lambda, std::span<double> dv,
               bool inequality_only = false);

}  // namespace ldlpgs
