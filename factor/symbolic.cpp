// Symbolic phase: the block structure of L (ordering/elimination_graph.h plays the elimination
// game), then the packed layout, the RSI and the load map (symbolic.h).
#include "ldlpgs/factor/symbolic.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <numeric>
#include <string>

#include "ldlpgs/factor/dense.h"
#include "ldlpgs/ordering/elimination_graph.h"
#include "ldlpgs/ordering/postorder.h"
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

// The steps of analyze, in its order (as CSparse's cs_schol: the counts first, then what is
// built from them). Each fills the members its comment names.
struct Symbolic::Steps {
  // block_, size_, row_start_, perm_, max_size_: the pivots' blocks in pivot order.
  static void pivot_rows(Symbolic& s, const BlockPattern& blocks, std::span<const int> pivots) {
    const int np = blocks.num_blocks();
    s.block_.assign(pivots.begin(), pivots.end());
    s.size_.resize(np);
    s.row_start_.assign(np + 1, 0);
    for (int k = 0; k < np; ++k) {
      s.size_[k] = blocks.block(pivots[k]).size;
      s.row_start_[k + 1] = s.row_start_[k] + s.size_[k];
      s.max_size_ = std::max(s.max_size_, s.size_[k]);
    }
    s.perm_.reserve(s.n_);
    for (int k = 0; k < np; ++k)
      for (int l = 0; l < s.size_[k]; ++l) s.perm_.push_back(blocks.block(pivots[k]).position + l);
  }

  // The edge blocks of L (fill included) from the elimination game, each one's row in its column
  // and size; per pivot the column height h_k, and the counts nnz_l_ and flops_.
  static void counts(Symbolic& s, const Elimination& elim) {
    const int np = s.num_pivots();
    s.edge_ptr_ = elim.ptr;
    s.edge_pivot_ = elim.edges;
    s.edge_fill_ = elim.fill;
    s.num_fill_ = elim.fill_edges;
    s.edge_row_.resize(s.edge_pivot_.size());
    s.edge_size_.resize(s.edge_pivot_.size());
    s.height_.assign(np, 0);
    for (int k = 0; k < np; ++k) {
      int h = 0;
      for (int e = s.edge_ptr_[k]; e < s.edge_ptr_[k + 1]; ++e) {
        s.edge_row_[e] = h;
        s.edge_size_[e] = s.size_[s.edge_pivot_[e]];
        h += s.edge_size_[e];
      }
      const int64_t d = s.size_[k];
      s.height_[k] = h;
      s.nnz_l_ += d * (d + 1) / 2 + int64_t{h} * d;
      s.flops_ += static_cast<double>(d * (d + 1) * (2 * d + 1) / 6 + int64_t{h} * d * (d + 1) + d * h * h);
    }
  }

  // k + 1 is k's parent in the elimination tree (the first edge block of k is k + 1).
  static bool parent_is_next(const Symbolic& s, int k) {
    return s.edge_ptr_[k + 1] > s.edge_ptr_[k] && s.edge_pivot_[s.edge_ptr_[k]] == k + 1;
  }
  // k nests in k + 1: the rest of k's column, a subset of struct(k + 1), is all of it.
  static bool nests(const Symbolic& s, int k) {
    return parent_is_next(s, k) && s.height_[k] == s.size_[k + 1] + s.height_[k + 1];
  }
  // Whether the group [first, last] stores few enough explicit zeros below its diagonal blocks:
  // pivot i stores size_i (rows after it in the group + h_last) and holds size_i h_i.
  static bool relaxed_ok(const Symbolic& s, int first, int last, double relax_max_zeros) {
    int64_t zeros = 0, stored = 0;
    for (int i = first; i <= last; ++i) {
      const int64_t below = s.row_start_[last + 1] - s.row_start_[i + 1] + s.height_[last];
      stored += s.size_[i] * below;
      zeros += s.size_[i] * (below - s.height_[i]);
    }
    return static_cast<double>(zeros) <= relax_max_zeros * static_cast<double>(stored);
  }

  // sn_begin_. Maximal runs of nested pivots (k's first edge block is k + 1 and the rest of its
  // column is k + 1's: since k + 1 is then k's parent in the elimination tree, the rest is a subset
  // of struct(k + 1), equal when the heights match), kept when wide enough (SymbolicOptions).
  // The other pivots form small supernodes greedily in pivot order, each as many whole pivots as
  // fit in small_supernode_max_rows rows, where every pivot but the last has the next as its
  // parent: any consecutive part of a nested run, and a relaxed one (CHOLMOD's relaxed
  // amalgamation) when the explicit zeros it stores stay within relax_max_zeros. A parent chain
  // keeps every block of the group's columns inside the group's rows and struct(last), so the
  // layout (node block and the last pivot's E), the RSI and the load map need nothing else; the
  // zeros are zeroed by the load like any value the load map misses.
  static void supernodes(Symbolic& s, const SymbolicOptions& options) {
    const int np = s.num_pivots();
    std::vector<int> run_end(np, -1);  // at the first pivot of a run made one supernode: its end (size np)
    for (int k = 0; k < np;) {
      int end = k + 1;
      while (end < np && nests(s, end - 1)) ++end;
      const int rows = s.row_start_[end] - s.row_start_[k];
      if (options.supernode_min_rows > 0 && rows >= options.supernode_min_rows &&
          rows + s.height_[end - 1] >= options.supernode_min_front)
        std::fill(run_end.begin() + k, run_end.begin() + end, end);
      k = end;
    }
    s.sn_begin_.assign(1, 0);
    const int most = options.supernode_min_rows > 0 ? options.small_supernode_max_rows : 1;
    for (int k = 0; k < np;) {
      if (run_end[k] >= 0) {
        s.sn_begin_.push_back(k = run_end[k]);
        continue;
      }
      // A small supernode from k: while the next pivot is the last one's parent, is not in a
      // supernode of its own, fits, and nests or keeps the zeros within bounds.
      int last = k;
      while (last + 1 < np && run_end[last + 1] < 0 && parent_is_next(s, last) &&
             s.row_start_[last + 2] - s.row_start_[k] <= most &&
             (nests(s, last) || relaxed_ok(s, k, last + 1, options.relax_max_zeros)))
        ++last;
      s.sn_begin_.push_back(k = last + 1);
    }
  }

  // The packed layout per supernode: sn_of_pivot_, sn_blas_, sn_node_offset_ (node block, then
  // E), l_rows_ (E's permuted rows), scratch_size_.
  static void layout(Symbolic& s, const SymbolicOptions& options) {
    const int ns = s.num_supernodes();
    s.sn_of_pivot_.resize(s.num_pivots());
    s.sn_blas_.assign(ns, 0);
    s.sn_node_offset_.assign(ns + 1, 0);
    s.l_rows_ptr_.assign(ns + 1, 0);
    for (int t = 0; t < ns; ++t) {
      for (int k = s.sn_begin_[t]; k < s.sn_begin_[t + 1]; ++k) s.sn_of_pivot_[k] = t;
      const int64_t d = s.supernode_size(t), h = s.supernode_height(t);
      s.sn_blas_[t] = options.blas_min_rows > 0 && d >= options.blas_min_rows;
      s.sn_node_offset_[t + 1] = s.sn_node_offset_[t] + d * d + h * d;
      s.l_rows_ptr_[t + 1] = s.l_rows_ptr_[t] + h;
      const int64_t blas = s.sn_blas_[t] ? std::max(h * d + h * h, d * dense::kPanel) : 0;
      s.scratch_size_ = std::max({s.scratch_size_, h * d, blas});
    }
    if (s.num_values() > std::numeric_limits<int32_t>::max())
      throw InputError("the factor needs " + std::to_string(s.num_values()) +
                       " values, more than the 32-bit reduction-scattering indices address");
    s.l_rows_.reserve(s.l_rows_ptr_[ns]);
    for (int t = 0; t < ns; ++t)
      for (int j : s.supernode_edges(t))
        for (int l = 0; l < s.size_[j]; ++l) s.l_rows_.push_back(s.row_start_[j] + l);
  }

  // Where row block p lands in supernode t's storage (rows of stride supernode_size(t)): inside
  // t, the row of its node block; below, the row of t's E (marked by mark_column on t's last
  // pivot). The elimination game guarantees one of the two for every block of struct(k), k in t.
  static int64_t target_row(const Symbolic& s, const std::vector<int>& mark, int t, int p) {
    if (s.sn_of_pivot_[p] == t)
      return s.node_offset(t) + int64_t{s.row_start_[p] - s.supernode_row_start(t)} * s.supernode_size(t);
    assert(mark[p] >= 0 && "the elimination game left out a fill block");
    return s.column_offset(t) + int64_t{mark[p]} * s.supernode_size(t);
  }

  // rsi_, rsi_ptr_. For each edge block b of supernode t's column (pivot jb = col[b], in
  // supernode u), the products E_a L_b^T of the blocks a >= b land in u at jb's columns: a == b
  // on u's diagonal, a > b in u's node block or E (target_row). Targets of consecutive a that are
  // consecutive rows of u (stride size(u)) form one run: a panel of rows of E times L_b^T lands as
  // one contiguous block. The talk keeps one index per scalar pair; a run is one index for up to
  // all of them (papers/factor.md). Stored per supernode, per b: the number of runs and the
  // stride, then (target, first row in E, rows) each.
  static void rsi(Symbolic& s) {
    const int ns = s.num_supernodes();
    std::vector<int> mark(s.num_pivots(), -1);  // row of an edge block in the marked column (size np)
    s.rsi_ptr_.assign(ns + 1, 0);
    for (int t = 0; t < ns; ++t) {
      const std::span<const int> col = s.supernode_edges(t);
      const int* rows_in_e = s.edge_rows(t);
      const int m = static_cast<int>(col.size());
      for (int b = 0; b < m; ++b) {
        const int jb = col[b], u = s.sn_of_pivot_[jb];
        const int64_t stride = s.supernode_size(u), column = s.row_start_[jb] - s.supernode_row_start(u);
        const size_t header = s.rsi_.size();
        s.rsi_.insert(s.rsi_.end(), {0, static_cast<int32_t>(stride)});
        const int last_of_u = s.sn_begin_[u + 1] - 1;
        mark_column(s.edge_ptr_, s.edge_pivot_, s.edge_row_, last_of_u, mark);
        int64_t next_target = -1;  // where a run's next row would land
        for (int a = b; a < m; ++a) {
          const int64_t target = target_row(s, mark, u, col[a]) + column;
          const int rows = s.size_[col[a]];
          if (target == next_target) {
            s.rsi_.back() += rows;
          } else {
            s.rsi_.insert(s.rsi_.end(), {static_cast<int32_t>(target), rows_in_e[a], rows});
            ++s.rsi_[header];
          }
          next_target = target + int64_t{rows} * stride;
        }
        unmark_column(s.edge_ptr_, s.edge_pivot_, last_of_u, mark);
      }
      s.rsi_ptr_[t + 1] = static_cast<int64_t>(s.rsi_.size());
    }
  }

  // sn_mapped_, any_mapped_. Over budget (SymbolicOptions::rsi_max_per_entry), the supernodes with
  // the most runs scatter through relative maps instead, largest first, until the runs left fit:
  // the fewest mapped supernodes for the memory, since a mapped one pays O(rows of each target)
  // per factorization (papers/factor.md, "Relative maps"). Their runs leave rsi_.
  static void map_over_budget(Symbolic& s, const SymbolicOptions& options) {
    const int ns = s.num_supernodes();
    s.sn_mapped_.assign(ns, 0);
    const double budget = options.rsi_max_per_entry == 0
                              ? 0.0
                              : std::max(options.rsi_max_per_entry * static_cast<double>(s.nnz_l_),
                                         static_cast<double>(options.rsi_min_entries));
    if (!(options.rsi_max_per_entry >= 0 && static_cast<double>(s.rsi_.size()) > budget)) return;
    std::vector<int> by_size(ns);  // supernodes, most runs first (size ns)
    std::iota(by_size.begin(), by_size.end(), 0);
    auto entries = [&](int t) { return s.rsi_ptr_[t + 1] - s.rsi_ptr_[t]; };
    std::stable_sort(by_size.begin(), by_size.end(), [&](int a, int b) { return entries(a) > entries(b); });
    double left = static_cast<double>(s.rsi_.size());
    for (int t : by_size) {
      if (left <= budget || entries(t) == 0) break;
      left -= static_cast<double>(entries(t));
      s.sn_mapped_[t] = 1;
      s.any_mapped_ = true;
    }
    std::vector<int32_t> kept;  // the runs of the supernodes not mapped (size left)
    kept.reserve(static_cast<size_t>(left));
    std::vector<int64_t> ptr(ns + 1, 0);  // (size ns+1)
    for (int t = 0; t < ns; ++t) {
      if (!s.sn_mapped_[t]) kept.insert(kept.end(), s.rsi_.begin() + s.rsi_ptr_[t], s.rsi_.begin() + s.rsi_ptr_[t + 1]);
      ptr[t + 1] = static_cast<int64_t>(kept.size());
    }
    s.rsi_ = std::move(kept);
    s.rsi_ptr_ = std::move(ptr);
  }

  // rsi_'s flags. In elimination order, a run below its target's diagonal whose every entry is
  // neither loaded (load_map_) nor written by an earlier run writes its target first: its rows
  // are negated, and the numeric phase stores there instead of subtracting from zeros (so it
  // need not zero them). On a loop that is the fill every column carries (papers/factor.md,
  // "First writes"). None with mapped supernodes, whose writes are in no run.
  static void first_writes(Symbolic& s) {
    if (s.any_mapped_) return;
    std::vector<uint8_t> written(s.num_values(), 0);  // loaded, or written by a run so far
    for (const int32_t q : s.load_map_) written[q] = 1;
    for (int t = 0; t < s.num_supernodes(); ++t)
      for_each_run(s.rsi_.data() + s.rsi_ptr_[t], s.edge_sizes(t), static_cast<int>(s.supernode_edges(t).size()),
                   [&](int32_t* run, int i, int ld, int db) {
                     bool first = i > 0;
                     for_each_run_entry(run, i, ld, db, [&](int64_t q) { first = first && !written[q]; });
                     for_each_run_entry(run, i, ld, db, [&](int64_t q) { written[q] = 1; });
                     if (first) run[2] = -run[2];
                   });
  }

  // load_map_. Entry (r, c) of the lower triangle, r in block br, c in block bc, lands in the
  // supernode t of the earlier of the two pivots, at the later one's row (target_row) and the
  // earlier one's column (node_entry inside t's node block). Entries are bucketed by t so each
  // supernode is marked once. Throws ArgumentError for an entry that joins blocks the block
  // pattern does not connect.
  static void load_map(Symbolic& s, const SymmetricCsc& pattern, const BlockPattern& blocks) {
    const int np = s.num_pivots(), ns = s.num_supernodes();
    std::vector<int> pos(np, -1);  // pivot position of each block (size np)
    for (int k = 0; k < np; ++k) pos[s.block_[k]] = k;
    const std::vector<int> block_of_row = blocks.block_of_row();
    auto entry_supernode = [&](int r, int c) {
      return s.sn_of_pivot_[std::min(pos[block_of_row[r]], pos[block_of_row[c]])];
    };
    // The pattern's entries by supernode: bucket[bucket_ptr[t] .. bucket_ptr[t + 1]).
    std::vector<int64_t> bucket_ptr(ns + 1, 0);  // (size ns+1)
    std::vector<int64_t> bucket(pattern.nnz());  // (size nnz)
    for (int c = 0; c < pattern.n; ++c)
      for (int p = pattern.col_ptr[c]; p < pattern.col_ptr[c + 1]; ++p) ++bucket_ptr[entry_supernode(pattern.row_idx[p], c) + 1];
    for (int t = 0; t < ns; ++t) bucket_ptr[t + 1] += bucket_ptr[t];
    std::vector<int64_t> next(bucket_ptr.begin(), bucket_ptr.end() - 1);  // (size ns)
    std::vector<int> col_of_entry(pattern.nnz());  // column c of each stored entry (size nnz)
    for (int c = 0; c < pattern.n; ++c)
      for (int p = pattern.col_ptr[c]; p < pattern.col_ptr[c + 1]; ++p) {
        bucket[next[entry_supernode(pattern.row_idx[p], c)]++] = p;
        col_of_entry[p] = c;
      }
    s.load_map_.assign(pattern.nnz(), -1);
    std::vector<int> mark(np, -1);  // row of an edge block in the marked column (size np)
    for (int t = 0; t < ns; ++t) {
      const int last = s.sn_begin_[t + 1] - 1;
      mark_column(s.edge_ptr_, s.edge_pivot_, s.edge_row_, last, mark);
      for (int64_t q = bucket_ptr[t]; q < bucket_ptr[t + 1]; ++q) {
        const int64_t p = bucket[q];
        const int r = pattern.row_idx[p], c = col_of_entry[p];
        const int br = block_of_row[r], bc = block_of_row[c];
        // Permuted rows of the two ends: the later gives the row of L, the earlier the column.
        const int pr = s.row_start_[pos[br]] + r - blocks.block(br).position;
        const int pc = s.row_start_[pos[bc]] + c - blocks.block(bc).position;
        const bool row_is_r = pr > pc;
        const int later = row_is_r ? pos[br] : pos[bc];
        const int lrow = row_is_r ? pr - s.row_start_[later] : pc - s.row_start_[later];
        const int lcol = (row_is_r ? pc : pr) - s.supernode_row_start(t);
        if (s.sn_of_pivot_[later] != t && mark[later] < 0)
          throw ArgumentError("symbolic analysis: entry (" + std::to_string(r) + ", " + std::to_string(c) +
                              ") joins blocks " + std::to_string(br) + " and " + std::to_string(bc) +
                              ", which the block pattern does not connect");
        const int64_t at = s.sn_of_pivot_[later] == t
                               ? s.node_entry(t, s.row_start_[later] - s.supernode_row_start(t) + lrow, lcol)
                               : target_row(s, mark, t, later) + int64_t{lrow} * s.supernode_size(t) + lcol;
        s.load_map_[p] = static_cast<int32_t>(at);
      }
      unmark_column(s.edge_ptr_, s.edge_pivot_, last, mark);
    }
  }
};

Symbolic Symbolic::analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, const Ordering& ordering,
                           const SymbolicOptions& options) {
  Symbolic s = ordering.level == Level::scalar ? analyze(pattern, BlockPattern::unit(pattern), ordering.pivots, options)
                                               : analyze(pattern, blocks, ordering.pivots, options);
  s.ordering_ = ordering.chosen;
  return s;
}

Symbolic Symbolic::analyze(const SymmetricCsc& pattern, const BlockPattern& blocks, std::span<const int> pivots,
                           const SymbolicOptions& options) {
  check_symmetric_csc(pattern, "symbolic analysis");
  if (blocks.num_rows() != pattern.n)
    throw ArgumentError("symbolic analysis: the block partition covers " + std::to_string(blocks.num_rows()) +
                        " rows of a matrix with " + std::to_string(pattern.n));
  check_permutation(pivots, blocks.num_blocks(), "symbolic analysis (block pivots)");
  Symbolic s;
  s.n_ = pattern.n;
  s.pattern_col_ptr_ = pattern.col_ptr;
  s.pattern_row_idx_ = pattern.row_idx;
  Elimination game = eliminate(blocks, pivots);
  std::vector<int> postordered;
  if (options.postorder) {
    postordered = postorder(blocks, pivots, game);
    pivots = postordered;
    game = eliminate(blocks, pivots);
  }
  Steps::pivot_rows(s, blocks, pivots);
  Steps::counts(s, game);
  Steps::supernodes(s, options);
  Steps::layout(s, options);
  Steps::rsi(s);
  Steps::map_over_budget(s, options);
  Steps::load_map(s, pattern, blocks);
  Steps::first_writes(s);
  return s;
}

int Symbolic::pivot_of_row(int row) const {
  assert(row >= 0 && row < n_);
  return static_cast<int>(std::upper_bound(row_start_.begin(), row_start_.end(), row) - row_start_.begin()) - 1;
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
  return bytes(block_) + bytes(size_) + bytes(row_start_) + bytes(height_) + bytes(sn_begin_) + bytes(sn_of_pivot_) + bytes(sn_blas_) + bytes(sn_mapped_) + bytes(sn_node_offset_) +
         bytes(edge_ptr_) + bytes(edge_pivot_) + bytes(edge_fill_) + bytes(edge_row_) + bytes(edge_size_) + bytes(l_rows_ptr_) + bytes(l_rows_) +
         bytes(rsi_ptr_) + bytes(rsi_) + bytes(load_map_) + bytes(perm_) + bytes(pattern_col_ptr_) +
         bytes(pattern_row_idx_);
}

}  // namespace ldlpgs
