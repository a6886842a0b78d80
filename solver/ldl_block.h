#pragma once
// Internal to solver/: the talk's block 0 of LDL-PGS, all equality rows as one block of the
// block Gauss-Seidel iteration, solved exactly by the sparse block LDL^T of
// H_0 + eps diag(H_0) (ldl_pgs.cpp). Symbolic phase in the constructor, numeric per step.
#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/solver/equality_matrix.h"
#include "ldlpgs/solver/row_cache.h"
#include "ldlpgs/solver/solver.h"

namespace ldlpgs {

class LdlBlock {
 public:
  LdlBlock(const System& structure, const std::string& ordering);
  // Assembles H_0 + diag(eps_i (H_0)_ii) straight into the factor's packed storage and factors
  // it (rows: the row cache, updated for `system`).
  FactorInfo factorize(const System& system, const RowCache& rows);
  // One exact block step: dlambda_0 = (H_0 + E D_0)^-1 (R_0 - J_0 dV - E D_0 lambda_0),
  // lambda_0 += dlambda_0, dV += W J_0^T dlambda_0 (D_0 = diag(H_0) = the row cache's diag,
  // E = diag(eps_i)).
  void block_step(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv);
  // The exact solve of an equality-only system with the current factor: lambda = (H_0 + E D_0)^-1 R,
  // dV = W J^T lambda (no warm start).
  void exact_solve(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv);
  const Symbolic& symbolic() const { return *symbolic_; }
  // The system blocks in the factor, in its row order, and x <- M^-1 x over those rows (the
  // Schur complement's solves: schur.h).
  std::span<const int> blocks() const { return h_.system_blocks(); }
  void solve(std::span<double> x, int nrhs = 1) { numeric_->solve(x, nrhs); }
  // Whether factored inequality rows are in the block (held at their bounds by block_step).
  bool bounded() const { return !bounded_.empty(); }
  // At most this many bounded rows held at their bounds in one block step (beyond them, the
  // rest are projected): each costs one more solve.
  static constexpr int kMaxHeldRows = 16;
  // Whether this block's rows are exactly the factored blocks of `system` (RowBlock::in_factor:
  // the same blocks, sizes and columns), so that its symbolic phase serves it.
  bool serves(const System& system) const;

 private:
  EqualityMatrix h_;
  std::unique_ptr<Symbolic> symbolic_;  // stable address: numeric_ points to it
  std::unique_ptr<Numeric> numeric_;
  std::vector<double> work_;  // the block's residual, then its dlambda (size rows of H_0)
  std::vector<int64_t> packed_index_, packed_diagonal_;  // EqualityMatrix's positions in the factor's values
  std::vector<int> columns_;  // column_a, column_b of each block in the factor (size 2 blocks)

  // The bounded rows in the block (factored inequality blocks): place in the block, System row.
  struct Bounded {
    int at, system_row;
  };
  struct Held {
    int index;     // into bounded_
    bool lower;    // held at its lower bound (else the upper)
    double bound;
  };
  using HeldMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxHeldRows, kMaxHeldRows>;
  using HeldVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxHeldRows, 1>;
  void hold_bounded_rows(const System& system, std::span<const double> lambda);
  std::vector<Bounded> bounded_;          // (size bounded rows)
  std::array<Held, kMaxHeldRows> held_{};
  std::vector<double> unconstrained_;     // the step before any row is held (size rows of the block)
  std::vector<double> inverse_columns_;   // M^-1 e_c of each held row c (size kMaxHeldRows x rows), when bounded_ is not empty
};

// ldl_pgs.cpp: ldl-pgs's iterations on a system with inequality rows, after the factorization
// (factored: whether it succeeded; if not, only the PGS sweeps run and lambda keeps their impulses).
// Returns false if a tolerance was given and the iterations stopped at their count instead.
// The block-gs schedule stops early once an iteration changes no entry of dV by more than
// `tolerance` (0: never), comparing against `dv_before` (scratch, the size of dV); the schur
// schedule once a sweep changes no row's residual by more than it (schur.h, its workspace).
class SchurComplement;
struct LdlPgsIterations {
  int count;
  HybridSchedule schedule;
  double tolerance;
  std::span<double> dv_before;
  SchurComplement* schur;
};
bool ldl_pgs_iterate(const System& system, const LdlPgsIterations& iterations, const RowCache& rows, LdlBlock& ldl,
                     bool factored, std::span<double> lambda, std::span<double> dv);

}  // namespace ldlpgs
