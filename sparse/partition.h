#pragma once
// Block partitions of the rows: which consecutive rows form one block.
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// Blocks of `size` rows; the last block takes the remainder when size does not divide n.
std::vector<int> partition_uniform(int n, int size);

// Groups consecutive rows whose sparsity patterns (diagonal included) are identical, as
// supernodal codes detect identical columns; a block never exceeds max_size rows.
std::vector<int> partition_auto(const SymmetricCsc& a, int max_size = 6);

// Refines `blocks` (sizes summing to a.n): each block is cut into the maximal runs of
// consecutive rows whose patterns of nonzero values (diagonal included, exact zeros ignored:
// without_zeros) are identical, as partition_auto does, but never across the given blocks' edges.
// A constraint whose coupling blocks are partly zero (a ball joint at a body's centre couples its
// translation rows only) becomes several sub-blocks, which the block orderings can then eliminate
// apart, as scalar AMD and METIS do (papers/orderings.md, "Block partitions that see inside
// blocks"). Throws ArgumentError if the sizes are not positive or do not sum to a.n.
std::vector<int> partition_refine(const SymmetricCsc& a, std::span<const int> blocks);

// Reads a partition file: one positive block size per line, in row order, summing to n.
// Blank lines and lines starting with '#' or '%' are skipped. Throws InputError naming the
// file and line.
std::vector<int> read_partition(const std::string& path, int n);

// The command line's --blocks: "auto", a positive integer (uniform), or a partition file.
std::vector<int> parse_partition(const std::string& spec, const SymmetricCsc& a, int max_size = 6);

}  // namespace ldlpgs
