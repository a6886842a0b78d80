// H_0 = J_0 W J_0^T over the equality blocks. Two blocks couple where they share a velocity
// block c, through J_xc W_c J_yc^T: the constraint graph's edge is the shared body (the talk).
// Each such product is precomputed as a list of positions in the CSC values, so assembling is
// a sweep of small dense products with no search.
#include "ldlpgs/solver/equality_matrix.h"

#include <algorithm>
#include <cassert>

namespace ldlpgs {

EqualityMatrix::EqualityMatrix(const System& structure) {
  std::vector<int> eq_position(structure.blocks.size(), -1);  // first row in H_0 (size num_blocks)
  std::vector<int> sizes;
  int n = 0;
  for (int k = 0; k < static_cast<int>(structure.blocks.size()); ++k) {
    if (!structure.blocks[k].equality) continue;
    system_block_.push_back(k);
    sizes.push_back(structure.blocks[k].size);
    eq_position[k] = n;
    n += structure.blocks[k].size;
  }
  // incident[c] = the (block, side) pairs touching column c, blocks ascending
  std::vector<std::vector<std::pair<int, int>>> incident(structure.num_columns);
  for (int k : system_block_) {
    const RowBlock& b = structure.blocks[k];
    if (b.column_a >= 0) incident[b.column_a].push_back({k, 0});
    if (b.column_b >= 0) incident[b.column_b].push_back({k, 1});
  }
  std::vector<Triplet> entries;
  for (int c = 0; c < structure.num_columns; ++c) {
    const auto& inc = incident[c];
    for (size_t p = 0; p < inc.size(); ++p)
      for (size_t q = p; q < inc.size(); ++q) {
        Product prod{inc[p].first, inc[q].first, inc[p].second, inc[q].second, c, 0};
        products_.push_back(prod);
        const RowBlock &bx = structure.blocks[prod.x], &by = structure.blocks[prod.y];
        for (int rx = 0; rx < bx.size; ++rx)
          for (int ry = 0; ry < by.size; ++ry) entries.push_back({eq_position[prod.x] + rx, eq_position[prod.y] + ry, 0.0});
      }
  }
  h_ = csc_from_triplets(n, entries);
  for (int j = 0; j < n; ++j) {  // rows ascending within a column: the diagonal comes first
    assert(h_.row_idx[h_.col_ptr[j]] == j);
    diagonal_.push_back(h_.col_ptr[j]);
  }
  for (int k : system_block_)
    for (int r = 0; r < structure.blocks[k].size; ++r) system_row_.push_back(structure.blocks[k].position + r);
  blocks_ = BlockPattern::from_scalar(h_, sizes);
  // positions of each product's entries in the lower triangle
  for (Product& prod : products_) {
    prod.index = static_cast<int64_t>(index_.size());
    const RowBlock &bx = structure.blocks[prod.x], &by = structure.blocks[prod.y];
    for (int rx = 0; rx < bx.size; ++rx)
      for (int ry = 0; ry < by.size; ++ry) {
        const int gx = eq_position[prod.x] + rx, gy = eq_position[prod.y] + ry;
        if (prod.x == prod.y && gx < gy) {  // a diagonal block's upper half: its mirror is stored
          index_.push_back(-1);
          continue;
        }
        const int row = std::max(gx, gy), col = std::min(gx, gy);
        const auto first = h_.row_idx.begin() + h_.col_ptr[col], last = h_.row_idx.begin() + h_.col_ptr[col + 1];
        const auto it = std::lower_bound(first, last, row);
        assert(it != last && *it == row);
        index_.push_back(it - h_.row_idx.begin());
      }
  }
}

void EqualityMatrix::assemble(const System& system) {
  RowCache rows;
  rows.update(system);
  std::fill(h_.values.begin(), h_.values.end(), 0.0);
  assemble(system, rows, h_.values, index_, diagonal_);
}

// Each entry (rx, ry) of a product is J_x,rx . (W_c J_y,ry^T): the row cache holds W J^T per row
// and side, computed once per step, so an entry costs 6 multiplications (recomputing W_c J^T per
// product cost 36 per row and was a fifth of a whole step on a chain: callgrind, chain of 10).
void EqualityMatrix::assemble(const System& system, const RowCache& rows, std::span<double> target,
                              std::span<const int64_t> index, std::span<const int64_t> diagonal) const {
  for (const Product& prod : products_) {
    const RowBlock &bx = system.blocks[prod.x], &by = system.blocks[prod.y];
    const double* jx = prod.side_x == 0 ? system.cell_a(prod.x) : system.cell_b(prod.x);
    const int64_t* idx = index.data() + prod.index;
    for (int ry = 0; ry < by.size; ++ry) {
      const double* wj = rows.wjt.data() + 12 * static_cast<size_t>(by.position + ry) + 6 * prod.side_y;
      for (int rx = 0; rx < bx.size; ++rx) {
        const int64_t at = idx[rx * by.size + ry];
        if (at < 0) continue;
        const double* j = jx + 6 * rx;
        target[at] += j[0] * wj[0] + j[1] * wj[1] + j[2] * wj[2] + j[3] * wj[3] + j[4] * wj[4] + j[5] * wj[5];
      }
    }
  }
  for (int r = 0; r < h_.n; ++r) target[diagonal[r]] *= 1 + system.compliance[system_row_[r]];
}

void EqualityMatrix::remap(std::span<const int32_t> map, std::vector<int64_t>* index,
                           std::vector<int64_t>* diagonal) const {
  index->resize(index_.size());
  for (size_t e = 0; e < index_.size(); ++e) (*index)[e] = index_[e] < 0 ? -1 : map[index_[e]];
  diagonal->resize(diagonal_.size());
  for (size_t r = 0; r < diagonal_.size(); ++r) (*diagonal)[r] = map[diagonal_[r]];
}

}  // namespace ldlpgs
