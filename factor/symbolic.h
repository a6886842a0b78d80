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
// replaced by L with one copy. A BLAS supernode's node block (dense.h) is the exception: the
// load map fills it column-major, LAPACK's lower triangle, and the RSI's updates land in its
// row-major lower triangle, which the numeric phase adds in before factoring it.
//
// Supernodes: where consecutive pivots k, k+1, ... have nested structure (the first edge block
// of k is k+1 and the rest of k's column is k+1's: struct(k) = {k+1} + struct(k+1), CHOLMOD's
// fundamental supernode), their columns are one dense trapezoid, and the numeric phase treats the
// run as one pivot of their summed size: one node block (the pivots' node blocks and the edge
// blocks between them, which the nesting makes structurally nonzero), one E below it. Nothing
// changes in L: nnz_l and flops are those of the block columns, which the supernode stores
// exactly (no explicit zeros but the node block's upper triangle). Dense fronts (grids, stars,
// structural matrices) get kernels of their real width, wide ones level-3 BLAS (dense.h);
// chains and trees, whose pivots rarely nest, keep the unrolled per-block path. A run too narrow
// for one supernode is cut into small ones of up to 6 rows, the unrolled kernels' widths
// (SymbolicOptions::small_supernode_max_rows). The layout and the RSI are per supernode; a pivot
// not merged is a supernode of one.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// How the symbolic phase groups pivots into supernodes, and which of them the numeric phase
// eliminates with BLAS. The defaults come from measurements (papers/factor.md, "Supernodes").
struct SymbolicOptions {
  // Factor in the weighted postorder of the given pivots' block elimination tree (CHOLMOD's
  // default): the same fill and flops, but chains of parents become consecutive pivots, which the
  // rules below can group into supernodes. perm() and block() are then of the postorder.
  // papers/factor.md, "Postordered pivots".
  bool postorder = true;
  // A maximal run of nested pivots becomes one supernode when it has at least this many rows
  // and its front (its rows and the rows of L below them) at least supernode_min_front: under
  // 128 rows a front is faster per block than on BLAS. 0 keeps every pivot alone (a huge value
  // cuts every run into small supernodes, below). papers/factor.md, "Supernodes: before and after"
  // and "Small supernodes and Cholesky panels".
  int supernode_min_rows = 16;
  int supernode_min_front = 128;
  // A run of nested pivots that is not one supernode by the two rules above is cut into
  // supernodes of at most this many rows (greedily, in pivot order), which the unrolled kernels
  // of that width eliminate (kernels.h unrolls 1-6): scalar pivots pay the per-pivot cost once
  // per 6 rows, and two 3-row blocks of a grid run as one 6-row kernel. 1 (or supernode_min_rows
  // 0) keeps such pivots alone. papers/factor.md, "Small supernodes and Cholesky panels".
  int small_supernode_max_rows = 6;
  // A small supernode may also take pivots that do not nest, when each is the previous one's
  // parent (CHOLMOD's relaxed amalgamation: the group's columns are stored over the union of
  // their rows, with explicit zeros), as long as the zeros are at most this fraction of the
  // entries it stores below its diagonal blocks. 0: nested runs only. The factor's counts
  // (nnz_l, flops) and Numeric::scalar_ldl stay those of L; num_values counts the zeros.
  // papers/factor.md, "Relaxed small supernodes".
  double relax_max_zeros = 0.5;
  // Supernodes of at least this many rows are eliminated with dense.h (BLAS), the rest with the
  // kernels of kernels.h at their width.
  int blas_min_rows = 16;
  // The RSI's budget: at most this many indices per entry of L (nnz_l). Over it, the supernodes
  // with the most runs scatter through a map of each target supernode's rows instead, built by
  // the numeric phase in O(rows of the target) (CHOLMOD's relative map, Map in
  // cholmod_super_numeric): narrow columns with many edge blocks make many more runs than
  // entries of L. The mechanisms' runs fit and keep their speed. 0: every supernode mapped;
  // negative: none. papers/factor.md, "Relative maps".
  double rsi_max_per_entry = 1.0;
  // ... but never below this many indices (2^16, 256 KB), unless rsi_max_per_entry is 0: small
  // matrices of scalar blocks have more runs than entries of L, and mapping them costs more than
  // their runs' memory. papers/factor.md, "Relative maps".
  int64_t rsi_min_entries = int64_t{1} << 16;
};

// Calls f(run, i, ld, db) for each run of one supernode's entry of Symbolic::rsi (`runs`, its
// `edges` edge blocks of sizes[b] rows): run points at the (target, first row in E, rows) triple
// of the i-th run of an edge block of db rows, ld the target's row stride. Run is int32_t or
// const int32_t. Returns the end of the entry.
template <class Run, class F>
Run* for_each_run(Run* runs, const int* sizes, int edges, F&& f) {
  for (int b = 0; b < edges; ++b) {
    const int count = runs[0], ld = runs[1];
    runs += 2;
    for (int i = 0; i < count; ++i, runs += 3) f(runs, i, ld, sizes[b]);
  }
  return runs;
}

// Calls f(value offset) for every entry that `run`, one (target, first row in E, rows) triple of
// Symbolic::rsi, writes: the i-th run of an edge block of db rows, row stride ld. Rows of db
// values; the first run's first db rows, on the target's diagonal, their lower triangle only.
template <class F>
void for_each_run_entry(const int32_t* run, int i, int ld, int db, F&& f) {
  const int64_t rows = run[2] < 0 ? -int64_t{run[2]} : run[2];
  for (int64_t r = 0; r < rows; ++r)
    for (int c = 0; c < (i == 0 && r < db ? r + 1 : db); ++c) f(run[0] + r * ld + c);
}

class Symbolic {
 public:
  Symbolic() = default;
  // pattern: the stored entries (values ignored) of the matrices to factor; blocks: its partition
  // into blocks (every stored entry must lie in a block of `blocks`'s graph or on its diagonal);
  // pivots: the block pivot sequence (pivots[k] = block eliminated k-th, a permutation), factored
  // in its elimination tree's postorder unless options.postorder is false. All three are checked
  // (ArgumentError naming the fault), in every build.
  static Symbolic analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, std::span<const int> pivots,
                          const SymbolicOptions& options = {});
  // The same for a computed ordering: a scalar ordering (amd-scalar, metis-scalar) factors with
  // 1 x 1 blocks.
  static Symbolic analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, const Ordering& ordering,
                          const SymbolicOptions& options = {});

  // The ordering that gave the pivots (Ordering::chosen: best's winner); empty from bare pivots.
  const std::string& ordering() const { return ordering_; }
  int num_rows() const { return n_; }
  int num_pivots() const { return static_cast<int>(size_.size()); }
  int64_t num_values() const { return sn_node_offset_.empty() ? 0 : sn_node_offset_.back(); }
  int64_t num_edges() const { return static_cast<int64_t>(edge_pivot_.size()); }
  int64_t num_fill_edges() const { return num_fill_; }
  // Scalar entries of L, diagonal included, counting every block as dense (CHOLMOD's lnz when the
  // blocks are dense), and the flops of the factorization: per pivot of size d and height h,
  // sum over its d columns of (column count)^2 = d(d+1)(2d+1)/6 + h d(d+1) + d h^2 (CHOLMOD's fl).
  int64_t nnz_l() const { return nnz_l_; }
  double flops() const { return flops_; }

  // Bytes held by this object (layout, RSI, load map): what a mechanism pays once.
  int64_t memory_bytes() const;
  // The numeric phase's scratch: W = E L^-T of the widest column (h x d), and for a BLAS
  // supernode also C = W Y^T (h x h) after it, or the d x dense::kPanel panel of dense::factor_supernode.
  int64_t scratch_size() const { return scratch_size_; }

  // The block structure of L, per pivot position k (0 <= k < num_pivots):
  int block(int k) const { return block_[k]; }
  int size(int k) const { return size_[k]; }
  int row_start(int k) const { return row_start_[k]; }  // first row of pivot k in the permuted order
  int height(int k) const { return height_[k]; }        // rows of E_{*,k}
  std::span<const int> edges(int k) const {  // pivot positions j > k of the edge blocks, ascending
    return {edge_pivot_.data() + edge_ptr_[k], static_cast<size_t>(edge_ptr_[k + 1] - edge_ptr_[k])};
  }
  bool is_fill(int64_t edge) const { return edge_fill_[edge] != 0; }
  int64_t first_edge(int k) const { return edge_ptr_[k]; }
  int pivot_of_row(int row) const;  // the pivot holding permuted row `row`

  // The numeric layout, per supernode s (0 <= s < num_supernodes): pivots
  // [supernode_begin(s), supernode_begin(s + 1)), one node block and one E of the last pivot's
  // edge blocks.
  int num_supernodes() const { return static_cast<int>(sn_begin_.size()) - 1; }
  int supernode_begin(int s) const { return sn_begin_[s]; }
  int supernode_of(int k) const { return sn_of_pivot_[k]; }
  int supernode_row_start(int s) const { return row_start_[sn_begin_[s]]; }
  int supernode_size(int s) const { return row_start_[sn_begin_[s + 1]] - row_start_[sn_begin_[s]]; }  // rows d
  int supernode_height(int s) const { return height_[sn_begin_[s + 1] - 1]; }                         // rows h of E
  bool supernode_blas(int s) const { return sn_blas_[s] != 0; }  // eliminated with dense.h
  // Scatters through a relative map of each target's rows instead of RSI runs (its rsi() entry
  // is empty; SymbolicOptions::rsi_max_per_entry).
  bool supernode_mapped(int s) const { return sn_mapped_[s] != 0; }
  bool any_mapped() const { return any_mapped_; }
  int64_t node_offset(int s) const { return sn_node_offset_[s]; }
  int64_t column_offset(int s) const { return sn_node_offset_[s] + int64_t{supernode_size(s)} * supernode_size(s); }
  // Value offset of entry (r, c) of supernode s's node block: row-major where kernels.h
  // eliminates, column-major in a BLAS supernode (dense.h).
  int64_t node_entry(int s, int64_t r, int64_t c) const {
    const int64_t d = supernode_size(s);
    return sn_node_offset_[s] + (sn_blas_[s] ? c * d + r : r * d + c);
  }
  std::span<const int> supernode_edges(int s) const { return edges(sn_begin_[s + 1] - 1); }
  // Permuted scalar row of each row of E (size supernode_height(s)).
  const int* column_rows(int s) const { return l_rows_.data() + l_rows_ptr_[s]; }
  // Of the supernode's edge blocks: first row in E and size (each of length supernode_edges(s).size()).
  const int* edge_rows(int s) const { return edge_row_.data() + edge_ptr_[sn_begin_[s + 1] - 1]; }
  const int* edge_sizes(int s) const { return edge_size_.data() + edge_ptr_[sn_begin_[s + 1] - 1]; }
  // The reduction-scattering runs of supernode s (none when it is mapped), for each edge block b in order: the number of
  // runs and the row stride of the target supernode (its size), then per run (value offset of its
  // first target row, its first row in E, rows). The run's rows of E times L_b^T land at
  // consecutive target rows of that stride, the first run's first size(b) rows on the target's
  // diagonal (of which only the lower triangle is written). A later run with its rows negated
  // writes its target first: none of its entries is loaded from the pattern or written by an
  // earlier run, so the numeric phase stores there instead of subtracting from zeros.
  const int32_t* rsi(int s) const { return rsi_.data() + rsi_ptr_[s]; }
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
  struct Steps;  // analyze's phases (symbolic.cpp)
  int n_ = 0;
  std::string ordering_;              // Ordering::chosen of the ordering analysed, or empty
  std::vector<int> block_;            // original block of each pivot (size num_pivots)
  std::vector<int> size_;             // block size d_k (size num_pivots)
  std::vector<int> row_start_;        // permuted row of each pivot's first row (size num_pivots+1)
  std::vector<int> height_;           // h_k (size num_pivots)
  std::vector<int> edge_ptr_;         // edges of pivot k: [edge_ptr[k], edge_ptr[k+1]) (size num_pivots+1)
  std::vector<int> edge_pivot_;       // pivot position of each edge block's rows (size num_edges)
  std::vector<uint8_t> edge_fill_;    // 1 for a fill block (size num_edges)
  std::vector<int> edge_row_;         // first row of each edge block in its column's E (size num_edges)
  std::vector<int> edge_size_;        // rows of each edge block (size num_edges)
  std::vector<int> sn_begin_;         // first pivot of each supernode (size num_supernodes+1)
  std::vector<int> sn_of_pivot_;      // supernode of each pivot (size num_pivots)
  std::vector<uint8_t> sn_blas_;      // 1: eliminated with dense.h (size num_supernodes)
  std::vector<uint8_t> sn_mapped_;    // 1: scattered through a relative map (size num_supernodes)
  bool any_mapped_ = false;
  std::vector<int64_t> sn_node_offset_;  // start of each node block; the last entry is the values' size (size num_supernodes+1)
  std::vector<int64_t> l_rows_ptr_;   // (size num_supernodes+1)
  std::vector<int> l_rows_;           // permuted scalar rows of every supernode's E (size sum h_s)
  std::vector<int64_t> rsi_ptr_;      // (size num_supernodes+1)
  std::vector<int32_t> rsi_;          // runs per supernode, see rsi() (size rsi_ptr[num_supernodes])
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
