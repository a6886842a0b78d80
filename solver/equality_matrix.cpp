// H_0 = J_0 W J_0^T over the equality blocks. Two blocks couple where they share a velocity
// block c, through J_xc W_c J_yc^T: the constraint graph's edge is the shared body (the talk).
// Each such product is precomputed as a list of positions in the CSC values, so assembling is
// a sweep of small dense products with no search.
#include "ldlpgs/solver/equality_matrix.h"

#include <algorithm>
#include <cassert>

namespace ldlpgs {

EqualityMatrix::EqualityMatrix(const System& structure) {
  std::vector<int> sizes;  // rows of each equality block (size equality blocks)
  for (int k = 0; k < static_cast<int>(structure.blocks.size()); ++k) {
    if (!structure.blocks[k].in_factor()) continue;
    system_block_.push_back(k);
    sizes.push_back(structure.blocks[k].size);
  }
  // incident[c] = the (block, side) pairs touching column c, blocks ascending
  std::vector<std::vector<std::pair<int, int>>> incident(structure.num_columns);
  for (int k : system_block_) {
    const RowBlock& b = structure.blocks[k];
    if (b.column_a >= 0) incident[b.column_a].push_back({k, 0});
    if (b.column_b >= 0) incident[b.column_b].push_back({k, 1});
  }
  std::vector<int> eq_index(structure.blocks.size(), -1);  // equality block of each System block (size num_blocks)
  for (int e = 0; e < std::ssize(system_block_); ++e) eq_index[system_block_[e]] = e;
  // The pattern by blocks: an edge for every product of two blocks, each coupling dense, so that
  // H_0's CSC is BlockPattern::expand's and an entry's place is computed, not searched for.
  // (Triplets and a binary search per entry were a fifth of `ldlpgs spy` on a 1000-arm star.)
  std::vector<std::pair<int, int>> edges;
  int64_t num_entries = 0;
  for (int c = 0; c < structure.num_columns; ++c) {
    const auto& inc = incident[c];
    for (size_t p = 0; p < inc.size(); ++p)
      for (size_t q = p; q < inc.size(); ++q) {
        Product prod{inc[p].first, inc[q].first, inc[p].second, inc[q].second, c, num_entries};
        products_.push_back(prod);
        num_entries += int64_t{structure.blocks[prod.x].size} * structure.blocks[prod.y].size;
        if (prod.x != prod.y) edges.emplace_back(eq_index[prod.x], eq_index[prod.y]);
      }
  }
  blocks_ = BlockPattern(sizes, graph_from_edges(static_cast<int>(sizes.size()), edges));
  edges = {};
  h_ = blocks_.expand();
  std::fill(h_.values.begin(), h_.values.end(), 0.0);
  for (int j = 0; j < h_.n; ++j) diagonal_.push_back(h_.col_ptr[j]);  // expand puts the diagonal first
  for (int k : system_block_)
    for (int r = 0; r < structure.blocks[k].size; ++r) {
      system_row_.push_back(structure.blocks[k].position + r);
      system_block_of_row_.push_back(k);
    }
  // Column j of block X holds X's rows j.. first, then each neighbour Y > X's rows, Y ascending:
  // below[a] = the rows before neighbour graph.adj[a]'s in X's columns, past X's own
  // (size 2 edges; only neighbours above X are used).
  const Graph& graph = blocks_.graph();
  std::vector<int> below(graph.adj.size(), 0);
  for (int x = 0; x < graph.n; ++x) {
    int rows = 0;
    for (int a = graph.ptr[x]; a < graph.ptr[x + 1]; ++a) {
      if (graph.adj[a] < x) continue;
      below[a] = rows;
      rows += sizes[graph.adj[a]];
    }
  }
  index_.resize(num_entries);
  for (const Product& prod : products_) {
    const int x = eq_index[prod.x], y = eq_index[prod.y];  // x <= y: products_ pair blocks in System order
    const int sx = sizes[x], sy = sizes[y], px = blocks_.block(x).position;
    int64_t* idx = index_.data() + prod.index;  // entry (rx, ry) at idx[rx * sy + ry]
    if (x == y) {  // the lower half of X's diagonal block, in column px + ry: rows px + ry..
      for (int rx = 0; rx < sx; ++rx)
        for (int ry = 0; ry < sy; ++ry) idx[rx * sy + ry] = ry > rx ? -1 : h_.col_ptr[px + ry] + (rx - ry);
      continue;
    }
    const auto nbrs = graph.neighbors(x);
    const int64_t a = std::lower_bound(nbrs.begin(), nbrs.end(), y) - nbrs.begin() + graph.ptr[x];
    assert(a < graph.ptr[x + 1] && graph.adj[a] == y);
    for (int rx = 0; rx < sx; ++rx) {  // row y's ry of column px + rx
      const int64_t first = h_.col_ptr[px + rx] + (sx - rx) + below[a];
      for (int ry = 0; ry < sy; ++ry) idx[rx * sy + ry] = first + ry;
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
  for (int r = 0; r < h_.n; ++r)
    target[diagonal[r]] *= 1 + system.compliance[system_row_[r]] + system.blocks[system_block_of_row_[r]].regularization;
}

void EqualityMatrix::remap(std::span<const int32_t> map, std::vector<int64_t>* index,
                           std::vector<int64_t>* diagonal) const {
  index->resize(index_.size());
  for (size_t e = 0; e < index_.size(); ++e) (*index)[e] = index_[e] < 0 ? -1 : map[index_[e]];
  diagonal->resize(diagonal_.size());
  for (size_t r = 0; r < diagonal_.size(); ++r) (*diagonal)[r] = map[diagonal_[r]];
}

}  // namespace ldlpgs
