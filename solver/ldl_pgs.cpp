// ldl-pgs, the talk's hybrid: N-1 PGS sweeps over all rows, then one block Gauss-Seidel sweep
// in which every equality row belongs to one block (index 0) solved exactly by the sparse
// block LDL^T, and each inequality row is solved and projected on its own. Inequality rows
// marked `factored` (contacts that stay active) join the exact block and are then projected. PGS brings the
// inequality impulses near their active set; the exact block then removes the equality error
// that PGS leaves on long chains, heavy loads and loops.
#include "ldlpgs/solver/ldl_block.h"

#include <algorithm>

#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

LdlBlock::LdlBlock(const System& structure, const std::string& ordering) : h_(structure) {
  const Ordering o = compute_ordering(find_ordering(ordering), h_.blocks(), h_.matrix());
  symbolic_ = std::make_unique<Symbolic>(Symbolic::analyze(h_.matrix(), h_.blocks(), o));
  numeric_ = std::make_unique<Numeric>(*symbolic_);
  work_.resize(h_.num_rows());
  h_.remap(symbolic_->load_map(), &packed_index_, &packed_diagonal_);
  for (int k : h_.system_blocks()) {
    columns_.push_back(structure.blocks[k].column_a);
    columns_.push_back(structure.blocks[k].column_b);
  }
}

bool LdlBlock::serves(const System& system) const {
  const std::span<const int> mine = h_.system_blocks();
  size_t at = 0;
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    if (!b.in_factor()) continue;
    if (at == mine.size() || mine[at] != k || h_.blocks().block(static_cast<int>(at)).size != b.size ||
        columns_[2 * at] != b.column_a || columns_[2 * at + 1] != b.column_b)
      return false;
    ++at;
  }
  return at == mine.size();
}

FactorInfo LdlBlock::factorize(const System& system, const RowCache& rows) {
  h_.assemble(system, rows, numeric_->begin_load(), packed_index_, packed_diagonal_);
  return numeric_->factorize_loaded();  // the compliance is in H_0's diagonal already
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
      const int i = b.position + r;
      double step = work_[at];
      // A factored inequality row is projected onto its bounds (a contact pulling is let go).
      if (!b.equality) step = std::clamp(lambda[i] + step, system.lower[i], system.upper[i]) - lambda[i];
      lambda[i] += step;
      add_row_impulse(system, rows, k, r, step, dv);
    }
  }
}

void LdlBlock::exact_solve(const System& system, const RowCache& rows, std::span<double> lambda,
                           std::span<double> dv) {
  int at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r) work_[at++] = system.rhs[b.position + r];
  }
  if (!work_.empty()) numeric_->solve(work_);
  std::fill(lambda.begin(), lambda.end(), 0.0);
  std::fill(dv.begin(), dv.end(), 0.0);
  at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at) {
      lambda[b.position + r] = work_[at];
      add_row_impulse(system, rows, k, r, work_[at], dv);  // dV = W J^T lambda from the cached W J^T
    }
  }
}

void ldl_pgs_iterate(const System& system, int iterations, HybridSchedule schedule, const RowCache& rows,
                     LdlBlock& ldl, bool factored, std::span<double> lambda, std::span<double> dv) {
  const int sweeps = schedule == HybridSchedule::block_gs ? 0 : iterations - 1;
  const bool inequality_only = schedule == HybridSchedule::inequality_pgs;
  for (int it = 0; it < sweeps; ++it) pgs_sweep(system, rows, lambda, dv, inequality_only);
  if (!factored) return;  // lambda keeps the PGS impulses; the caller reports the status
  const int block_sweeps = schedule == HybridSchedule::block_gs ? iterations : 1;
  for (int it = 0; it < block_sweeps; ++it) {
    ldl.block_step(system, rows, lambda, dv);
    pgs_sweep(system, rows, lambda, dv, /*inequality_only=*/true);
  }
}

}  // namespace ldlpgs
