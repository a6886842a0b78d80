// Symbolic phase: the block structure of L (ordering/elimination_graph.h plays the elimination
// game), then the packed layout, the RSI and the load map (symbolic.h).
#include "ldlpgs/factor/symbolic.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <string>

#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {

// For one column jb: marks, for every pivot j with an edge block in column jb, the first row of
// that block inside E_{*,jb} (-1 elsewhere). Reset by unmark.
void mark_column(const std::vector<int>& edge_ptr, const std::vector<int>& edge_pivot,
                 const std::vector<int>& edge_row, int jb, std::vector<int>& mark) {
  for (int e = edge_ptr[jb]; e < edge_ptr[jb + 1]; ++e) mark[edge_pivot[e]] = edge_row[e];
}
void unmark_column(const std::vector<int>& edge_ptr, const std::vector<int>& edge_pivot, int jb,
                   std::vector<int>& mark) {
  for (int e = edge_ptr[jb]; e < edge_ptr[jb + 1]; ++e) mark[edge_pivot[e]] = -1;
}

}  // namespace

Symbolic Symbolic::analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, const Ordering& ordering) {
  Symbolic s = ordering.level == Level::scalar ? analyze(pattern, BlockPattern::unit(pattern), ordering.pivots)
                                               : analyze(pattern, blocks, ordering.pivots);
  s.ordering_ = ordering.chosen;
  return s;
}

Symbolic Symbolic::analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, std::span<const int> pivots) {
  check_symmetric_csc(pattern, "symbolic analysis");
  if (blocks.num_rows() != pattern.n)
    throw ArgumentError("symbolic analysis: the block partition covers " + std::to_string(blocks.num_rows()) +
                        " rows of a matrix with " + std::to_string(pattern.n));
  check_permutation(pivots, blocks.num_blocks(), "symbolic analysis (block pivots)");
  Symbolic s;
  const int np = blocks.num_blocks();
  s.n_ = pattern.n;
  s.pattern_col_ptr_ = pattern.col_ptr;
  s.pattern_row_idx_ = pattern.row_idx;
  std::vector<int> pos(np, -1);  // pivot position of each block (size np)
  for (int k = 0; k < np; ++k) pos[pivots[k]] = k;
  const Elimination elim = eliminate(blocks, pivots);
  s.block_.assign(pivots.begin(), pivots.end());
  s.size_.resize(np);
  s.row_start_.assign(np + 1, 0);
  for (int k = 0; k < np; ++k) {
    s.size_[k] = blocks.block(pivots[k]).size;
    s.row_start_[k + 1] = s.row_start_[k] + s.size_[k];
  }
  s.perm_.reserve(pattern.n);
  for (int k = 0; k < np; ++k)
    for (int l = 0; l < s.size_[k]; ++l) s.perm_.push_back(blocks.block(pivots[k]).position + l);

  // Column heights, edge rows within their column, and the layout.
  s.edge_ptr_ = elim.ptr;
  s.edge_pivot_ = elim.edges;
  s.edge_fill_ = elim.fill;
  s.num_fill_ = elim.fill_edges;
  s.edge_row_.resize(s.edge_pivot_.size());
  s.edge_size_.resize(s.edge_pivot_.size());
  s.height_.assign(np, 0);
  s.node_offset_.assign(np + 1, 0);
  s.l_rows_ptr_.assign(np + 1, 0);
  for (int k = 0; k < np; ++k) {
    int h = 0;
    for (int e = s.edge_ptr_[k]; e < s.edge_ptr_[k + 1]; ++e) {
      s.edge_row_[e] = h;
      s.edge_size_[e] = s.size_[s.edge_pivot_[e]];
      h += s.edge_size_[e];
    }
    const int64_t d = s.size_[k];
    s.height_[k] = h;
    s.node_offset_[k + 1] = s.node_offset_[k] + d * d + int64_t{h} * d;
    s.l_rows_ptr_[k + 1] = s.l_rows_ptr_[k] + h;
    s.nnz_l_ += d * (d + 1) / 2 + int64_t{h} * d;
    s.flops_ += static_cast<double>(d * (d + 1) * (2 * d + 1) / 6 + int64_t{h} * d * (d + 1) + d * h * h);
    s.scratch_size_ = std::max(s.scratch_size_, int64_t{h} * d);
    s.max_size_ = std::max(s.max_size_, s.size_[k]);
  }
  if (s.num_values() > std::numeric_limits<int32_t>::max())
    throw InputError("the factor needs " + std::to_string(s.num_values()) +
                     " values, more than the 32-bit reduction-scattering indices address");
  s.l_rows_.reserve(s.l_rows_ptr_[np]);
  for (int k = 0; k < np; ++k)
    for (int j : s.edges(k))
      for (int l = 0; l < s.size_[j]; ++l) s.l_rows_.push_back(s.row_start_[j] + l);

  // RSI: for each edge block b of column k (pivot jb = col[b]), the products E_a L_b^T of the
  // blocks a >= b land in column jb: a == b in jb's node block, a > b in the edge block of
  // col[a] in column jb, which the elimination game guarantees exists. Targets of consecutive a
  // that are consecutive rows of column jb (node block, then its E, all with row stride d_jb)
  // form one run: a panel of rows of E_k times L_b^T lands as one contiguous block. The talk
  // keeps one index per scalar pair; a run is one index for up to all of them (papers/factor.md).
  // Stored per pivot, per b: the number of runs, then (target, first row in E_k, rows) each.
  s.rsi_ptr_.assign(np + 1, 0);
  std::vector<int> mark(np, -1);  // row of an edge block in the marked column (size np)
  for (int k = 0; k < np; ++k) {
    const std::span<const int> col = s.edges(k);
    const int m = static_cast<int>(col.size());
    for (int b = 0; b < m; ++b) {
      const int jb = col[b];
      const size_t header = s.rsi_.size();
      s.rsi_.push_back(0);
      mark_column(s.edge_ptr_, s.edge_pivot_, s.edge_row_, jb, mark);
      int64_t next_target = -1;  // where a run's next row would land
      for (int a = b; a < m; ++a) {
        int64_t target;
        if (a == b) {
          target = s.node_offset_[jb];
        } else {
          assert(mark[col[a]] >= 0 && "the elimination game left out a fill block");
          target = s.column_offset(jb) + int64_t{mark[col[a]]} * s.size_[jb];
        }
        const int rows = s.size_[col[a]];
        if (target == next_target) {
          s.rsi_.back() += rows;
        } else {
          s.rsi_.insert(s.rsi_.end(), {static_cast<int32_t>(target), s.edge_row_[s.edge_ptr_[k] + a], rows});
          ++s.rsi_[header];
        }
        next_target = target + int64_t{rows} * s.size_[jb];
      }
      unmark_column(s.edge_ptr_, s.edge_pivot_, jb, mark);
    }
    s.rsi_ptr_[k + 1] = static_cast<int64_t>(s.rsi_.size());
  }

  // Load map: entry (r, c) of the lower triangle, r in block br, c in block bc. Same block: the
  // node block's lower triangle. Otherwise the entry or its transpose lies in the edge block of
  // the later pivot in the column of the earlier one. Entries are bucketed by that column so each
  // column is marked once.
  const std::vector<int> block_of_row = blocks.block_of_row();
  s.load_map_.assign(pattern.nnz(), -1);
  std::vector<int64_t> bucket_ptr(np + 1, 0);  // (size np+1)
  std::vector<int64_t> bucket;                 // pattern entries by column of L (size nnz)
  auto entry_column = [&](int r, int c) { return std::min(pos[block_of_row[r]], pos[block_of_row[c]]); };
  for (int c = 0; c < pattern.n; ++c)
    for (int p = pattern.col_ptr[c]; p < pattern.col_ptr[c + 1]; ++p) ++bucket_ptr[entry_column(pattern.row_idx[p], c) + 1];
  for (int k = 0; k < np; ++k) bucket_ptr[k + 1] += bucket_ptr[k];
  bucket.resize(pattern.nnz());
  {
    std::vector<int64_t> next(bucket_ptr.begin(), bucket_ptr.end() - 1);
    for (int c = 0; c < pattern.n; ++c)
      for (int p = pattern.col_ptr[c]; p < pattern.col_ptr[c + 1]; ++p) bucket[next[entry_column(pattern.row_idx[p], c)]++] = p;
  }
  std::vector<int> col_of_entry(pattern.nnz());  // column c of each stored entry (size nnz)
  for (int c = 0; c < pattern.n; ++c)
    for (int p = pattern.col_ptr[c]; p < pattern.col_ptr[c + 1]; ++p) col_of_entry[p] = c;
  for (int k = 0; k < np; ++k) {
    mark_column(s.edge_ptr_, s.edge_pivot_, s.edge_row_, k, mark);
    for (int64_t q = bucket_ptr[k]; q < bucket_ptr[k + 1]; ++q) {
      const int64_t p = bucket[q];
      const int r = pattern.row_idx[p], c = col_of_entry[p];
      const int br = block_of_row[r], bc = block_of_row[c];
      const int lr = r - blocks.block(br).position, lc = c - blocks.block(bc).position;
      if (br == bc) {
        s.load_map_[p] = static_cast<int32_t>(s.node_offset_[k] + int64_t{std::max(lr, lc)} * s.size_[k] + std::min(lr, lc));
        continue;
      }
      // The later of the two blocks gives the row of L, the earlier (pivot k) the column.
      const bool row_is_r = pos[br] > pos[bc];
      const int later = row_is_r ? pos[br] : pos[bc];
      const int lrow = row_is_r ? lr : lc, lcol = row_is_r ? lc : lr;
      if (mark[later] < 0)
        throw ArgumentError("symbolic analysis: entry (" + std::to_string(r) + ", " + std::to_string(c) +
                            ") joins blocks " + std::to_string(br) + " and " + std::to_string(bc) +
                            ", which the block pattern does not connect");
      s.load_map_[p] = static_cast<int32_t>(s.column_offset(k) + int64_t{mark[later] + lrow} * s.size_[k] + lcol);
    }
    unmark_column(s.edge_ptr_, s.edge_pivot_, k, mark);
  }
  return s;
}

void Symbolic::check_pattern(const SymmetricCsc& a, const char* what) const {
  if (a.n != n_)
    throw ArgumentError(std::string(what) + ": a matrix of " + std::to_string(a.n) + " rows; the symbolic phase analyzed " +
                        std::to_string(n_));
  // The analyzed pattern passed check_symmetric_csc, so a matrix with the same col_ptr and
  // row_idx (two memcmp) and as many values is well formed too: the full check, whose branch per
  // entry was a third of factorize(a) on a 300-joint chain, runs only to name a fault.
  if (a.col_ptr == pattern_col_ptr_ && a.row_idx == pattern_row_idx_ && a.values.size() == a.row_idx.size()) return;
  check_symmetric_csc(a, what);
  for (int j = 0; j < n_; ++j) {
    const int p = a.col_ptr[j], q = a.col_ptr[j + 1];
    if (p != pattern_col_ptr_[j] || q != pattern_col_ptr_[j + 1] ||
        !std::equal(a.row_idx.begin() + p, a.row_idx.begin() + q, pattern_row_idx_.begin() + p))
      throw ArgumentError(std::string(what) + ": column " + std::to_string(j) +
                          " stores other entries than the pattern the symbolic phase analyzed");
  }
}

int64_t Symbolic::memory_bytes() const {
  auto bytes = [](const auto& v) { return static_cast<int64_t>(v.size() * sizeof(v[0])); };
  return bytes(block_) + bytes(size_) + bytes(row_start_) + bytes(height_) + bytes(node_offset_) +
         bytes(edge_ptr_) + bytes(edge_pivot_) + bytes(edge_fill_) + bytes(edge_row_) + bytes(edge_size_) + bytes(l_rows_ptr_) + bytes(l_rows_) +
         bytes(rsi_ptr_) + bytes(rsi_) + bytes(load_map_) + bytes(perm_) + bytes(pattern_col_ptr_) +
         bytes(pattern_row_idx_);
}

}  // namespace ldlpgs
