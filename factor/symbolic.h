#pragma once
// The symbolic phase of the block LDL^T (the talk: once per mechanism): from a block pattern and a
// block pivot sequence, the block structure of L with its fill blocks, the packed memory layout
// of all node and edge blocks, the reduction-scattering indices (RSI, one per pair of blocks) and the map that loads a
// matrix's stored entries into the layout. Immutable; any matrix with the same pattern reuses it.
//
// Layout, as the talk packs it: blocks in column-major order (pivot k's node block N_k, then the
// edge blocks of its column, fill included, in pivot order), the elements of each block
// row-major. The edge blocks of a column are then one contiguous h x d row-major matrix E_{*,k}:
// the reduction reads rows of E and of L as unit-stride vectors of length d, and a column is
// replaced by L with one copy.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

class Symbolic {
 public:
  Symbolic() = default;
  // pattern: the stored entries (values ignored) of the matrices to factor; blocks: its partition
  // into blocks (every stored entry must lie in a block of `blocks`'s graph or on its diagonal);
  // pivots: the block pivot sequence (pivots[k] = block eliminated k-th, a permutation). All
  // three are checked (ArgumentError naming the fault), in every build.
  static Symbolic analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, std::span<const int> pivots);
  // The same for a computed ordering: a scalar ordering (amd-scalar, metis-scalar) factors with
  // 1 x 1 blocks.
  static Symbolic analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, const Ordering& ordering);

  // The ordering that gave the pivots (Ordering::chosen: best's winner); empty from bare pivots.
  const std::string& ordering() const { return ordering_; }
  int num_rows() const { return n_; }
  int num_pivots() const { return static_cast<int>(size_.size()); }
  int64_t num_values() const { return node_offset_.empty() ? 0 : node_offset_.back(); }
  int64_t num_edges() const { return static_cast<int64_t>(edge_pivot_.size()); }
  int64_t num_fill_edges() const { return num_fill_; }
  // Scalar entries of L, diagonal included, counting every block as dense (CHOLMOD's lnz when the
  // blocks are dense), and the flops of the factorization: per pivot of size d and height h,
  // sum over its d columns of (column count)^2 = d(d+1)(2d+1)/6 + h d(d+1) + d h^2 (CHOLMOD's fl).
  int64_t nnz_l() const { return nnz_l_; }
  double flops() const { return flops_; }
  // Bytes held by this object (layout, RSI, load map): what a mechanism pays once.
  int64_t memory_bytes() const;
  // Largest h x d of a column: the size of the numeric phase's scratch (kernels::begin_l's W).
  int64_t scratch_size() const { return scratch_size_; }

  // Per pivot position k (0 <= k < num_pivots):
  int block(int k) const { return block_[k]; }
  int size(int k) const { return size_[k]; }
  int row_start(int k) const { return row_start_[k]; }  // first row of pivot k in the permuted order
  int height(int k) const { return height_[k]; }        // rows of E_{*,k}
  int64_t node_offset(int k) const { return node_offset_[k]; }
  int64_t column_offset(int k) const { return node_offset_[k] + int64_t{size_[k]} * size_[k]; }
  std::span<const int> edges(int k) const {  // pivot positions j > k of the edge blocks, ascending
    return {edge_pivot_.data() + edge_ptr_[k], static_cast<size_t>(edge_ptr_[k + 1] - edge_ptr_[k])};
  }
  bool is_fill(int64_t edge) const { return edge_fill_[edge] != 0; }
  int64_t first_edge(int k) const { return edge_ptr_[k]; }
  // Permuted scalar row of each row of E_{*,k} (size height(k)).
  const int* column_rows(int k) const { return l_rows_.data() + l_rows_ptr_[k]; }
  // Of column k's edge blocks: first row in E_{*,k} and size (each of length edges(k).size()).
  const int* edge_rows(int k) const { return edge_row_.data() + edge_ptr_[k]; }
  const int* edge_sizes(int k) const { return edge_size_.data() + edge_ptr_[k]; }
  // The reduction-scattering runs of column k, for each edge block b in order: the number of
  // runs, then per run (value offset of its first target row, its first row in E_{*,k}, rows).
  // The run's rows of E_{*,k} times L_b^T land at consecutive target rows of stride size(b).
  const int32_t* rsi(int k) const { return rsi_.data() + rsi_ptr_[k]; }
  int64_t rsi_size() const { return static_cast<int64_t>(rsi_.size()); }
  int max_size() const { return max_size_; }  // largest block
  // perm[i] = original row at permuted position i (size num_rows)
  std::span<const int> perm() const { return perm_; }
  // Offset in the values of each stored entry of the pattern (size pattern nnz).
  std::span<const int32_t> load_map() const { return load_map_; }
  int64_t pattern_nnz() const { return static_cast<int64_t>(load_map_.size()); }
  // Throws ArgumentError naming `what` and the first column where a's stored entries are not the
  // analyzed pattern's (the load map would scatter them to wrong places or past the end).
  void check_pattern(const SymmetricCsc& a, const char* what) const;

 private:
  int n_ = 0;
  std::string ordering_;              // Ordering::chosen of the ordering analysed, or empty
  std::vector<int> block_;            // original block of each pivot (size num_pivots)
  std::vector<int> size_;             // block size d_k (size num_pivots)
  std::vector<int> row_start_;        // permuted row of each pivot's first row (size num_pivots+1)
  std::vector<int> height_;           // h_k (size num_pivots)
  std::vector<int64_t> node_offset_;  // start of N_k; the last entry is the values' size (size num_pivots+1)
  std::vector<int> edge_ptr_;         // edges of pivot k: [edge_ptr[k], edge_ptr[k+1]) (size num_pivots+1)
  std::vector<int> edge_pivot_;       // pivot position of each edge block's rows (size num_edges)
  std::vector<uint8_t> edge_fill_;    // 1 for a fill block (size num_edges)
  std::vector<int> edge_row_;         // first row of each edge block in its column's E (size num_edges)
  std::vector<int> edge_size_;        // rows of each edge block (size num_edges)
  std::vector<int64_t> l_rows_ptr_;   // (size num_pivots+1)
  std::vector<int> l_rows_;           // permuted scalar rows of every E_{*,k} (size sum h_k)
  std::vector<int64_t> rsi_ptr_;      // (size num_pivots+1)
  std::vector<int32_t> rsi_;          // runs per pivot, see rsi() (size rsi_ptr[num_pivots])
  std::vector<int32_t> load_map_;     // value offset of each stored pattern entry (size pattern nnz)
  std::vector<int> perm_;             // (size n)
  std::vector<int> pattern_col_ptr_;  // the analyzed pattern, for check_pattern (size n+1)
  std::vector<int> pattern_row_idx_;  // (size pattern nnz)
  int64_t num_fill_ = 0;
  int64_t nnz_l_ = 0;
  double flops_ = 0;
  int64_t scratch_size_ = 0;
  int max_size_ = 0;
};

}  // namespace ldlpgs
