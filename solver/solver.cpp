// The solvers chosen by name, their per-structure state, and the velocity residual.
#include "solver/solver.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <string_view>

#include "solver/block_gs.h"
#include "solver/ldl_block.h"

namespace ldlpgs {

namespace {
constexpr std::array<const char*, 4> kNames = {"pgs", "block-gs", "ldl-pgs", "direct"};
}  // namespace

const char* to_string(SolverKind kind) { return kNames[static_cast<int>(kind)]; }

bool solver_kind_from_string(std::string_view name, SolverKind* kind) {
  for (size_t i = 0; i < kNames.size(); ++i)
    if (name == kNames[i]) {
      *kind = static_cast<SolverKind>(i);
      return true;
    }
  return false;
}

std::span<const char* const> solver_names() { return kNames; }

class SolverState {
 public:
  RowCache rows;
  BlockCache blocks;
  std::unique_ptr<LdlBlock> ldl;  // ldl-pgs, direct
};

Solver::Solver(const System& system, const SolverOptions& options)
    : options_(options), state_(std::make_unique<SolverState>()) {
  assert(options.iterations >= 1);
  if (options.kind == SolverKind::ldl_pgs || options.kind == SolverKind::direct) {
    assert(options.kind != SolverKind::direct ||
           std::all_of(system.blocks.begin(), system.blocks.end(), [](const RowBlock& b) { return b.equality; }));
    state_->ldl = std::make_unique<LdlBlock>(system, options.ordering);
  }
}

Solver::~Solver() = default;
Solver::Solver(Solver&&) noexcept = default;
Solver& Solver::operator=(Solver&&) noexcept = default;

const Symbolic* Solver::symbolic() const { return state_->ldl ? &state_->ldl->symbolic() : nullptr; }

SolveResult Solver::solve(const System& system, std::span<double> lambda, std::span<double> dv) {
  assert(static_cast<int>(lambda.size()) == system.num_rows && static_cast<int>(dv.size()) == 6 * system.num_columns);
  SolverState& s = *state_;
  s.rows.update(system);
  if (options_.kind != SolverKind::direct) {  // warm start: dV = W J^T lambda
    for (int i = 0; i < system.num_rows; ++i) lambda[i] = std::clamp(lambda[i], system.lower[i], system.upper[i]);
    std::fill(dv.begin(), dv.end(), 0.0);
    add_velocity_change(system, lambda, dv);
  }
  switch (options_.kind) {
    case SolverKind::pgs:
      for (int it = 0; it < options_.iterations; ++it) pgs_sweep(system, s.rows, lambda, dv);
      return {};
    case SolverKind::block_gs:
      s.blocks.update(system);
      for (int it = 0; it < options_.iterations; ++it) block_gs_sweep(system, s.rows, s.blocks, lambda, dv);
      return {};
    case SolverKind::ldl_pgs:
      return solve_ldl_pgs(system, options_.iterations, s.rows, *s.ldl, lambda, dv);
    case SolverKind::direct:
      return solve_direct(system, s.rows, *s.ldl, lambda, dv);
  }
  return {};
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
