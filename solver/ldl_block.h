#pragma once
// Internal to solver/: the talk's block 0 of LDL-PGS, all equality rows as one block of the
// block Gauss-Seidel iteration, solved exactly by the sparse block LDL^T of
// H_0 + eps diag(H_0) (ldl_pgs.cpp). Symbolic phase in the constructor, numeric per step.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "factor/numeric.h"
#include "factor/symbolic.h"
#include "solver/equality_matrix.h"
#include "solver/row_cache.h"
#include "solver/solver.h"

namespace ldlpgs {

class LdlBlock {
 public:
  LdlBlock(const System& structure, const std::string& ordering);
  // Assembles H_0 + diag(eps_i (H_0)_ii) and factors it.
  FactorInfo factorize(const System& system);
  // One exact block step: dlambda_0 = (H_0 + E D_0)^-1 (R_0 - J_0 dV - E D_0 lambda_0),
  // lambda_0 += dlambda_0, dV += W J_0^T dlambda_0 (D_0 = diag(H_0) = the row cache's diag,
  // E = diag(eps_i)).
  void block_step(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv);
  const Symbolic& symbolic() const { return *symbolic_; }

 private:
  EqualityMatrix h_;
  std::unique_ptr<Symbolic> symbolic_;  // stable address: numeric_ points to it
  std::unique_ptr<Numeric> numeric_;
  std::vector<double> work_;  // the block's residual, then its dlambda (size rows of H_0)
};

// ldl_pgs.cpp and direct.cpp: the two solvers built on the block.
SolveResult solve_ldl_pgs(const System& system, int iterations, const RowCache& rows, LdlBlock& ldl,
                          std::span<double> lambda, std::span<double> dv);
SolveResult solve_direct(const System& system, const RowCache& rows, LdlBlock& ldl, std::span<double> lambda,
                         std::span<double> dv);

}  // namespace ldlpgs
