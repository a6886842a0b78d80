// The solvers chosen by name, their per-structure state, and the velocity residual.
#include "ldlpgs/solver/solver.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "ldlpgs/solver/block_gs.h"
#include "ldlpgs/solver/ldl_block.h"
#include "ldlpgs/solver/schur.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {
constexpr std::array<const char*, 4> kNames = {"pgs", "block-gs", "ldl-pgs", "direct"};
constexpr std::array<const char*, 4> kSchedules = {"talk", "inequality-pgs", "block-gs", "schur"};

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
  // ldl-pgs, direct: one LDL block per set of factored blocks seen, most recently used first, at
  // most kMaxSymbolics (contacts joining the factor change the set; a resting scene repeats it).
  static constexpr size_t kMaxSymbolics = 16;
  std::vector<std::unique_ptr<LdlBlock>> ldl;
  std::string ordering;
  bool factors = false;  // ldl-pgs, direct
  // A system without inequality rows: one exact solve and no sweeps (the talk's N-1 PGS sweeps
  // would only move lambda the exact block then replaces)
  bool exact = false;
  FactorInfo factor;  // the last solve's factorization (ldl-pgs, direct)
  SymbolicStats stats;
  std::vector<double> dv_before;  // dV before a block Gauss-Seidel iteration (size 6 num_columns)
  SchurComplement schur;          // the schur schedule's workspace

  // The LDL block serving `system`'s factored blocks, analysed now if no cached one does.
  LdlBlock& ldl_for(const System& system) {
    for (size_t i = 0; i < ldl.size(); ++i)
      if (ldl[i]->serves(system)) {
        std::rotate(ldl.begin(), ldl.begin() + static_cast<std::ptrdiff_t>(i), ldl.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        return *ldl.front();
      }
    const auto start = std::chrono::steady_clock::now();
    if (ldl.size() == kMaxSymbolics) ldl.pop_back();
    ldl.insert(ldl.begin(), std::make_unique<LdlBlock>(system, ordering));
    ++stats.analyses;
    stats.analysis_us += std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    return *ldl.front();
  }
};

Solver::Solver(const System& system, const SolverOptions& options)
    : options_(options), state_(std::make_unique<SolverState>()) {
  assert(options.iterations >= 1);
  state_->dv_before.resize(6 * static_cast<size_t>(system.num_columns));
  if (options.kind == SolverKind::ldl_pgs || options.kind == SolverKind::direct) {
    state_->factors = true;
    state_->ordering = options.ordering;
    assert(options.kind != SolverKind::direct ||
           std::all_of(system.blocks.begin(), system.blocks.end(), [](const RowBlock& b) { return b.equality; }));
    state_->ldl_for(system);
  }
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

const Symbolic* Solver::symbolic() const { return state_->factors ? &state_->ldl.front()->symbolic() : nullptr; }
const SymbolicStats& Solver::symbolic_stats() const { return state_->stats; }

namespace {

// lambda clamped into its bounds and dV = W J^T lambda, from the rows' W J^T (a third of
// add_velocity_change's products): the warm start of the iterative solvers.
void warm_start(const System& system, const RowCache& rows, std::span<double> lambda, std::span<double> dv) {
  project_onto_bounds(system, lambda);
  std::fill(dv.begin(), dv.end(), 0.0);
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k)
    for (int r = 0; r < system.blocks[k].size; ++r) {
      const double impulse = lambda[system.blocks[k].position + r];
      if (impulse != 0) add_row_impulse(system, rows, k, r, impulse, dv);
    }
}

}  // namespace

SolveResult Solver::factorize(const System& system) {
  SolverState& s = *state_;
  s.exact = std::all_of(system.blocks.begin(), system.blocks.end(), [](const RowBlock& b) { return b.equality; });
  if (options_.kind == SolverKind::direct && !s.exact)
    throw ArgumentError("Solver: direct takes equality rows only (an inequality block was given)");
  s.rows.update(system);
  if (s.factors) s.factor = s.ldl_for(system).factorize(system, s.rows);
  if (options_.kind == SolverKind::block_gs) s.blocks.update(system);
  SolveResult result;
  if (s.factors) result.factor = s.factor;
  return result;
}

SolveResult Solver::solve(const System& system, std::span<double> lambda, std::span<double> dv,
                          std::optional<HybridSchedule> schedule) {
  factorize(system);
  return resolve(system, lambda, dv, 0, schedule);
}

SolveResult Solver::resolve(const System& system, std::span<double> lambda, std::span<double> dv, int iterations,
                            std::optional<HybridSchedule> schedule, double tolerance) {
  // Caller errors that would corrupt memory are checked in every build.
  if (static_cast<int>(lambda.size()) != system.num_rows || static_cast<int>(dv.size()) != 6 * system.num_columns)
    throw std::invalid_argument("Solver: lambda must have num_rows entries and dv 6 num_columns");
  SolverState& s = *state_;
  const int n = iterations > 0 ? iterations : options_.iterations;
  SolveResult result;
  if (s.exact && s.factors) {
    result.factor = s.factor;
    if (result.ok()) s.ldl.front()->exact_solve(system, s.rows, lambda, dv);
    return result;
  }
  warm_start(system, s.rows, lambda, dv);
  s.rows.lanes.load(system);
  switch (options_.kind) {
    case SolverKind::pgs:
      for (int it = 0; it < n; ++it) pgs_sweep(system, s.rows, lambda, dv);
      break;
    case SolverKind::block_gs:
      for (int it = 0; it < n; ++it) block_gs_sweep(system, s.rows, s.blocks, lambda, dv);
      break;
    case SolverKind::ldl_pgs: {
      result.factor = s.factor;
      const LdlPgsIterations iterations{n, schedule.value_or(options_.schedule), tolerance, s.dv_before, &s.schur};
      result.converged = ldl_pgs_iterate(system, iterations, s.rows, *s.ldl.front(), s.factor.usable(), lambda, dv);
      break;
    }
    case SolverKind::direct:  // exact (checked in factorize)
      break;
  }
  return result;
}

namespace {
// A friction disk's residual: inside the disk the rows must meet their targets (|g|); on its rim
// the impulse must oppose the residual g = J dV - R (maximal dissipation): g's part across the
// impulse, and g's part along it when positive.
double friction_disk_residual(const System& system, int k, std::span<const double> lambda, std::span<const double> dv) {
  const RowBlock& b = system.blocks[k];
  std::array<double, 6> g{};
  double g_sq = 0, l_sq = 0, along = 0;
  for (int r = 0; r < b.size; ++r) {
    const int i = b.position + r;
    g[r] = row_times(system, k, r, dv) - system.rhs[i];
    g_sq += g[r] * g[r];
    l_sq += lambda[i] * lambda[i];
    along += g[r] * lambda[i];
  }
  const double radius = friction_radius(b, lambda);
  if (radius == 0) return 0;
  if (std::sqrt(l_sq) < radius * (1 - 1e-12)) return std::sqrt(g_sq);
  const double along_unit = along / std::sqrt(l_sq);  // g . lambda / |lambda|
  return std::sqrt(std::max(0.0, g_sq - along_unit * along_unit)) + std::max(0.0, along_unit);
}
}  // namespace

double velocity_residual(const System& system, std::span<const double> lambda, std::span<const double> dv) {
  double worst = 0;
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    if (b.friction_row >= 0 && !b.friction_pyramid) {
      worst = std::max(worst, friction_disk_residual(system, k, lambda, dv));
      continue;
    }
    for (int r = 0; r < b.size; ++r) {
      const int i = b.position + r;
      // J_i dV + eps_i H_ii lambda_i - R_i (a compliant row meets its target less its give)
      double g = row_times(system, k, r, dv) - system.rhs[i];
      if (system.compliance[i] != 0) g += system.compliance[i] * row_diagonal(system, k, r) * lambda[i];
      // velocity units throughout: an unbounded or strictly interior row must meet its target;
      // a row at its lower bound may only exceed it (g >= 0), at its upper bound only fall short.
      double lo, hi;
      row_bounds(system, b, i, lambda, &lo, &hi);
      double v = std::abs(g);
      if (lambda[i] <= lo) v = std::max(0.0, -g);
      else if (lambda[i] >= hi) v = std::max(0.0, g);
      if (lo == hi) v = 0;  // a row with no room (friction at a zero normal impulse)
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
