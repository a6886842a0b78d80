#pragma once
// Symmetric block sparsity: a partition of the rows into blocks and the block graph
// (nodes = blocks, edges = nonzero off-diagonal blocks). For a mechanism this is the constraint
// graph: blocks are constraints with their row counts, edges are bodies they share (the talk).
#include <cstdint>
#include <span>
#include <vector>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// Block names as Ceres has them: a block of `size` rows starting at row `position`.
struct Block {
  int size;
  int position;
};

class BlockPattern {
 public:
  BlockPattern() = default;
  // block_sizes: one positive size per block, in row order; graph: the block adjacency.
  BlockPattern(std::span<const int> block_sizes, Graph graph);

  // The blocks of a scalar matrix under a partition: blocks I != J are adjacent when any entry
  // (i, j), i in I, j in J, is stored. Asserts that the sizes sum to a.n.
  static BlockPattern from_scalar(const SymmetricCsc& a, std::span<const int> block_sizes);
  // One block per row (the scalar graph), for orderings that work row by row.
  static BlockPattern unit(const SymmetricCsc& a);

  int num_blocks() const { return static_cast<int>(blocks_.size()); }
  int num_rows() const { return num_rows_; }
  const std::vector<Block>& blocks() const { return blocks_; }
  const Block& block(int b) const { return blocks_[b]; }
  const Graph& graph() const { return graph_; }
  std::span<const int> neighbors(int b) const { return graph_.neighbors(b); }
  int64_t num_edges() const { return graph_.num_edges(); }
  std::vector<int> block_sizes() const;
  // block_of_row[r] = the block holding row r (size num_rows)
  std::vector<int> block_of_row() const;

  // Scalar matrix with every block dense, values as CHOLMOD gives a pattern matrix
  // (off-diagonal -1, diagonal 1 + degree): symmetric positive definite, diagonally dominant.
  SymmetricCsc expand() const;

 private:
  std::vector<Block> blocks_;  // (size num_blocks)
  Graph graph_;                // block adjacency (graph_.n = num_blocks)
  int num_rows_ = 0;
};

}  // namespace ldlpgs
