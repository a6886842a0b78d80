// BlockSparseMatrix from a SymmetricCsc and a partition, on a hand-built case (layout worked out
// from the header's description) and on every test matrix with auto and uniform partitions:
// to_csc() equals the original as a dense matrix and stores exactly the in-block positions, the
// cells of each block column are ordered and tile values(), and each cell's values are the
// original's entries in the row-major layout (diagonal blocks whole and symmetric).
#include "ldlpgs/sparse/block_matrix.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

using Sizes = std::vector<int>;
using Position = std::pair<int, int>;  // (row, col), row >= col

using testing::dense;
using testing::expect_valid;
using testing::stored;
using testing::test_matrices;

// Brute force from a and the sizes alone: block of each row, block adjacency as a boolean
// matrix (blocks I != J adjacent iff a stores an entry between them).
struct Blocks {
  std::vector<int> of_row, position;
  std::vector<std::vector<bool>> adjacent;
};
Blocks blocks_of(const SymmetricCsc& a, const Sizes& sizes) {
  Blocks b;
  const int nb = static_cast<int>(sizes.size());
  for (int k = 0, pos = 0; k < nb; pos += sizes[k], ++k) {
    b.of_row.insert(b.of_row.end(), sizes[k], k);
    b.position.push_back(pos);
  }
  b.adjacent.assign(nb, std::vector<bool>(nb, false));
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int x = b.of_row[a.row_idx[p]], y = b.of_row[j];
      if (x != y) b.adjacent[x][y] = b.adjacent[y][x] = true;
    }
  }
  return b;
}

// Everything the header promises, each part against a's arrays and the brute-force blocks.
void expect_block_matrix(const SymmetricCsc& a, const Sizes& sizes) {
  const BlockSparseMatrix m(a, sizes);
  const Blocks b = blocks_of(a, sizes);
  const int nb = static_cast<int>(sizes.size());
  ASSERT_EQ(m.num_rows(), a.n);
  ASSERT_EQ(m.pattern().block_sizes(), sizes);
  const Eigen::MatrixXd da = dense(a);

  // Cells of block column j: the diagonal block first, then exactly the adjacent blocks below j,
  // ascending; each cell a (rows of its block) x (columns of j) dense block at its position.
  std::vector<std::pair<int, int>> extents;  // [position, position + area) of every cell
  for (int j = 0; j < nb; ++j) {
    const auto cells = m.column(j);
    std::vector<int> expected_ids = {j};
    for (int i = j + 1; i < nb; ++i) {
      if (b.adjacent[i][j]) expected_ids.push_back(i);
    }
    std::vector<int> ids;
    for (const Cell& cell : cells) ids.push_back(cell.block_id);
    ASSERT_EQ(ids, expected_ids) << "block column " << j;
    for (const Cell& cell : cells) {
      const int rows = sizes[cell.block_id], cols = sizes[j];
      extents.emplace_back(cell.position, cell.position + rows * cols);
      // Row-major values, equal to a's entries (zero where a stores none); for the diagonal
      // block this covers both triangles, so it is stored whole and symmetric.
      for (int lr = 0; lr < rows; ++lr) {
        for (int lc = 0; lc < cols; ++lc) {
          const int r = b.position[cell.block_id] + lr, c = b.position[j] + lc;
          ASSERT_EQ(m.values()[cell.position + lr * cols + lc], da(r, c))
              << "cell (" << cell.block_id << "," << j << "), local (" << lr << "," << lc << ")";
        }
      }
    }
  }
  // The cells tile values(): sorted by position, each starts where the previous ended.
  std::sort(extents.begin(), extents.end());
  int end = 0;
  for (auto [first, last] : extents) {
    ASSERT_EQ(first, end) << "gap or overlap in values()";
    end = last;
  }
  EXPECT_EQ(static_cast<size_t>(end), m.values().size());

  // to_csc(): a valid lower triangle equal to a as a dense matrix (so every original entry kept
  // with its value, zero everywhere else), storing exactly the positions of the stored blocks.
  const SymmetricCsc c = m.to_csc();
  ASSERT_EQ(c.n, a.n);
  expect_valid(c);
  EXPECT_TRUE(dense(c) == da) << "to_csc() differs from the original";
  const std::set<Position> sa = stored(a), sc = stored(c);
  EXPECT_TRUE(std::includes(sc.begin(), sc.end(), sa.begin(), sa.end()))
      << "an original entry is missing";
  std::set<Position> in_blocks;
  for (int col = 0; col < a.n; ++col) {
    for (int row = col; row < a.n; ++row) {
      const int x = b.of_row[row], y = b.of_row[col];
      if (x == y || b.adjacent[x][y]) in_blocks.insert({row, col});
    }
  }
  EXPECT_EQ(sc, in_blocks);
}

TEST(BlockSparseMatrix, HandBuiltLayout) {
  // 5 x 5 in blocks {0,1} {2,3,4}: lower entries (0,0)=1 (1,0)=2 (1,1)=3 (3,0)=4 (4,1)=5
  // (2,2)=6 (4,2)=7 (4,4)=8. Layout (header): block column 0 = diagonal cell 2x2 at 0, then
  // cell of block 1 (3 rows x 2 cols) at 4; block column 1 = diagonal cell 3x3 at 10.
  const SymmetricCsc a = csc_from_triplets(
      5, std::vector<Triplet>{{0, 0, 1}, {1, 0, 2}, {1, 1, 3}, {3, 0, 4}, {4, 1, 5}, {2, 2, 6},
                              {4, 2, 7}, {4, 4, 8}});
  const BlockSparseMatrix m(a, Sizes{2, 3});
  ASSERT_EQ(m.column(0).size(), 2u);
  ASSERT_EQ(m.column(1).size(), 1u);
  EXPECT_EQ(m.column(0)[0].block_id, 0);
  EXPECT_EQ(m.column(0)[0].position, 0);
  EXPECT_EQ(m.column(0)[1].block_id, 1);
  EXPECT_EQ(m.column(0)[1].position, 4);
  EXPECT_EQ(m.column(1)[0].block_id, 1);
  EXPECT_EQ(m.column(1)[0].position, 10);
  // Diagonal cell 0: [1 2; 2 3]. Cell (1,0), rows 2..4 x cols 0..1: [0 0; 4 0; 0 5].
  // Diagonal cell 1, rows/cols 2..4: [6 0 7; 0 0 0; 7 0 8].
  EXPECT_EQ(m.values(), (std::vector<double>{1, 2, 2, 3, 0, 0, 4, 0, 0, 5, 6, 0, 7, 0, 0, 0, 7,
                                             0, 8}));
  expect_block_matrix(a, Sizes{2, 3});
}

TEST(BlockSparseMatrix, ValuesAreWritable) {
  // values() is the storage to_csc() reads: a change shows up at the position it belongs to.
  const SymmetricCsc a =
      csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {2, 0, 2}, {1, 1, 3}, {2, 2, 4}});
  BlockSparseMatrix m(a, Sizes{2, 1});
  // Block column 0: diagonal 2x2 at 0 (rows 0,1), then block 1 (row 2) x cols 0,1 at 4.
  ASSERT_EQ(m.column(0)[1].position, 4);
  m.values()[5] = -9;  // row 2, column 1: not in a, but inside a stored block
  const Eigen::MatrixXd d = dense(m.to_csc());
  EXPECT_EQ(d(2, 1), -9);
  EXPECT_EQ(d(2, 0), 2);
}

TEST(BlockSparseMatrix, CheckerCanFail) {
  // The brute-force block adjacency must see the entry that couples two blocks, and the dense
  // comparison must see a changed value.
  const SymmetricCsc a =
      csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {2, 0, 2}, {1, 1, 3}, {2, 2, 4}});
  const Blocks b = blocks_of(a, Sizes{1, 1, 1});
  EXPECT_TRUE(b.adjacent[0][2]);
  EXPECT_FALSE(b.adjacent[0][1]);
  BlockSparseMatrix m(a, Sizes{1, 1, 1});
  m.values()[0] += 1;
  EXPECT_FALSE(dense(m.to_csc()) == dense(a));
}

TEST(BlockSparseMatrix, SingleRowBlocksAreTheMatrixItself) {
  const SymmetricCsc& a = test_matrices().front().a;
  const SymmetricCsc c = BlockSparseMatrix(a, Sizes(a.n, 1)).to_csc();
  EXPECT_EQ(c.col_ptr, a.col_ptr);
  EXPECT_EQ(c.row_idx, a.row_idx);
  EXPECT_EQ(c.values, a.values);
}

TEST(BlockSparseMatrix, MissingDiagonalIsAZeroInTheDiagonalBlock) {
  // Row 1 has no stored diagonal: the dense block holds a zero there, and to_csc() stores it.
  const SymmetricCsc a = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1}, {1, 0, 5}, {2, 2, 4}});
  expect_block_matrix(a, Sizes{2, 1});
  expect_block_matrix(a, Sizes{3});
}

TEST(BlockSparseMatrix, EveryTestMatrixAutoAndUniform) {
  ASSERT_GE(test_matrices().size(), 11u);
  for (const auto& [name, a] : test_matrices()) {
    for (const auto& [how, sizes] : {std::pair<std::string, Sizes>{"auto", partition_auto(a)},
                                     {"uniform 3", partition_uniform(a.n, 3)}}) {
      SCOPED_TRACE(name + ", " + how);
      expect_block_matrix(a, sizes);
    }
  }
}

}  // namespace
}  // namespace ldlpgs
