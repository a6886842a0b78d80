// block-gs: Gauss-Seidel over the constraint blocks (the talk's "block Gauss-Seidel": ball 3x3,
// hinge 5x5, ...). Each N_k is invertible because a constraint is regular; single-row
// inequality blocks are projected as PGS rows.
#include "ldlpgs/solver/block_gs.h"

#include <cassert>

namespace ldlpgs {

void BlockCache::update(const System& system) {
  factors.resize(system.blocks.size());
  diag_n.assign(system.num_rows, 0.0);
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    if (!b.equality) continue;
    assert(b.size <= kMaxRowBlock);
    SmallMatrix n = SmallMatrix::Zero(b.size, b.size);
    for (int side = 0; side < 2; ++side) {
      const int col = side == 0 ? b.column_a : b.column_b;
      if (col < 0) continue;
      using Cell = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor, kMaxRowBlock, 6>;
      const Eigen::Map<const Cell> j(side == 0 ? system.cell_a(k) : system.cell_b(k), b.size, 6);
      const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> w(system.inverse_mass.data() + 36 * col);
      n.noalias() += j * w * j.transpose();
    }
    for (int r = 0; r < b.size; ++r) {
      diag_n[b.position + r] = system.compliance[b.position + r] * n(r, r);
      n(r, r) += diag_n[b.position + r];
    }
    factors[k].compute(n);
  }
}

namespace {

// Block k's step: an equality block solved exactly on its own N_k, a bounded one as PGS rows.
void block_gs_step(const System& system, const RowCache& rows, const BlockCache& blocks, int k,
                   std::span<double> lambda, std::span<double> dv) {
  const RowBlock& b = system.blocks[k];
  if (!b.equality) {
    pgs_block(system, rows, k, lambda, dv);
    return;
  }
  // residual R_k - J_k dV - eps diag(N_k) lambda_k
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxRowBlock, 1> res(b.size);
  for (int r = 0; r < b.size; ++r) {
    const int i = b.position + r;
    res(r) = system.rhs[i] - row_times(system, k, r, dv) - blocks.diag_n[i] * lambda[i];
  }
  const auto delta = blocks.factors[k].solve(res).eval();
  for (int r = 0; r < b.size; ++r) {
    const int i = b.position + r;
    lambda[i] += delta(r);
    add_row_impulse(system, rows, k, r, delta(r), dv);
  }
}

}  // namespace

// In the lanes' order (lanes.h): the blocks outside the lanes in block order, then the groups.
void block_gs_sweep(const System& system, const RowCache& rows, const BlockCache& blocks, std::span<double> lambda,
                    std::span<double> dv) {
  for (int k : rows.lanes.scalar_blocks) block_gs_step(system, rows, blocks, k, lambda, dv);
  sweep_lane_groups(system, rows, lambda, dv);
}

}  // namespace ldlpgs
