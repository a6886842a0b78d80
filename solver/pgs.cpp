// pgs: projected Gauss-Seidel in the talk's impulse (Kaczmarz) form. H is never built: each row
// reads J_i dV and writes dV += W J_i^T dlambda, so a sweep costs O(rows), not O(nnz(H)).
#include "ldlpgs/solver/row_cache.h"

#include <algorithm>
#include <cmath>

namespace ldlpgs {

void pgs_sweep(const System& system, const RowCache& cache, std::span<double> lambda, std::span<double> dv,
               bool inequality_only) {
  for (int k : cache.lanes.scalar_blocks) {
    if (inequality_only && system.blocks[k].equality) continue;
    pgs_block(system, cache, k, lambda, dv);
  }
  sweep_lane_groups(system, cache, lambda, dv);
}

void disk_minimizer(double k11, double k12, double k22, const double b[2], double r, double x[2]) {
  const double inverse_det = 1 / (k11 * k22 - k12 * k12);  // (K's alone: off the chain through b)
  x[0] = -(k22 * b[0] - k12 * b[1]) * inverse_det;
  x[1] = -(k11 * b[1] - k12 * b[0]) * inverse_det;
  if (x[0] * x[0] + x[1] * x[1] <= r * r) return;
  if (r <= 0) {
    x[0] = x[1] = 0;
    return;
  }
  // K = Q diag(e1, e2) Q^T, Q = [[c, -s], [s, c]]
  const double half_trace = 0.5 * (k11 + k22), gap = std::hypot(0.5 * (k11 - k22), k12);
  const double e1 = half_trace + gap, e2 = half_trace - gap;
  const double angle = 0.5 * std::atan2(2 * k12, k11 - k22), c = std::cos(angle), s = std::sin(angle);
  const double p1 = c * b[0] + s * b[1], p2 = -s * b[0] + c * b[1];  // Q^T b
  double nu = 0;
  for (int it = 0; it < 30; ++it) {
    const double y1 = p1 / (e1 + nu), y2 = p2 / (e2 + nu);
    const double norm = std::hypot(y1, y2);
    // phi(nu) = 1/|y| - 1/r, phi' = (y1^2 / (e1 + nu) + y2^2 / (e2 + nu)) / |y|^3
    const double phi = 1 / norm - 1 / r;
    const double slope = (y1 * y1 / (e1 + nu) + y2 * y2 / (e2 + nu)) / (norm * norm * norm);
    const double next = std::max(0.0, nu - phi / slope);
    if (std::abs(next - nu) <= 1e-14 * (e1 + nu)) {
      nu = next;
      break;
    }
    nu = next;
  }
  const double y1 = -p1 / (e1 + nu), y2 = -p2 / (e2 + nu);
  const double scale = r / std::max(std::hypot(y1, y2), r);  // exactly on the rim despite rounding
  x[0] = (c * y1 - s * y2) * scale;
  x[1] = (s * y1 + c * y2) * scale;
}


void pgs_friction_disk(const System& system, const RowCache& cache, int k, std::span<double> lambda,
                       std::span<double> dv) {
  const RowBlock& b = system.blocks[k];
  if (b.size != 2) {  // (one tangent: the disk is the interval)
    for (int r = 0; r < b.size; ++r) pgs_row(system, cache, k, r, lambda, dv);
    return;
  }
  const int i = b.position;
  const double radius = friction_radius(b, lambda);
  if (radius == 0) {  // no normal impulse (a speculative contact not reached): no friction
    add_row_impulse(system, cache, k, 0, -lambda[i], dv);
    add_row_impulse(system, cache, k, 1, -lambda[i + 1], dv);
    lambda[i] = lambda[i + 1] = 0;
    return;
  }
  // The block's exact step on its disk: x = lambda_new minimizes (1/2) x^T K x + x^T (g - K lambda)
  // with K = the block's N_k + E diag(N_k), g = J dV - R + E diag(N_k) lambda, |x| <= mu lambda_n:
  // maximal dissipation, the friction opposing the slip that remains (a per-row step and a
  // rescale would bend the friction toward the stiffer direction of K).
  // J_0 dV, J_1 dV and K's coupling J_0 W J_1^T in one pass over the block's columns.
  const double* w0 = cache.wjt.data() + 12 * static_cast<size_t>(i);
  const double* w1 = w0 + 12;
  double* va = b.column_a >= 0 ? dv.data() + 6 * b.column_a : nullptr;
  double* vb = b.column_b >= 0 ? dv.data() + 6 * b.column_b : nullptr;
  const double *ja = system.cell_a(k), *jb = ja + 12;
  double jv0 = 0, jv1 = 0, k12 = 0;
  if (va) {
    jv0 += dot6(ja, va);
    jv1 += dot6(ja + 6, va);
    k12 += dot6(ja, w1);
  }
  if (vb) {
    jv0 += dot6(jb, vb);
    jv1 += dot6(jb + 6, vb);
    k12 += dot6(jb, w1 + 6);
  }
  const double eps0 = system.compliance[i], eps1 = system.compliance[i + 1];
  const double k11 = cache.diag[i] * (1 + eps0), k22 = cache.diag[i + 1] * (1 + eps1);
  if (!disk_solvable(k11, k12, k22)) {  // (a degenerate block: row by row)
    pgs_row(system, cache, k, 0, lambda, dv);
    pgs_row(system, cache, k, 1, lambda, dv);
    return;
  }
  const double l0 = lambda[i], l1 = lambda[i + 1];
  const double g0 = jv0 - system.rhs[i] + eps0 * cache.diag[i] * l0;
  const double g1 = jv1 - system.rhs[i + 1] + eps1 * cache.diag[i + 1] * l1;
  const double bvec[2] = {g0 - (k11 * l0 + k12 * l1), g1 - (k12 * l0 + k22 * l1)};
  double x[2];
  disk_minimizer(k11, k12, k22, bvec, radius, x);
  lambda[i] = x[0];
  lambda[i + 1] = x[1];
  // dV += W J_0^T dx_0 + W J_1^T dx_1, each column's two terms in that order
  const double d0 = x[0] - l0, d1 = x[1] - l1;
  if (va)
    for (int c = 0; c < 6; ++c) va[c] = va[c] + w0[c] * d0 + w1[c] * d1;
  if (vb)
    for (int c = 0; c < 6; ++c) vb[c] = vb[c] + w0[6 + c] * d0 + w1[6 + c] * d1;
}

void project_onto_bounds(const System& system, std::span<double> lambda) {
  for (const RowBlock& b : system.blocks) {
    if (b.friction_row < 0) {
      for (int i = b.position; i < b.position + b.size; ++i) lambda[i] = std::clamp(lambda[i], system.lower[i], system.upper[i]);
      continue;
    }
    const double radius = friction_radius(b, lambda);
    double sq = 0;
    for (int i = b.position; i < b.position + b.size; ++i) {
      if (b.friction_pyramid) lambda[i] = std::clamp(lambda[i], -radius, radius);
      sq += lambda[i] * lambda[i];
    }
    if (!b.friction_pyramid && sq > radius * radius) {
      const double scale = radius / std::sqrt(sq);
      for (int i = b.position; i < b.position + b.size; ++i) lambda[i] *= scale;
    }
  }
}

}  // namespace ldlpgs
