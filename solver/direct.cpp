// direct: equality-only systems solved exactly, lambda = (H + eps diag(H))^-1 R, by the same
// sparse block LDL^T: the reference the iterative solvers are measured against. No warm start
// matters: the block step from lambda = 0, dV = 0 is the exact solve.
#include <algorithm>

#include "solver/ldl_block.h"
#include "solver/solver.h"

namespace ldlpgs {

SolveResult solve_direct(const System& system, const RowCache& rows, LdlBlock& ldl, std::span<double> lambda,
                         std::span<double> dv) {
  std::fill(lambda.begin(), lambda.end(), 0.0);
  std::fill(dv.begin(), dv.end(), 0.0);
  SolveResult result;
  result.factor = ldl.factorize(system);
  if (result.ok()) ldl.block_step(system, rows, lambda, dv);
  return result;
}

}  // namespace ldlpgs
