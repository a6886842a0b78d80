#pragma once
// Internal to solver/: ldl-pgs's schur schedule. The LDL block eliminates the equality rows E
// exactly, which leaves an LCP on the inequality rows I alone:
//   w_I = S lambda_I - q, complementary to lambda_I within its bounds,
//   S = H_II + E_I D_I - H_IE M^-1 H_EI,   q = R_I - H_IE M^-1 R_E,   M = H_EE + E_E D_E,
// then lambda_E = M^-1 (R_E - H_EI lambda_I). S is dense on each island (the rows whose bodies
// are joined through rows of E or I; S is zero between islands), one solve with the factor per
// row of I, and projected Gauss-Seidel on it gives every row its effective mass with the joints'
// response included. I's rows are kept island by island, each island's S block apart: 22
// humanoids cost 22 small blocks, not one of their size squared (papers/physics.md, "MJCF
// models: Gymnasium's"). Block Gauss-Seidel's sweep instead moves the bodies of a row as if free and
// the next block step pulls them back: on contacts pressing on jointed bodies it converges
// slowly (papers/physics.md, "Vehicles on the ground").
#include <span>
#include <vector>

#include "ldlpgs/solver/ldl_block.h"
#include "ldlpgs/solver/row_cache.h"

namespace ldlpgs {

class SchurComplement {
 public:
  // lambda: I's warm start on entry, every row's impulse on return; dv = W J^T lambda. At most
  // `sweeps` sweeps, stopping once a sweep changes no row's residual by more than `tolerance`
  // (S_ii |dlambda_i|; 0: once nothing changes). The factor must hold equality rows only
  // (LdlBlock::bounded).
  // Returns whether it stopped on the tolerance.
  bool solve(const System& system, const RowCache& rows, LdlBlock& ldl, int sweeps, double tolerance,
             std::span<double> lambda, std::span<double> dv);

 private:
  void gather_rows(const System& system, std::span<double> lambda);
  void build(const System& system, const RowCache& rows, LdlBlock& ldl);
  double sweep(const System& system, const RowCache& rows, std::span<double> lambda);
  void back_substitute(const System& system, const RowCache& rows, LdlBlock& ldl, std::span<double> lambda,
                       std::span<double> dv);
  void couple_rows(const System& system, const RowCache& rows, const LdlBlock& ldl);
  void solve_equalities(const System& system, LdlBlock& ldl);
  void group_islands(const System& system, const LdlBlock& ldl);
  int find(int column);  // the island's root column (union-find with path halving)
  double* s_column(size_t c) { return s_.data() + s_offset_[row_island_[c]] + (c - island_start(c)) * island_size(c); }
  size_t island_start(size_t c) const { return islands_[row_island_[c]]; }
  size_t island_size(size_t c) const { return islands_[row_island_[c] + 1] - islands_[row_island_[c]]; }

  struct Row {
    int block, row, index;  // block k, its row r, the System row
  };
  std::vector<Row> rows_;       // I: the inequality rows that can carry an impulse, island by island, in block order within one
  std::vector<int> blocks_;     // where each of I's blocks starts in rows_, and rows_.size() last
  std::vector<size_t> islands_;     // where each island starts in rows_, and rows_.size() last
  std::vector<int> row_island_;     // the island of each row of rows_
  std::vector<size_t> s_offset_;    // where each island's block of S starts in s_
  std::vector<int> parent_;         // union-find over the velocity columns (size num_columns)
  std::vector<std::pair<int, int>> order_;  // (island root, block start in rows_) to sort I's blocks by
  std::vector<Row> sorted_;         // rows_ reordered
  std::vector<double> s_;       // S, island by island, each block column-major (size sum of |island|^2)
  std::vector<double> q_, w_;   // q and S lambda_I (size |I|)
  std::vector<double> e_;       // a vector over E's rows in the factor's order
  std::vector<double> x_;       // M^-1 G, column-major (size |E| |I|)
  std::vector<double> v_;       // a velocity change (size 6 num_columns)
  // E's rows on each velocity column (Row::index: the place in the factor), compressed
  std::vector<int> column_start_, fill_;
  std::vector<Row> column_rows_;
  // G = H_EI by columns of I: g_[g_start_[j] .. g_start_[j + 1]) (place in the factor, value)
  struct Entry {
    int at;
    double value;
  };
  std::vector<int> g_start_;
  std::vector<Entry> g_;
};

}  // namespace ldlpgs
