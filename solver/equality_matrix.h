#pragma once
// Internal to solver/: H_0 = J_0 W J_0^T over the equality blocks (the talk's block 0 of
// LDL-PGS), in a fixed scalar pattern so that one symbolic phase serves every step.
#include <cstdint>
#include <span>
#include <vector>

#include "ldlpgs/solver/row_cache.h"
#include "ldlpgs/solver/system.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

class EqualityMatrix {
 public:
  EqualityMatrix() = default;
  // The pattern: every pair of equality blocks sharing a column is a dense block of H_0.
  explicit EqualityMatrix(const System& structure);

  // H_0 + diag(eps_i (H_0)_ii) for this step, J_0 W J_0^T and the rows' compliance, into matrix().
  void assemble(const System& system);
  // The same straight into another layout (the factor's packed blocks: no intermediate matrix):
  // entry e of the products is added at target[index[e]] (index: of matrix()'s values remapped
  // by remap()), with the rows' W J^T from `rows` (updated for `system`). target starts zeroed.
  void assemble(const System& system, const RowCache& rows, std::span<double> target, std::span<const int64_t> index,
                std::span<const int64_t> diagonal) const;
  // index_ and diagonal_ through a map from matrix()'s value positions to another layout
  // (Symbolic::load_map): the arguments of the assemble above.
  void remap(std::span<const int32_t> map, std::vector<int64_t>* index, std::vector<int64_t>* diagonal) const;

  const SymmetricCsc& matrix() const { return h_; }
  const BlockPattern& blocks() const { return blocks_; }
  int num_rows() const { return h_.n; }
  // block_of[e] = the System block of equality block e (size num equality blocks)
  std::span<const int> system_blocks() const { return system_block_; }

 private:
  // One product J_x W_c J_y^T of two equality blocks x <= y (in system order) sharing column c.
  struct Product {
    int x, y;           // System blocks
    int side_x, side_y; // 0: the block's column a, 1: column b
    int column;
    int64_t index;      // first of size_x * size_y entries in index_
  };
  SymmetricCsc h_;
  BlockPattern blocks_;
  std::vector<int> system_block_;  // (size equality blocks)
  std::vector<Product> products_;  // (size number of products)
  std::vector<int64_t> index_;     // position in h_.values of each product entry (rx, ry), row-major; -1: upper half
  std::vector<int64_t> diagonal_;  // position in h_.values of each diagonal entry (size h_.n)
  std::vector<int> system_row_;    // the System row of each row of H_0 (size h_.n)
  std::vector<int> system_block_of_row_;  // and its System block (size h_.n)
};

}  // namespace ldlpgs
