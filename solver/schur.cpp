// ldl-pgs's schur schedule: the inequality rows' LCP with the equality rows eliminated by the
// LDL block (schur.h), solved by projected Gauss-Seidel on the dense Schur complement.
#include "ldlpgs/solver/schur.h"

#include <algorithm>
#include <cmath>

namespace ldlpgs {

bool SchurComplement::solve(const System& system, const RowCache& rows, LdlBlock& ldl, int sweeps, double tolerance,
                            std::span<double> lambda, std::span<double> dv) {
  gather_rows(system, lambda);
  group_islands(system, ldl);
  build(system, rows, ldl);
  const size_t n = rows_.size();
  w_.assign(n, 0.0);
  for (size_t c = 0; c < n; ++c) {
    const double* column = s_column(c);
    for (size_t j = island_start(c), m = island_size(c), i = 0; i < m; ++i) w_[j + i] += column[i] * lambda[rows_[c].index];
  }
  int it = 0;
  while (it < sweeps && sweep(system, rows, lambda) > tolerance) ++it;
  back_substitute(system, rows, ldl, lambda, dv);
  return it < sweeps;
}

// I: the rows outside the factor, but for friction blocks with no friction (a contact at position
// level), whose impulse is 0.
void SchurComplement::gather_rows(const System& system, std::span<double> lambda) {
  rows_.clear();
  blocks_.clear();
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    if (b.in_factor()) continue;
    if (b.friction_row >= 0 && b.friction == 0) {
      std::fill(lambda.begin() + b.position, lambda.begin() + b.position + b.size, 0.0);
      continue;
    }
    blocks_.push_back(static_cast<int>(rows_.size()));
    for (int r = 0; r < b.size; ++r) rows_.push_back({k, r, b.position + r});
  }
  blocks_.push_back(static_cast<int>(rows_.size()));
}

int SchurComplement::find(int column) {
  while (parent_[column] != column) column = parent_[column] = parent_[parent_[column]];
  return column;
}

// I's rows island by island (an island: the velocity columns joined by E's and I's blocks), in
// block order within one, each island's block of S placed in s_.
void SchurComplement::group_islands(const System& system, const LdlBlock& ldl) {
  parent_.resize(system.num_columns);
  for (int c = 0; c < system.num_columns; ++c) parent_[c] = c;
  const auto join = [&](const RowBlock& b) {
    if (b.column_a >= 0 && b.column_b >= 0) parent_[find(b.column_a)] = find(b.column_b);
  };
  for (int k : ldl.blocks()) join(system.blocks[k]);
  for (size_t bi = 0; bi + 1 < blocks_.size(); ++bi) join(system.blocks[rows_[blocks_[bi]].block]);
  order_.clear();
  for (size_t bi = 0; bi + 1 < blocks_.size(); ++bi) {
    const RowBlock& b = system.blocks[rows_[blocks_[bi]].block];
    order_.push_back({find(b.column_a >= 0 ? b.column_a : b.column_b), blocks_[bi]});
  }
  std::sort(order_.begin(), order_.end());  // (by island, then block order; std::stable_sort would allocate)
  sorted_.clear();
  islands_.clear();
  s_offset_.clear();
  size_t s_size = 0;
  for (size_t o = 0; o < order_.size(); ++o) {
    if (o == 0 || order_[o].first != order_[o - 1].first) islands_.push_back(sorted_.size());
    const int first = order_[o].second;
    const RowBlock& b = system.blocks[rows_[first].block];
    blocks_[o] = static_cast<int>(sorted_.size());
    for (int r = 0; r < b.size; ++r) sorted_.push_back(rows_[first + r]);
  }
  islands_.push_back(sorted_.size());
  rows_.swap(sorted_);
  row_island_.resize(rows_.size());
  for (size_t i = 0; i + 1 < islands_.size(); ++i) {
    s_offset_.push_back(s_size);
    const size_t m = islands_[i + 1] - islands_[i];
    s_size += m * m;
    for (size_t c = islands_[i]; c < islands_[i + 1]; ++c) row_island_[c] = static_cast<int>(i);
  }
  s_.resize(s_size);
}

// e_ = lambda_E = M^-1 (R_E - J_E v_): E's exact answer to its right-hand side and v_.
void SchurComplement::solve_equalities(const System& system, LdlBlock& ldl) {
  int at = 0;
  for (int k : ldl.blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at) e_[at] = system.rhs[b.position + r] - row_times(system, k, r, v_);
  }
  if (at > 0) ldl.solve(e_);
}

// G = H_EI, sparse: row j of I meets only the equality rows on its two bodies. Column j's
// entries (place in the factor's rows, value), each body's part apart.
void SchurComplement::couple_rows(const System& system, const RowCache& rows, const LdlBlock& ldl) {
  // the factor's rows on each velocity column, as compressed lists
  column_start_.assign(static_cast<size_t>(system.num_columns) + 1, 0);
  for (int k : ldl.blocks())
    for (int column : {system.blocks[k].column_a, system.blocks[k].column_b})
      if (column >= 0) column_start_[column + 1] += system.blocks[k].size;
  for (int c = 0; c < system.num_columns; ++c) column_start_[c + 1] += column_start_[c];
  column_rows_.resize(column_start_.back());
  fill_.assign(column_start_.begin(), column_start_.end() - 1);
  int at = 0;
  for (int k : ldl.blocks()) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r, ++at)
      for (int column : {b.column_a, b.column_b})
        if (column >= 0) column_rows_[fill_[column]++] = {k, r, at};
  }
  g_start_.clear();
  g_.clear();
  for (const Row& row : rows_) {
    g_start_.push_back(static_cast<int>(g_.size()));
    const RowBlock& b = system.blocks[row.block];
    const double* wjt = rows.wjt.data() + 12 * static_cast<size_t>(row.index);
    for (int side = 0; side < 2; ++side) {
      const int column = side == 0 ? b.column_a : b.column_b;
      if (column < 0) continue;
      for (int p = column_start_[column]; p < column_start_[column + 1]; ++p) {
        const Row& e = column_rows_[p];
        const RowBlock& eb = system.blocks[e.block];
        const double* j = (eb.column_a == column ? system.cell_a(e.block) : system.cell_b(e.block)) + 6 * e.row;
        g_.push_back({e.index, dot6(j, wjt + 6 * side)});
      }
    }
  }
  g_start_.push_back(static_cast<int>(g_.size()));
}

// S = H_II + E_I D_I - G^T M^-1 G (M^-1 G: one solve with |I| right-hand sides);
// q = R_I - G^T M^-1 R_E.
void SchurComplement::build(const System& system, const RowCache& rows, LdlBlock& ldl) {
  const size_t n = rows_.size();
  size_t equality_rows = 0;
  for (int k : ldl.blocks()) equality_rows += system.blocks[k].size;
  e_.resize(equality_rows);
  v_.assign(kVelocityBlock * static_cast<size_t>(system.num_columns), 0.0);
  q_.resize(n);
  couple_rows(system, rows, ldl);
  const auto g_times = [&](size_t j, const double* x) {  // (G^T x)_j
    double sum = 0;
    for (int p = g_start_[j]; p < g_start_[j + 1]; ++p) sum += g_[p].value * x[g_[p].at];
    return sum;
  };
  x_.assign(equality_rows * n, 0.0);
  for (size_t c = 0; c < n; ++c)
    for (int p = g_start_[c]; p < g_start_[c + 1]; ++p) x_[c * equality_rows + g_[p].at] += g_[p].value;
  if (equality_rows > 0 && n > 0) ldl.solve(x_, static_cast<int>(n));
  for (size_t c = 0; c < n; ++c) {  // (S is zero between islands: only c's own is built)
    const Row& row = rows_[c];
    const double* x = x_.data() + c * equality_rows;
    double* column = s_column(c);
    const size_t first = island_start(c), m = island_size(c);
    add_row_impulse(system, rows, row.block, row.row, 1.0, v_);  // W J_c^T: H_Ic = J_I v_
    for (size_t i = 0; i < m; ++i)
      column[i] = row_times(system, rows_[first + i].block, rows_[first + i].row, v_) - g_times(first + i, x);
    add_row_impulse(system, rows, row.block, row.row, -1.0, v_);
    column[c - first] += system.compliance[row.index] * rows.diag[row.index];
  }
  solve_equalities(system, ldl);  // (v_ is zero again: each column's impulse was taken back)
  for (size_t j = 0; j < n; ++j) q_[j] = system.rhs[rows_[j].index] - g_times(j, e_.data());
}

// One projected Gauss-Seidel sweep on S lambda_I = q (w_ = S lambda_I kept up to date), row by
// row within each row's bounds, a friction disk's two rows together (pgs_friction_disk's step,
// on S's 2x2 block). Returns the largest S_ii |dlambda_i|.
double SchurComplement::sweep(const System& system, const RowCache& rows, std::span<double> lambda) {
  double largest = 0;
  const auto entry = [&](size_t c, size_t j) { return s_column(c)[j - island_start(c)]; };  // S_cj, one island
  const auto move = [&](size_t c, double step) {
    lambda[rows_[c].index] += step;
    const double* column = s_column(c);
    const size_t first = island_start(c), m = island_size(c);
    for (size_t i = 0; i < m; ++i) w_[first + i] += column[i] * step;
    largest = std::max(largest, column[c - first] * std::abs(step));
  };
  const auto row_step = [&](size_t c) {
    const Row& row = rows_[c];
    const RowBlock& b = system.blocks[row.block];
    const double d = entry(c, c) + b.regularization * rows.diag[row.index];
    if (!(d > 0)) return;
    double lo, hi;
    row_bounds(system, b, row.index, lambda, &lo, &hi);
    const double old = lambda[row.index];
    move(c, std::clamp(old + (q_[c] - w_[c]) / d, lo, hi) - old);
  };
  for (size_t bi = 0; bi + 1 < blocks_.size(); ++bi) {
    const size_t first = blocks_[bi], end = blocks_[bi + 1];
    const RowBlock& b = system.blocks[rows_[first].block];
    const double k11 = entry(first, first), k22 = end - first == 2 ? entry(first + 1, first + 1) : 0;
    const double k12 = end - first == 2 ? entry(first, first + 1) : 0;
    const bool disk = b.friction_row >= 0 && !b.friction_pyramid && end - first == 2;
    if (!disk || !disk_solvable(k11, k12, k22)) {
      for (size_t c = first; c < end; ++c) row_step(c);
      continue;
    }
    const double l0 = lambda[rows_[first].index], l1 = lambda[rows_[first + 1].index];
    const double g[2] = {w_[first] - q_[first] - (k11 * l0 + k12 * l1), w_[first + 1] - q_[first + 1] - (k12 * l0 + k22 * l1)};
    double x[2];
    disk_minimizer(k11, k12, k22, g, friction_radius(b, lambda), x);
    move(first, x[0] - l0);
    move(first + 1, x[1] - l1);
  }
  return largest;
}

// lambda_E = M^-1 (R_E - H_EI lambda_I), and dV = W J_I^T lambda_I + W J_E^T lambda_E.
void SchurComplement::back_substitute(const System& system, const RowCache& rows, LdlBlock& ldl,
                                      std::span<double> lambda, std::span<double> dv) {
  std::fill(v_.begin(), v_.end(), 0.0);
  for (const Row& row : rows_) add_row_impulse(system, rows, row.block, row.row, lambda[row.index], v_);
  solve_equalities(system, ldl);
  int at = 0;
  for (int k : ldl.blocks())
    for (int r = 0; r < system.blocks[k].size; ++r, ++at) {
      lambda[system.blocks[k].position + r] = e_[at];
      add_row_impulse(system, rows, k, r, e_[at], v_);
    }
  std::copy(v_.begin(), v_.end(), dv.begin());
}

}  // namespace ldlpgs
