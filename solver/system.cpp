// The System's bookkeeping and its two products with J (the only way the solvers touch J).
#include "ldlpgs/solver/system.h"

#include <cassert>
#include <cmath>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

int System::add_block(int size, int column_a, int column_b) {
  // The public API's check, in every build. One column on both sides is refused: H_0's product
  // for the pair (EqualityMatrix) would keep J_a W J_b^T and drop its mirror J_b W J_a^T (a
  // constraint joins two different bodies; physics/io/scene.cpp refuses the same body twice).
  if (size <= 0) throw ArgumentError("System::add_block: a block of " + std::to_string(size) + " rows");
  for (const int c : {column_a, column_b})
    if (c < -1 || c >= num_columns)
      throw ArgumentError("System::add_block: column " + std::to_string(c) + " outside -1.." +
                          std::to_string(num_columns - 1));
  if (column_a >= 0 && column_a == column_b)
    throw ArgumentError("System::add_block: both sides on column " + std::to_string(column_a) +
                        " (a block joins two different columns, or one and -1)");
  RowBlock b;
  b.size = size;
  b.position = num_rows;
  b.column_a = column_a;
  b.column_b = column_b;
  b.offset = static_cast<int64_t>(jacobian.size());
  blocks.push_back(b);
  num_rows += size;
  jacobian.resize(jacobian.size() + 12 * static_cast<size_t>(size), 0.0);
  lower.resize(num_rows, -kUnbounded);
  upper.resize(num_rows, kUnbounded);
  rhs.resize(num_rows, 0.0);
  compliance.resize(num_rows, 0.0);
  return static_cast<int>(blocks.size()) - 1;
}

void System::set_bounds(int block, double lower_bound, double upper_bound) {
  RowBlock& b = blocks[block];
  for (int r = b.position; r < b.position + b.size; ++r) {
    lower[r] = lower_bound;
    upper[r] = upper_bound;
  }
  b.equality = lower_bound == -kUnbounded && upper_bound == kUnbounded;
}

void System::set_friction(int block, int normal_row, double mu, bool pyramid) {
  if (normal_row < 0 || normal_row >= num_rows)
    throw ArgumentError("System::set_friction: normal row " + std::to_string(normal_row) + " outside 0.." +
                        std::to_string(num_rows - 1));
  if (!(mu >= 0 && std::isfinite(mu))) throw ArgumentError("System::set_friction: friction must be finite and >= 0");
  RowBlock& b = blocks[block];
  b.friction_row = normal_row;
  b.friction = mu;
  b.friction_pyramid = pyramid;
  b.equality = false;
}

void System::truncate(int num_blocks) {
  if (num_blocks < 0 || num_blocks > static_cast<int>(blocks.size()))
    throw ArgumentError("System::truncate: " + std::to_string(num_blocks) + " blocks of " + std::to_string(blocks.size()));
  if (num_blocks == static_cast<int>(blocks.size())) return;
  const RowBlock& first = blocks[num_blocks];
  num_rows = first.position;
  jacobian.resize(first.offset);
  lower.resize(num_rows);
  upper.resize(num_rows);
  rhs.resize(num_rows);
  compliance.resize(num_rows);
  blocks.resize(num_blocks);
}

bool System::same_structure(const System& other) const {
  if (num_columns != other.num_columns || num_rows != other.num_rows || blocks.size() != other.blocks.size())
    return false;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const RowBlock &x = blocks[k], &y = other.blocks[k];
    if (x.size != y.size || x.column_a != y.column_a || x.column_b != y.column_b || x.equality != y.equality)
      return false;
  }
  return true;
}

double row_diagonal(const System& system, int block, int row) {
  const RowBlock& b = system.blocks[block];
  double h = 0;
  const auto add = [&](const double* j, int column) {
    if (column < 0) return;
    const double* w = system.inverse_mass.data() + 36 * static_cast<size_t>(column);
    for (int x = 0; x < 6; ++x)
      for (int y = 0; y < 6; ++y) h += j[x] * w[6 * x + y] * j[y];
  };
  add(system.cell_a(block) + 6 * row, b.column_a);
  add(system.cell_b(block) + 6 * row, b.column_b);
  return h;
}

void multiply_jacobian(const System& system, std::span<const double> x, std::span<double> y) {
  assert(static_cast<int>(x.size()) >= 6 * system.num_columns && static_cast<int>(y.size()) >= system.num_rows);
  for (size_t k = 0; k < system.blocks.size(); ++k) {
    const RowBlock& b = system.blocks[k];
    const double* ja = system.cell_a(static_cast<int>(k));
    const double* jb = system.cell_b(static_cast<int>(k));
    for (int r = 0; r < b.size; ++r) {
      double s = 0;
      if (b.column_a >= 0)
        for (int c = 0; c < 6; ++c) s += ja[6 * r + c] * x[6 * b.column_a + c];
      if (b.column_b >= 0)
        for (int c = 0; c < 6; ++c) s += jb[6 * r + c] * x[6 * b.column_b + c];
      y[b.position + r] = s;
    }
  }
}

void add_velocity_change(const System& system, std::span<const double> lambda, std::span<double> dv) {
  assert(static_cast<int>(lambda.size()) >= system.num_rows && static_cast<int>(dv.size()) >= 6 * system.num_columns);
  for (size_t k = 0; k < system.blocks.size(); ++k) {
    const RowBlock& b = system.blocks[k];
    for (int side = 0; side < 2; ++side) {
      const int col = side == 0 ? b.column_a : b.column_b;
      if (col < 0) continue;
      const double* j = side == 0 ? system.cell_a(static_cast<int>(k)) : system.cell_b(static_cast<int>(k));
      double impulse[6] = {};  // J_col^T lambda
      for (int r = 0; r < b.size; ++r)
        for (int c = 0; c < 6; ++c) impulse[c] += j[6 * r + c] * lambda[b.position + r];
      const double* w = system.inverse_mass.data() + 36 * col;
      for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 6; ++c) dv[6 * col + i] += w[6 * i + c] * impulse[c];
    }
  }
}

}  // namespace ldlpgs
