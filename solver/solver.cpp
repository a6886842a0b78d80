// The solvers chosen by name, their per-structure state, and the velocity residual.
#include "ldlpgs/solver/solver.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "ldlpgs/solver/block_gs.h"
#include "ldlpgs/solver/ldl_block.h"

namespace ldlpgs {

namespace {
constexpr std::array<const char*, 4> kNames = {"pgs", "block-gs", "ldl-pgs", "direct"};
constexpr std::array<const char*, 3> kSchedules = {"talk", "inequality-pgs", "block-gs"};

// An enum spelled by its index in `names`; false if `name` is none of them.
template <class Enum, size_t N>
bool from_name(const std::array<const char*, N>& names, std::string_view name, Enum* out) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return false;
  *out = static_cast<Enum>(it - names.begin());
  return true;
}
}  // namespace

const char* to_string(SolverKind kind) { return kNames[static_cast<int>(kind)]; }
bool solver_kind_from_string(std::string_view name, SolverKind* kind) { return from_name(kNames, name, kind); }
std::span<const char* const> solver_names() { return kNames; }

const char* to_string(HybridSchedule schedule) { return kSchedules[static_cast<int>(schedule)]; }
bool hybrid_schedule_from_string(std::string_view name, HybridSchedule* schedule) {
  return from_name(kSchedules, name, schedule);
}
std::span<const char* const> hybrid_schedule_names() { return kSchedules; }

class SolverState {
 public:
  RowCache rows;
  BlockCache blocks;
  std::unique_ptr<LdlBlock> ldl;  // ldl-pgs, direct
  // ldl-pgs and direct on a system without inequality rows: one exact solve and no sweeps (the talk's N-1 PGS sweeps would only move lambda the exact block then replaces)
  bool exact = false;
  FactorInfo factor;  // the last solve's factorization (ldl-pgs, direct)
};

Solver::Solver(const System& system, const SolverOptions& options)
    : options_(options), state_(std::make_unique<SolverState>()) {
  assert(options.iterations >= 1);
  if (options.kind == SolverKind::ldl_pgs || options.kind == SolverKind::direct) {
    state_->exact = std::all_of(system.blocks.begin(), system.blocks.end(), [](const RowBlock& b) { return b.equality; });
    assert(options.kind != SolverKind::direct || state_->exact);
    state_->ldl = std::make_unique<LdlBlock>(system, options.ordering);
  }
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

const Symbolic* Solver::symbolic() const { return state_->ldl ? &state_->ldl->symbolic() : nullptr; }

namespace {

// lambda clamped into its bounds and dV = W J^T lambda: the warm start of the iterative solvers.
void warm_start(const System& system, std::span<double> lambda, std::span<double> dv) {
  for (int i = 0; i < system.num_rows; ++i) lambda[i] = std::clamp(lambda[i], system.lower[i], system.upper[i]);
  std::fill(dv.begin(), dv.end(), 0.0);
  add_velocity_change(system, lambda, dv);
}

}  // namespace

SolveResult Solver::solve(const System& system, std::span<double> lambda, std::span<double> dv) {
  SolverState& s = *state_;
  s.rows.update(system);
  if (s.ldl) s.factor = s.ldl->factorize(system, s.rows);
  if (options_.kind == SolverKind::block_gs) s.blocks.update(system);
  return resolve(system, lambda, dv);
}

SolveResult Solver::resolve(const System& system, std::span<double> lambda, std::span<double> dv, int iterations,
                            std::optional<HybridSchedule> schedule) {
  // Caller errors that would corrupt memory are checked in every build.
  if (static_cast<int>(lambda.size()) != system.num_rows || static_cast<int>(dv.size()) != 6 * system.num_columns)
    throw std::invalid_argument("Solver: lambda must have num_rows entries and dv 6 num_columns");
  SolverState& s = *state_;
  const int n = iterations > 0 ? iterations : options_.iterations;
  SolveResult result;
  if (s.exact) {
    result.factor = s.factor;
    if (result.ok()) s.ldl->exact_solve(system, s.rows, lambda, dv);
    return result;
  }
  warm_start(system, lambda, dv);
  switch (options_.kind) {
    case SolverKind::pgs:
      for (int it = 0; it < n; ++it) pgs_sweep(system, s.rows, lambda, dv);
      break;
    case SolverKind::block_gs:
      for (int it = 0; it < n; ++it) block_gs_sweep(system, s.rows, s.blocks, lambda, dv);
      break;
    case SolverKind::ldl_pgs:
      result.factor = s.factor;
      ldl_pgs_iterate(system, n, schedule.value_or(options_.schedule), s.rows, *s.ldl, s.factor.usable(), lambda, dv);
      break;
    case SolverKind::direct:  // exact (the constructor checked)
      break;
  }
  return result;
}

double velocity_residual(const System& system, std::span<const double> lambda, std::span<const double> dv) {
  double worst = 0;
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r) {
      const int i = b.position + r;
      const double g = row_times(system, k, r, dv) - system.rhs[i];  // J_i dV - R_i
      // velocity units throughout: an unbounded or strictly interior row must meet its target;
      // a row at its lower bound may only exceed it (g >= 0), at its upper bound only fall short.
      double v = std::abs(g);
      if (lambda[i] <= system.lower[i]) v = std::max(0.0, -g);
      else if (lambda[i] >= system.upper[i]) v = std::max(0.0, g);
      worst = std::max(worst, v);
    }
  }
  return worst;
}

SymmetricCsc equality_matrix(const System& system, std::vector<int>* block_sizes) {
  EqualityMatrix h(system);
  h.assemble(system);
  if (block_sizes) *block_sizes = h.blocks().block_sizes();
  return h.matrix();
}

}  // namespace ldlpgs
