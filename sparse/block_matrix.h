#pragma once
// A symmetric block-sparse matrix: a BlockPattern and dense values for the diagonal blocks and
// the nonzero blocks below the diagonal (the lower triangle), all in one values array. Names as
// in Ceres: each stored block is a Cell {block_id, position}, position the offset of its dense
// values, stored row-major (rows of block_id x columns of the cell's block column).
#include <span>
#include <vector>

#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

struct Cell {
  int block_id;  // block row
  int position;  // offset into values
};

class BlockSparseMatrix {
 public:
  // Copies the entries of a into dense blocks (entries a does not store are zeros).
  BlockSparseMatrix(const SymmetricCsc& a, std::span<const int> block_sizes);

  const BlockPattern& pattern() const { return pattern_; }
  int num_rows() const { return pattern_.num_rows(); }
  // The cells of block column j: the diagonal block first, then blocks i > j ascending.
  std::span<const Cell> column(int j) const {
    return {cells_.data() + col_ptr_[j], static_cast<size_t>(col_ptr_[j + 1] - col_ptr_[j])};
  }
  const std::vector<double>& values() const { return values_; }
  std::vector<double>& values() { return values_; }

  // Every entry of every stored block of the lower triangle, zeros included (the block
  // structure, which can hold more entries than the matrix it was built from).
  SymmetricCsc to_csc() const;

 private:
  BlockPattern pattern_;
  std::vector<int> col_ptr_;    // cells of each block column (size num_blocks+1)
  std::vector<Cell> cells_;     // (size col_ptr_[num_blocks])
  std::vector<double> values_;  // dense blocks, row-major (size: sum of cell areas)
};

}  // namespace ldlpgs
