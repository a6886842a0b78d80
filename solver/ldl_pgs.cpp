// ldl-pgs, the talk's hybrid: N-1 PGS sweeps over all rows, then one block Gauss-Seidel sweep
// in which every equality row belongs to one block (index 0) solved exactly by the sparse
// block LDL^T, and each inequality row is solved and projected on its own. PGS brings the
// inequality impulses near their active set; the exact block then removes the equality error
// that PGS leaves on long chains, heavy loads and loops.
#include "solver/ldl_block.h"

#include "ordering/ordering.h"

namespace ldlpgs {

LdlBlock::LdlBlock(const System& structure, const std::string& ordering) : h_(structure) {
  const Ordering o = compute_ordering(find_ordering(ordering), h_.blocks(), h_.matrix());
  symbolic_ = std::make_unique<Symbolic>(Symbolic::analyze(h_.matrix(), h_.blocks(), o));
  numeric_ = std::make_unique<Numeric>(*symbolic_);
  work_.resize(h_.num_rows());
}

FactorInfo LdlBlock::factorize(const System& system) {
  h_.assemble(system);
  return numeric_->factorize(h_.matrix());  // the compliance is in H_0's diagonal already
}

void LdlBlock::block_step(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv) {
  int at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at) {
      const int i = b.position + r;
      work_[at] = system.rhs[i] - row_times(system, k, r, dv) - system.compliance[i] * rows.diag[i] * lambda[i];
    }
  }
  if (!work_.empty()) numeric_->solve(work_);
  at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at) {
      lambda[b.position + r] += work_[at];
      add_row_impulse(system, rows, k, r, work_[at], dv);
    }
  }
}

SolveResult solve_ldl_pgs(const System& system, int iterations, const RowCache& rows, LdlBlock& ldl,
                          std::span<double> lambda, std::span<double> dv) {
  for (int it = 0; it + 1 < iterations; ++it) pgs_sweep(system, rows, lambda, dv);
  SolveResult result;
  result.factor = ldl.factorize(system);
  if (!result.ok()) return result;  // lambda keeps the PGS impulses; the caller reports the status
  ldl.block_step(system, rows, lambda, dv);
  pgs_sweep(system, rows, lambda, dv, /*inequality_only=*/true);
  return result;
}

}  // namespace ldlpgs
