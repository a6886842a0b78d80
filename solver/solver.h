#pragma once
// solver/: the constraint solvers of one step, on rows (system.h), free of rigid-body types.
//
//   system.h           System: J (block sparse, one block per constraint), W, bounds, R, eps
//   row_cache.cpp      per-step W J^T rows and diag(H): what PGS reads (the talk's impulse form)
//   pgs.cpp            pgs       projected Gauss-Seidel on rows, dV kept up to date, no H built
//   block_gs.cpp       block-gs  Gauss-Seidel over constraint blocks, each solved exactly by its
//                                small dense N_i; single-row inequality blocks projected
//   equality_matrix.h  H = J_0 W J_0^T + eps diag over the equality blocks, fixed pattern
//   ldl_pgs.cpp        ldl-pgs   the talk's hybrid: N-1 PGS iterations, then one block GS
//                                iteration with all equality rows as one block solved by the
//                                sparse block LDL^T (factor/), inequality rows projected one by
//                                one (HybridSchedule: how the iterations are spent); without
//                                inequality rows, one exact solve (what direct does)
//                      direct    equality-only systems solved exactly by the LDL^T: the reference
//
// The symbolic phase (H's pattern, ordering, Symbolic) runs in the constructor, once per
// structure; solve() is the numeric phase, every step, and may be called with any System whose
// factored blocks (the equalities, and bounded blocks marked `factored`) are the same; blocks
// that are not factored (contacts) may come and go between calls. A new set of factored blocks
// runs the symbolic phase again, kept for reuse (SymbolicStats). Lambda is warm-started: solve()
// starts from the lambda it is given. resolve() solves again with the last solve's matrix (its
// factor and caches) and a new right-hand side: the position projection of physics/step.h.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/solver/system.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

enum class SolverKind { pgs, block_gs, ldl_pgs, direct };
const char* to_string(SolverKind kind);
bool solver_kind_from_string(std::string_view name, SolverKind* kind);  // false: unknown name
std::span<const char* const> solver_names();

// How ldl-pgs spends its iterations on a system with inequality rows (N = iterations; the
// choice is measured in papers/physics.md, "Hybrid schedules"):
//   talk            N-1 PGS sweeps over all rows, then one block GS sweep (equality block by
//                   the LDL^T, inequality rows projected): the talk's N-1 + 1
//   inequality-pgs  N-1 PGS sweeps over the inequality rows only, then one block GS sweep: the
//                   equality rows' sweeps are wasted work when the block solves them exactly
//   block-gs        N block GS sweeps, each one LDL^T solve reusing the factor
//   schur           the inequality rows' LCP with the equality rows eliminated by the LDL^T
//                   (their dense Schur complement, one solve per inequality row), then N PGS
//                   sweeps on it: each row sees its effective mass through the joints (block-gs
//                   where the factor holds inequality rows)
enum class HybridSchedule { talk, inequality_pgs, block_gs, schur };
const char* to_string(HybridSchedule schedule);
bool hybrid_schedule_from_string(std::string_view name, HybridSchedule* schedule);  // false: unknown
std::span<const char* const> hybrid_schedule_names();

struct SolverOptions {
  SolverKind kind = SolverKind::ldl_pgs;
  // Iterations over all rows: pgs and block-gs do this many sweeps; ldl-pgs does iterations - 1
  // PGS sweeps and one block GS sweep (the talk's N-1 + 1); direct ignores it.
  int iterations = 10;
  std::string ordering = "best";  // elimination ordering of H's blocks (ordering/)
  HybridSchedule schedule = HybridSchedule::talk;  // ldl-pgs with inequality rows
};

struct SolveResult {
  FactorInfo factor;     // ldl-pgs, direct: the LDL^T's status (ok when not factored)
  // ldl-pgs's block-gs and schur schedules given a tolerance: whether they stopped on it, not at
  // their iteration cap
  bool converged = true;
  bool ok() const { return factor.usable(); }
};

// How often the LDL^T's symbolic phase ran: once in the constructor, and again whenever the set
// of factored blocks (RowBlock::in_factor) changes to one not seen among the last 16.
struct SymbolicStats {
  int64_t analyses = 0;
  double analysis_us = 0;  // their time, in all
};

class SolverState;  // the per-structure workspace and symbolic phase

class Solver {
 public:
  // Symbolic phase for the structure of `system` (only its blocks, columns and bounds are read).
  // direct on a system with inequality blocks is a programmer error (callers check first).
  Solver(const System& system, const SolverOptions& options);
  ~Solver();
  Solver(Solver&&) noexcept;
  Solver& operator=(Solver&&) noexcept;

  // Numeric phase. lambda (size num_rows): warm start in, impulses out. dv (size 6 num_columns):
  // out, W J^T lambda.
  // `schedule` overrides options()' for this call (the physics step's contacts take their own).
  SolveResult solve(const System& system, std::span<double> lambda, std::span<double> dv,
                    std::optional<HybridSchedule> schedule = std::nullopt);
  // solve()'s first half: the numeric factorization (and the row and block caches) for `system`,
  // whose status it returns; resolve() then iterates on it.
  SolveResult factorize(const System& system);
  // The same iterations on the matrix of the last solve() or factorize(): `system` must hold the J, W and
  // compliance that solve() was given (its rhs and lambda may differ); nothing is refactored.
  // A failed last factorization is returned again (lambda and dv are then left as pgs leaves them).
  // iterations > 0 and schedule override options()' for this call (the position level needs more
  // sweeps on inequality rows than the velocity level: papers/physics.md). ldl-pgs's block-gs
  // schedule stops early once an iteration changes no entry of dv by more than `tolerance` (0:
  // it runs every iteration).
  SolveResult resolve(const System& system, std::span<double> lambda, std::span<double> dv, int iterations = 0,
                      std::optional<HybridSchedule> schedule = std::nullopt, double tolerance = 0);

  const SolverOptions& options() const { return options_; }
  // The LDL^T's symbolic phase (ldl-pgs, direct), or null.
  const class Symbolic* symbolic() const;
  const SymbolicStats& symbolic_stats() const;

 private:
  SolverOptions options_;
  std::unique_ptr<SolverState> state_;
};

// The velocity residual, max over rows (m/s or rad/s): |g_i|, g_i = J_i dV + eps_i H_ii lambda_i
// - R_i (the compliant system's own equation), on rows that must meet their target (unbounded, or
// lambda strictly inside its bounds); on a row whose lambda sits at a bound, only the side the
// bound forbids (lower: g_i < 0, upper: g_i > 0).
double velocity_residual(const System& system, std::span<const double> lambda, std::span<const double> dv);

// H_0 + diag(eps_i (H_0)_ii), H_0 = J_0 W J_0^T over the equality blocks: the matrix ldl-pgs and direct
// factor, lower triangle, and its block sizes (the equality blocks' rows, in order).
SymmetricCsc equality_matrix(const System& system, std::vector<int>* block_sizes);

}  // namespace ldlpgs
