#include "ldlpgs/sparse/block_matrix.h"

#include <algorithm>
#include <cassert>

namespace ldlpgs {

BlockSparseMatrix::BlockSparseMatrix(const SymmetricCsc& a, std::span<const int> block_sizes)
    : pattern_(BlockPattern::from_scalar(a, block_sizes)) {
  const int nb = pattern_.num_blocks();
  // Layout: block columns in order; in each, the diagonal cell then the cells below it.
  col_ptr_.assign(nb + 1, 0);
  int position = 0;
  for (int j = 0; j < nb; ++j) {
    const int cols = pattern_.block(j).size;
    cells_.push_back({j, position});
    position += cols * cols;
    for (int i : pattern_.neighbors(j)) {
      if (i < j) continue;
      cells_.push_back({i, position});
      position += pattern_.block(i).size * cols;
    }
    col_ptr_[j + 1] = static_cast<int>(cells_.size());
  }
  values_.assign(position, 0.0);

  const std::vector<int> block_of = pattern_.block_of_row();
  for (int c = 0; c < a.n; ++c) {
    const int bj = block_of[c];
    const Block& col_block = pattern_.block(bj);
    std::span<const Cell> cells = column(bj);
    for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p) {
      const int r = a.row_idx[p], bi = block_of[r];
      auto cell = std::lower_bound(cells.begin(), cells.end(), bi,
                                   [](const Cell& x, int b) { return x.block_id < b; });
      assert(cell != cells.end() && cell->block_id == bi);
      const int local_r = r - pattern_.block(bi).position, local_c = c - col_block.position;
      values_[cell->position + local_r * col_block.size + local_c] = a.values[p];
      // The diagonal block is stored whole: mirror its strictly lower entries.
      if (bi == bj && local_r != local_c) {
        values_[cell->position + local_c * col_block.size + local_r] = a.values[p];
      }
    }
  }
}

SymmetricCsc BlockSparseMatrix::to_csc() const {
  SymmetricCsc a;
  a.n = pattern_.num_rows();
  a.col_ptr.assign(a.n + 1, 0);
  for (int j = 0; j < pattern_.num_blocks(); ++j) {
    const Block& cb = pattern_.block(j);
    for (int lc = 0; lc < cb.size; ++lc) {
      for (const Cell& cell : column(j)) {
        const Block& rb = pattern_.block(cell.block_id);
        for (int lr = (cell.block_id == j ? lc : 0); lr < rb.size; ++lr) {
          a.row_idx.push_back(rb.position + lr);
          a.values.push_back(values_[cell.position + lr * cb.size + lc]);
        }
      }
      a.col_ptr[cb.position + lc + 1] = static_cast<int>(a.row_idx.size());
    }
  }
  return a;
}

}  // namespace ldlpgs
