#pragma once
// Internal to solver/: what the sweeps read, refreshed once per step.
#include <algorithm>
#include <span>
#include <vector>

#include "ldlpgs/solver/system.h"

namespace ldlpgs {

// The talk's impulse form of PGS reads, per row i, J_i and W J_i^T (to keep dV = W J^T lambda up
// to date without building H) and H_ii = J_i W J_i^T.
struct RowCache {
  std::vector<double> wjt;   // W J_i^T per row: 6 for column a then 6 for column b (size 12 num_rows)
  std::vector<double> diag;  // H_ii (size num_rows)
  std::vector<char> separable;  // W of the velocity block has zero coupling blocks (size num_columns)
  void update(const System& system);
};

// J_i dV for row r of block k.
inline double row_times(const System& system, int k, int r, std::span<const double> dv) {
  const RowBlock& b = system.blocks[k];
  double s = 0;
  if (b.column_a >= 0)
    for (int c = 0; c < 6; ++c) s += system.cell_a(k)[6 * r + c] * dv[6 * b.column_a + c];
  if (b.column_b >= 0)
    for (int c = 0; c < 6; ++c) s += system.cell_b(k)[6 * r + c] * dv[6 * b.column_b + c];
  return s;
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

// One projected Gauss-Seidel step on row i (row r of block k) of (H + diag(eps_i H_ii)) lambda = R:
//   lambda_i <- clamp(lambda_i + (R_i - J_i dV - eps_i H_ii lambda_i) / ((1 + eps_i) H_ii))
//   dV_a += W_a J_ia^T dlambda,  dV_b += W_b J_ib^T dlambda
// About 50 flops (the talk). A row with H_ii = 0 touches no dynamic column and is skipped.
inline void pgs_row(const System& system, const RowCache& cache, int k, int r, std::span<double> lambda,
                    std::span<double> dv) {
  const int i = system.blocks[k].position + r;
  const double d = cache.diag[i];
  if (d <= 0) return;
  const double eps = system.compliance[i];
  const double old = lambda[i];
  const double updated = std::clamp(old + (system.rhs[i] - row_times(system, k, r, dv) - eps * d * old) / ((1 + eps) * d),
                                    system.lower[i], system.upper[i]);
  lambda[i] = updated;
  add_row_impulse(system, cache, k, r, updated - old, dv);
}

// pgs.cpp: one sweep over the rows of every block (inequality_only: of the bounded blocks).
void pgs_sweep(const System& system, const RowCache& cache, std::span<double> lambda, std::span<double> dv,
               bool inequality_only = false);

}  // namespace ldlpgs
