#include "ldlpgs/sparse/block_pattern.h"

#include <limits>
#include <numeric>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {
// A partition a caller passes: positive sizes. Checked in every build (ArgumentError).
int64_t checked_rows(std::span<const int> block_sizes) {
  int64_t rows = 0;
  for (size_t b = 0; b < block_sizes.size(); ++b) {
    if (block_sizes[b] <= 0)
      throw ArgumentError("block partition: block " + std::to_string(b) + " has size " + std::to_string(block_sizes[b]));
    rows += block_sizes[b];
  }
  return rows;
}
}  // namespace

BlockPattern::BlockPattern(std::span<const int> block_sizes, Graph graph) : graph_(std::move(graph)) {
  if (static_cast<int64_t>(block_sizes.size()) != graph_.n)
    throw ArgumentError("block partition: " + std::to_string(block_sizes.size()) + " block sizes for a block graph of " +
                        std::to_string(graph_.n) + " vertices");
  const int64_t rows = checked_rows(block_sizes);
  if (rows > std::numeric_limits<int>::max()) throw ArgumentError("block partition: more than 2^31 rows");
  blocks_.reserve(block_sizes.size());
  for (int size : block_sizes) {
    blocks_.push_back({size, num_rows_});
    num_rows_ += size;
  }
}

BlockPattern BlockPattern::from_scalar(const SymmetricCsc& a, std::span<const int> block_sizes) {
  check_symmetric_csc(a, "block pattern");
  if (const int64_t rows = checked_rows(block_sizes); rows != a.n)
    throw ArgumentError("block partition: the blocks cover " + std::to_string(rows) + " rows of a matrix with " +
                        std::to_string(a.n));
  std::vector<int> block_of(a.n);
  const int nb = static_cast<int>(block_sizes.size());
  for (int b = 0, r = 0; b < nb; ++b)
    for (int k = 0; k < block_sizes[b]; ++k) block_of[r++] = b;
  // One edge per coupling block, not per scalar entry: a lower-triangle entry (i, j) has
  // block_of[i] >= block_of[j], so block column bj sees each of its blocks bi, and only it does;
  // seen[bi] == bj marks bi as listed. One edge per scalar entry gave graph_from_edges 9 copies
  // of each edge of dense 3 x 3 couplings (papers/factor.md, "Supernodes: before and after").
  std::vector<int> seen(nb, -1);  // (size blocks)
  std::vector<std::pair<int, int>> edges;
  for (int bj = 0, j = 0; bj < nb; ++bj) {
    for (const int last = j + block_sizes[bj]; j < last; ++j) {
      for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
        const int bi = block_of[a.row_idx[p]];
        if (bi == bj || seen[bi] == bj) continue;
        seen[bi] = bj;
        edges.emplace_back(bi, bj);
      }
    }
  }
  return BlockPattern(block_sizes, graph_from_edges(nb, edges));
}

BlockPattern BlockPattern::unit(const SymmetricCsc& a) {
  return BlockPattern(std::vector<int>(a.n, 1), graph_of(a));
}

std::vector<int> BlockPattern::block_sizes() const {
  std::vector<int> sizes;
  sizes.reserve(blocks_.size());
  for (const Block& b : blocks_) sizes.push_back(b.size);
  return sizes;
}

std::vector<int> BlockPattern::block_of_row() const {
  std::vector<int> block_of(num_rows_);
  for (int b = 0; b < num_blocks(); ++b) {
    for (int k = 0; k < blocks_[b].size; ++k) block_of[blocks_[b].position + k] = b;
  }
  return block_of;
}

SymmetricCsc BlockPattern::expand() const {
  // Lower triangle of the dense-block matrix, column by column: the rows of column c are the
  // rows of its own block at or below c, then every row of each neighbouring block below.
  SymmetricCsc a;
  a.n = num_rows_;
  a.col_ptr.assign(a.n + 1, 0);
  std::vector<int> degree(a.n, 0);  // off-diagonal entries per row of the full matrix
  for (int b = 0; b < num_blocks(); ++b) {
    int nbr_rows = 0;
    for (int nb : neighbors(b)) nbr_rows += blocks_[nb].size;
    for (int k = 0; k < blocks_[b].size; ++k) degree[blocks_[b].position + k] = blocks_[b].size - 1 + nbr_rows;
  }
  for (int b = 0; b < num_blocks(); ++b) {
    const Block& blk = blocks_[b];
    for (int c = blk.position; c < blk.position + blk.size; ++c) {
      for (int r = c; r < blk.position + blk.size; ++r) {
        a.row_idx.push_back(r);
        a.values.push_back(r == c ? 1.0 + degree[c] : -1.0);
      }
      for (int nb : neighbors(b)) {
        if (nb < b) continue;
        for (int k = 0; k < blocks_[nb].size; ++k) {
          a.row_idx.push_back(blocks_[nb].position + k);
          a.values.push_back(-1.0);
        }
      }
      a.col_ptr[c + 1] = static_cast<int>(a.row_idx.size());
    }
  }
  return a;
}

}  // namespace ldlpgs
