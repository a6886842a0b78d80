#pragma once
// Internal to solver/: block Gauss-Seidel over constraint blocks (block_gs.cpp).
#include <span>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "ldlpgs/solver/row_cache.h"

namespace ldlpgs {

constexpr int kMaxRowBlock = 6;  // the talk's constraints have 1..6 rows
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxRowBlock, kMaxRowBlock>;

// Per equality block: N_k = J_k W J_k^T + diag(eps_i (N_k)_ii), factored once per step (fixed-size
// storage, no heap).
struct BlockCache {
  std::vector<Eigen::LDLT<SmallMatrix>> factors;  // (size num_blocks; empty for inequality blocks)
  std::vector<double> diag_n;                     // eps_i (N_k)_ii per row (size num_rows)
  void update(const System& system);
};

// One sweep: equality blocks solved exactly, lambda_k += N_k^-1 (R_k - J_k dV - eps diag(N_k)
// lambda_k); rows of bounded blocks by the projected row update (block solvers cannot project).
void block_gs_sweep(const System& system, const RowCache& rows, const BlockCache& blocks, std::span<double> lambda,
                    std::span<double> dv);

}  // namespace ldlpgs
