// ldl-pgs, the talk's hybrid: N-1 PGS sweeps over all rows, then one block Gauss-Seidel sweep
// in which every equality row belongs to one block (index 0) solved exactly by the sparse
// block LDL^T, and each inequality row is solved and projected on its own. PGS brings the
// inequality impulses near their active set; the exact block then removes the equality error
// that PGS leaves on long chains, heavy loads and loops. Inequality rows marked `factored`
// (contacts that keep pushing) join the exact block, held at their bounds by block pivoting.
#include "ldlpgs/solver/ldl_block.h"

#include <algorithm>
#include <cmath>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/solver/schur.h"

namespace ldlpgs {

LdlBlock::LdlBlock(const System& structure, const std::string& ordering) : h_(structure) {
  const Ordering o = compute_ordering(find_ordering(ordering), h_.blocks(), h_.matrix());
  symbolic_ = std::make_unique<Symbolic>(Symbolic::analyze(h_.matrix(), h_.blocks(), o));
  numeric_ = std::make_unique<Numeric>(*symbolic_);
  work_.resize(h_.num_rows());
  h_.remap(symbolic_->load_map(), &packed_index_, &packed_diagonal_);
  int at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = structure.blocks[k];
    columns_.push_back(b.column_a);
    columns_.push_back(b.column_b);
    for (int r = 0; r < b.size; ++r, ++at)
      if (!b.equality) bounded_.push_back({at, b.position + r});
  }
  if (!bounded_.empty()) {
    unconstrained_.resize(work_.size());
    inverse_columns_.resize(static_cast<size_t>(kMaxHeldRows) * work_.size());
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
  if (!bounded_.empty()) hold_bounded_rows(system, lambda);
  at = 0;
  for (int k : h_.system_blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at) {
      const int i = b.position + r;
      double step = work_[at];
      // (within its bounds already, but for rounding, or the active set's iteration limit)
      if (!b.equality) step = std::clamp(lambda[i] + step, system.lower[i], system.upper[i]) - lambda[i];
      lambda[i] += step;
      add_row_impulse(system, rows, k, r, step, dv);
    }
  }
}

// work_ holds the unconstrained step dlambda0 = M^-1 w (M the factored matrix, w the block's
// residual). The block's bounded rows must end within their bounds with complementarity: the rows
// held at a bound take the step that puts them there and the rest of the block its exact response,
//   dlambda = dlambda0 - M^-1 E_C mu,  (M^-1)_CC mu = dlambda0_C - (bound_C - lambda_C),
// and a held row whose multiplier pulls the wrong way (mu_c > 0 at a lower bound: it would leave
// the bound by itself) is let go. An active-set iteration (block pivoting) on the few rows at a
// bound, one column of M^-1 (one more solve with the same factor) for each row held.
void LdlBlock::hold_bounded_rows(const System& system, std::span<const double> lambda) {
  const size_t n = work_.size();
  std::copy(work_.begin(), work_.end(), unconstrained_.begin());
  int held = 0;  // held_[0..held): indices into bounded_, their M^-1 columns in inverse_columns_
  for (int round = 0; round < 2 * kMaxHeldRows; ++round) {
    // the step for the held set
    HeldVector mu(held);
    if (held > 0) {
      HeldMatrix m(held, held);
      for (int p = 0; p < held; ++p) {
        const Bounded& row = bounded_[held_[p].index];
        mu(p) = unconstrained_[row.at] - (held_[p].bound - lambda[row.system_row]);
        for (int q = 0; q < held; ++q) m(p, q) = inverse_columns_[q * n + row.at];
      }
      mu = m.ldlt().solve(mu).eval();
    }
    std::copy(unconstrained_.begin(), unconstrained_.end(), work_.begin());
    for (int q = 0; q < held; ++q)
      for (size_t x = 0; x < n; ++x) work_[x] -= inverse_columns_[q * n + x] * mu(q);
    // the held row pulled most the wrong way is let go, and the step recomputed
    int release = -1;
    double worst = 0;
    for (int p = 0; p < held; ++p) {
      const double wrong = held_[p].lower ? mu(p) : -mu(p);
      if (wrong > worst) {
        worst = wrong;
        release = p;
      }
    }
    if (release >= 0) {
      --held;
      held_[release] = held_[held];
      std::copy(inverse_columns_.begin() + held * n, inverse_columns_.begin() + (held + 1) * n,
                inverse_columns_.begin() + release * n);
      continue;
    }
    // the rows the step takes out of their bounds are held there
    bool added = false;
    for (int t = 0; t < static_cast<int>(bounded_.size()) && held < kMaxHeldRows; ++t) {
      const int i = bounded_[t].system_row;
      const double value = lambda[i] + work_[bounded_[t].at];
      if (value >= system.lower[i] && value <= system.upper[i]) continue;
      bool already = false;
      for (int p = 0; p < held; ++p) already = already || held_[p].index == t;
      if (already) continue;
      double* column = inverse_columns_.data() + held * n;
      std::fill(column, column + n, 0.0);
      column[bounded_[t].at] = 1;
      numeric_->solve({column, n});
      const bool lower = value < system.lower[i];
      held_[held++] = {t, lower, lower ? system.lower[i] : system.upper[i]};
      added = true;
    }
    if (!added) return;
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

namespace {

double largest_change(std::span<const double> before, std::span<const double> after) {
  double change = 0;
  for (size_t i = 0; i < after.size(); ++i) change = std::max(change, std::abs(after[i] - before[i]));
  return change;
}

}  // namespace

bool ldl_pgs_iterate(const System& system, const LdlPgsIterations& iterations, const RowCache& rows, LdlBlock& ldl,
                     bool factored, std::span<double> lambda, std::span<double> dv) {
  if (iterations.schedule == HybridSchedule::schur && factored && !ldl.bounded()) {
    return iterations.schur->solve(system, rows, ldl, iterations.count, iterations.tolerance, lambda, dv);
  }
  const bool block_gs = iterations.schedule == HybridSchedule::block_gs || iterations.schedule == HybridSchedule::schur;
  const int sweeps = block_gs ? 0 : iterations.count - 1;
  const bool inequality_only = iterations.schedule == HybridSchedule::inequality_pgs;
  for (int it = 0; it < sweeps; ++it) pgs_sweep(system, rows, lambda, dv, inequality_only);
  if (!factored) return true;  // lambda keeps the PGS impulses; the caller reports the status
  const int block_sweeps = block_gs ? iterations.count : 1;
  const bool stop_early = block_gs && iterations.tolerance > 0;
  for (int it = 0; it < block_sweeps; ++it) {
    if (stop_early) std::copy(dv.begin(), dv.end(), iterations.dv_before.begin());
    ldl.block_step(system, rows, lambda, dv);
    pgs_sweep(system, rows, lambda, dv, /*inequality_only=*/true);
    if (stop_early && largest_change(iterations.dv_before, dv) <= iterations.tolerance) return true;
  }
  return !stop_early;
}

}  // namespace ldlpgs
