// Partitions: uniform sizes, automatic grouping of identical rows (checked on a hand-built matrix
// and against a brute-force definition on every test matrix), partition files and --blocks.
#include "ldlpgs/sparse/partition.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/error.h"
#include "tests/support/temp_files.h"
#include "ldlpgs/sparse/matrix_market.h"

namespace ldlpgs {
namespace {

namespace fs = std::filesystem;
using Sizes = std::vector<int>;

std::string temp_file(const std::string& content) { return testing::temp_file("partition.txt", content); }

// The message of the InputError f throws (a test failure if it throws none).
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

// A symmetric matrix with the given off-diagonal edges (0-based, either order) and diagonal
// entries on the rows listed (a missing diagonal must not change anything).
SymmetricCsc matrix(int n, const std::vector<std::pair<int, int>>& edges,
                    const std::vector<int>& diagonal) {
  std::vector<Triplet> t;
  for (auto [i, j] : edges) t.push_back({i, j, -1.0});
  for (int r : diagonal) t.push_back({r, r, 10.0});
  return csc_from_triplets(n, t);
}

std::vector<int> all_rows(int n) {
  std::vector<int> r(n);
  std::iota(r.begin(), r.end(), 0);
  return r;
}

// --- partition_uniform ---------------------------------------------------------------------

TEST(PartitionUniform, Divides) { EXPECT_EQ(partition_uniform(9, 3), (Sizes{3, 3, 3})); }

TEST(PartitionUniform, Remainder) {
  EXPECT_EQ(partition_uniform(10, 3), (Sizes{3, 3, 3, 1}));
  EXPECT_EQ(partition_uniform(48, 7), (Sizes{7, 7, 7, 7, 7, 7, 6}));
}

TEST(PartitionUniform, BlockLargerThanMatrix) { EXPECT_EQ(partition_uniform(2, 5), (Sizes{2})); }

TEST(PartitionUniform, EmptyMatrix) { EXPECT_EQ(partition_uniform(0, 3), Sizes{}); }

TEST(PartitionUniform, SizeZeroIsAnError) {
  EXPECT_THROW(partition_uniform(10, 0), InputError);
  EXPECT_THROW(partition_uniform(10, -1), InputError);
}

// --- partition_auto on a matrix small enough to reason about ---------------------------------

// Rows 0,1,2: a clique, each also coupled to 5 -> row sets {0,1,2,5}.
// Rows 3,4: coupled to each other only -> {3,4}; row 3 has no stored diagonal.
// Row 5: {0,1,2,5}, the same set as rows 0-2 but not next to them, so alone.
// Rows 6..9: a clique of 4 -> {6,7,8,9}.
SymmetricCsc hand_built() {
  return matrix(10,
                {{1, 0}, {2, 0}, {2, 1}, {5, 0}, {5, 1}, {5, 2}, {4, 3}, {7, 6}, {8, 6}, {9, 6},
                 {8, 7}, {9, 7}, {9, 8}},
                {0, 1, 2, 4, 5, 6, 7, 8, 9});
}

TEST(PartitionAuto, HandBuilt) { EXPECT_EQ(partition_auto(hand_built()), (Sizes{3, 2, 1, 4})); }

TEST(PartitionAuto, HandBuiltRunsSplitAtMaxSize) {
  EXPECT_EQ(partition_auto(hand_built(), 3), (Sizes{3, 2, 1, 3, 1}));
  EXPECT_EQ(partition_auto(hand_built(), 2), (Sizes{2, 1, 2, 1, 2, 2}));
  EXPECT_EQ(partition_auto(hand_built(), 1), Sizes(10, 1));
}

TEST(PartitionAuto, SameNeighboursButNotCoupledAreNotMerged) {
  // Rows 0 and 1 both touch only row 2, but row 0's set {0,2} differs from row 1's {1,2}.
  EXPECT_EQ(partition_auto(matrix(3, {{2, 0}, {2, 1}}, all_rows(3))), (Sizes{1, 1, 1}));
}

TEST(PartitionAuto, DiagonalMatrixIsAllSingletons) {
  EXPECT_EQ(partition_auto(matrix(4, {}, all_rows(4))), (Sizes{1, 1, 1, 1}));
  EXPECT_EQ(partition_auto(matrix(4, {}, {})), (Sizes{1, 1, 1, 1}));
}

TEST(PartitionAuto, DenseMatrixIsCutIntoMaxSize) {
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < 14; ++i) {
    for (int j = 0; j < i; ++j) edges.emplace_back(i, j);
  }
  EXPECT_EQ(partition_auto(matrix(14, edges, {})), (Sizes{6, 6, 2}));
  EXPECT_EQ(partition_auto(matrix(14, edges, {}), 14), (Sizes{14}));
}

TEST(PartitionAuto, MaxSizeBelowOneIsAnError) {
  EXPECT_THROW(partition_auto(hand_built(), 0), InputError);
  EXPECT_THROW(partition_auto(hand_built(), -3), InputError);
}

// --- partition_auto against a brute-force definition on every test matrix -------------------

// Row r's column set in the full symmetric pattern, diagonal included, built straight from the
// stored lower triangle (no library helper in between).
std::vector<std::set<int>> row_sets(const SymmetricCsc& a) {
  std::vector<std::set<int>> s(a.n);
  for (int j = 0; j < a.n; ++j) {
    s[j].insert(j);
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      s[a.row_idx[p]].insert(j);
      s[j].insert(a.row_idx[p]);
    }
  }
  return s;
}

// The definition: blocks cover the rows in order, every block holds rows with identical sets
// and at most max_size of them, and two neighbouring blocks are cut apart only where the rows
// differ or where the first block is full (so each run is cut max_size, max_size, ..., rest).
// Returns the first violation, empty if none.
std::string auto_partition_violation(const std::vector<std::set<int>>& sets, const Sizes& blocks,
                                     int max_size) {
  const int n = static_cast<int>(sets.size());
  const int sum = std::accumulate(blocks.begin(), blocks.end(), 0);
  if (sum != n) return "sizes sum to " + std::to_string(sum) + ", not " + std::to_string(n);
  int start = 0;
  for (size_t b = 0; b < blocks.size(); ++b) {
    const std::string block = "block " + std::to_string(b) + " (rows " + std::to_string(start) +
                              ".." + std::to_string(start + blocks[b] - 1) + ")";
    if (blocks[b] < 1 || blocks[b] > max_size) return block + ": size out of 1..max_size";
    for (int r = start + 1; r < start + blocks[b]; ++r) {
      if (sets[r - 1] != sets[r]) return block + ": rows " + std::to_string(r - 1) + " and " +
                                         std::to_string(r) + " differ";
    }
    const int next = start + blocks[b];
    if (next < n && sets[next - 1] == sets[next] && blocks[b] != max_size) {
      return block + ": could take row " + std::to_string(next);
    }
    start = next;
  }
  return {};
}

TEST(PartitionAuto, MatchesBruteForceOnEveryTestMatrix) {
  int checked = 0;
  for (const auto& file : fs::directory_iterator(LDLPGS_MATRICES)) {
    if (file.path().extension() != ".mtx" || file.path().filename() == "Pd.mtx") continue;
    const SymmetricCsc a = read_matrix_market(file.path().string());
    const auto sets = row_sets(a);
    for (int max_size : {1, 2, 3, 6, 7, 1000}) {
      EXPECT_EQ(auto_partition_violation(sets, partition_auto(a, max_size), max_size), "")
          << file.path().filename() << ", max_size " << max_size;
    }
    ++checked;
  }
  EXPECT_GE(checked, 11);
}

TEST(PartitionAuto, BruteForceCheckCanFail) {
  // The checker must reject wrong answers, or the test above proves nothing.
  const auto sets = row_sets(hand_built());
  EXPECT_EQ(auto_partition_violation(sets, {3, 2, 1, 4}, 6), "");
  EXPECT_NE(auto_partition_violation(sets, {3, 2, 1, 3, 1}, 6).find("could take row 9"),
            std::string::npos);
  EXPECT_NE(auto_partition_violation(sets, {3, 3, 4}, 6).find("differ"), std::string::npos);
  EXPECT_NE(auto_partition_violation(sets, {3, 2, 1, 4}, 3).find("size"), std::string::npos);
  EXPECT_NE(auto_partition_violation(sets, {3, 2, 1, 3}, 6).find("sum"), std::string::npos);
}

TEST(PartitionAuto, KnownResultsOnCollectionMatrices) {
  // bcsstk02 is completely dense: one run of 66 identical rows.
  const SymmetricCsc dense = read_matrix_market(std::string(LDLPGS_MATRICES) + "/bcsstk02.mtx");
  EXPECT_EQ(partition_auto(dense), Sizes(11, 6));
  EXPECT_EQ(partition_auto(dense, 8), (Sizes{8, 8, 8, 8, 8, 8, 8, 8, 2}));
  // bcsstk01 has 6 unknowns per node, but its stored pattern does not show it: row 0 couples to
  // 4, 5, 6, ... and not to rows 1-3 of its own node, so no two consecutive rows are identical
  // (checked separately with a script) and auto finds only single rows.
  const SymmetricCsc k01 = read_matrix_market(std::string(LDLPGS_MATRICES) + "/bcsstk01.mtx");
  EXPECT_EQ(partition_auto(k01), Sizes(48, 1));
}

// --- partition_refine against a brute-force definition on random block matrices -------------

// Row r's column set counting only nonzero values (diagonal always included), from the stored
// lower triangle with no library helper in between.
std::vector<std::set<int>> nonzero_row_sets(const SymmetricCsc& a) {
  std::vector<std::set<int>> s(a.n);
  for (int j = 0; j < a.n; ++j) {
    s[j].insert(j);
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      if (a.values[p] == 0.0) continue;
      s[a.row_idx[p]].insert(j);
      s[j].insert(a.row_idx[p]);
    }
  }
  return s;
}

// The definition: every refined block lies inside one given block, its rows have identical sets,
// and two neighbouring refined blocks inside one given block could not be merged (their facing
// rows differ). Returns the first violation, empty if none.
std::string refine_violation(const std::vector<std::set<int>>& sets, const Sizes& given, const Sizes& refined) {
  const int n = static_cast<int>(sets.size());
  const int sum = std::accumulate(refined.begin(), refined.end(), 0);
  if (sum != n) return "sizes sum to " + std::to_string(sum) + ", not " + std::to_string(n);
  std::set<int> given_starts, refined_starts;
  for (int b = 0, start = 0; b < static_cast<int>(given.size()); start += given[b++]) given_starts.insert(start);
  for (int b = 0, start = 0; b < static_cast<int>(refined.size()); start += refined[b++]) {
    if (refined[b] < 1) return "block " + std::to_string(b) + " is empty";
    refined_starts.insert(start);
  }
  for (int start : given_starts) {
    if (!refined_starts.count(start)) return "given block at row " + std::to_string(start) + " is merged into another";
  }
  for (int r = 1; r < n; ++r) {
    const bool cut = refined_starts.count(r) > 0;
    if (!cut && sets[r - 1] != sets[r]) return "rows " + std::to_string(r - 1) + " and " + std::to_string(r) + " differ";
    if (cut && !given_starts.count(r) && sets[r - 1] == sets[r]) return "could merge at row " + std::to_string(r);
  }
  return {};
}

// A random symmetric block matrix: blocks of 1..6 rows, each pair of blocks coupled with
// probability 0.3, every coupled or diagonal block stored dense, and zeros planted as a
// mechanism's exports have them: whole rows of a coupling block (a row that does not touch the
// shared body), and scattered single entries.
struct BlockMatrix {
  SymmetricCsc a;
  Sizes blocks;
};
BlockMatrix random_block_matrix(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  BlockMatrix m;
  int n = 0;
  std::vector<int> start;
  const int num_blocks = 2 + static_cast<int>(rng() % 12);
  for (int b = 0; b < num_blocks; ++b) {
    m.blocks.push_back(1 + static_cast<int>(rng() % 6));
    start.push_back(n);
    n += m.blocks.back();
  }
  std::vector<Triplet> t;
  for (int bj = 0; bj < num_blocks; ++bj) {
    for (int bi = bj; bi < num_blocks; ++bi) {
      if (bi != bj && u(rng) > 0.3) continue;
      std::vector<uint8_t> zero_row(m.blocks[bi]);  // rows of bi planted all-zero in this block
      for (auto& z : zero_row) z = bi != bj && u(rng) < 0.4;
      for (int j = start[bj]; j < start[bj] + m.blocks[bj]; ++j) {
        for (int i = std::max(j, start[bi]); i < start[bi] + m.blocks[bi]; ++i) {
          const bool zero = i != j && (zero_row[i - start[bi]] || u(rng) < 0.1);
          t.push_back({i, j, zero ? 0.0 : (i == j ? 10.0 : -1.0)});
        }
      }
    }
  }
  m.a = csc_from_triplets(n, t);
  return m;
}

TEST(PartitionRefine, HandBuiltPlantedZeros) {
  // Blocks {3, 2}: rows 0-2 all coupled, rows 3-4 coupled; row 0 alone couples to row 3 (the
  // entries (3,1), (3,2), (4,*) of the coupling block are stored zeros).
  const std::vector<Triplet> t = {{0, 0, 4.0}, {1, 0, 1.0}, {2, 0, 1.0}, {1, 1, 4.0}, {2, 1, 1.0}, {2, 2, 4.0}, {3, 0, 1.0},
          {3, 1, 0.0}, {3, 2, 0.0}, {4, 0, 0.0}, {4, 1, 0.0}, {4, 2, 0.0}, {3, 3, 4.0}, {4, 3, 1.0}, {4, 4, 4.0}};
  const SymmetricCsc a = csc_from_triplets(5, t);
  EXPECT_EQ(partition_refine(a, Sizes{3, 2}), (Sizes{1, 2, 1, 1}));
  // Never merged across the given blocks, even where rows match (one block per row stays so).
  EXPECT_EQ(partition_refine(a, Sizes{1, 1, 1, 1, 1}), (Sizes{1, 1, 1, 1, 1}));
}

TEST(PartitionRefine, MatchesBruteForceOnRandomBlockMatrices) {
  int split = 0;
  for (uint32_t seed = 1; seed <= 300; ++seed) {
    const BlockMatrix m = random_block_matrix(seed);
    const Sizes refined = partition_refine(m.a, m.blocks);
    EXPECT_EQ(refine_violation(nonzero_row_sets(m.a), m.blocks, refined), "") << "seed " << seed;
    split += refined.size() > m.blocks.size();
  }
  EXPECT_GT(split, 200);  // the planted zeros split blocks in most matrices
}

TEST(PartitionRefine, BruteForceCheckCanFail) {
  // The checker must reject wrong answers: a merged pair, a needless cut, a cut across blocks.
  const BlockMatrix m = random_block_matrix(7);
  const auto sets = nonzero_row_sets(m.a);
  const Sizes right = partition_refine(m.a, m.blocks);
  ASSERT_EQ(refine_violation(sets, m.blocks, right), "");
  ASSERT_GT(right.size(), m.blocks.size());
  int tried = 0;
  for (size_t b = 0; b + 1 < right.size(); ++b) {
    Sizes merged = right;
    merged[b] += merged[b + 1];
    merged.erase(merged.begin() + static_cast<std::ptrdiff_t>(b) + 1);
    EXPECT_NE(refine_violation(sets, m.blocks, merged), "") << "merged " << b;
    ++tried;
  }
  for (size_t b = 0; b < right.size(); ++b) {
    if (right[b] < 2) continue;
    Sizes cut = right;
    cut[b] -= 1;
    cut.insert(cut.begin() + static_cast<std::ptrdiff_t>(b) + 1, 1);
    EXPECT_NE(refine_violation(sets, m.blocks, cut).find("could merge"), std::string::npos) << "cut " << b;
    ++tried;
  }
  EXPECT_GT(tried, 3);
}

TEST(PartitionRefine, SizesNotSummingToTheMatrixAreRefused) {
  const SymmetricCsc a = matrix(4, {{0, 1}}, all_rows(4));
  EXPECT_THROW(partition_refine(a, Sizes{2, 1}), ArgumentError);
  EXPECT_THROW(partition_refine(a, Sizes{2, 0, 2}), ArgumentError);
}

// --- read_partition --------------------------------------------------------------------------

TEST(ReadPartition, GoodFile) {
  const std::string path = temp_file("# blocks of a 10-row matrix\n3\n\n% note\n  4  \n2\r\n1\n");
  EXPECT_EQ(read_partition(path, 10), (Sizes{3, 4, 2, 1}));
}

TEST(ReadPartition, MissingFile) {
  const std::string path = ::testing::TempDir() + "ldlpgs_no_such_partition.txt";
  EXPECT_EQ(error_of([&] { read_partition(path, 10); }), path + ": cannot open file: No such file or directory");
}

// A directory opens on Linux (and reads as empty: blocks summing to 0); /dev/zero has no end of
// line (getline read it forever): both are refused, the second after a megabyte.
TEST(ReadPartition, DirectoryIsRefused) {
  const std::string dir = ::testing::TempDir() + "ldlpgs_a_directory.blocks";
  std::filesystem::create_directories(dir);
  EXPECT_EQ(error_of([&] { read_partition(dir, 10); }), dir + ": cannot read: it is a directory");
}

TEST(ReadPartition, EndlessLineIsRefused) {
  const std::string zero = error_of([&] { read_partition("/dev/zero", 10); });
  EXPECT_EQ(zero.rfind("/dev/zero:1: expected a positive integer block size, got '\\x00\\x00", 0), 0u) << zero;
  const std::string comment = temp_file("# " + std::string((1 << 20) + 10, 'c') + "\n3\n");
  EXPECT_EQ(error_of([&] { read_partition(comment, 3); }), comment + ":1: a line longer than 1 MiB: not a block partition");
}

TEST(ReadPartition, BadSum) {
  const std::string path = temp_file("6\n6\n6\n6\n6\n6\n4\n");
  EXPECT_EQ(error_of([&] { read_partition(path, 48); }),
            path + ": block sizes sum to 40, the matrix has 48 rows");
}

TEST(ReadPartition, EmptyFileSumsToZero) {
  const std::string path = temp_file("# nothing\n");
  EXPECT_EQ(error_of([&] { read_partition(path, 5); }),
            path + ": block sizes sum to 0, the matrix has 5 rows");
}

TEST(ReadPartition, NonIntegerLine) {
  const std::string path = temp_file("3\n# c\n2.5\n");
  const std::string message = error_of([&] { read_partition(path, 10); });
  EXPECT_EQ(message.rfind(path + ":3: ", 0), 0u) << message;
  EXPECT_NE(message.find("'2.5'"), std::string::npos) << message;
  EXPECT_THROW(read_partition(temp_file("3 4\n"), 7), InputError);
  EXPECT_THROW(read_partition(temp_file("three\n"), 3), InputError);
  EXPECT_THROW(read_partition(temp_file("99999999999999999999\n"), 3), InputError);
}

TEST(ReadPartition, ZeroLine) {
  const std::string path = temp_file("3\n0\n7\n");
  const std::string message = error_of([&] { read_partition(path, 10); });
  EXPECT_EQ(message, path + ":2: block size must be positive, got 0");
}

TEST(ReadPartition, NegativeLine) {
  const std::string path = temp_file("13\n-3\n");
  const std::string message = error_of([&] { read_partition(path, 10); });
  EXPECT_EQ(message, path + ":2: block size must be positive, got -3");
}

// The offending line, raw and whole, must not reach the message (a megabyte of binary, control
// bytes and a NUL, multi-line), nor the file name unescaped.
TEST(ReadPartition, MessagesAreOneBoundedPrintableLine) {
  std::string junk = "3\n";
  junk += '\x01';
  junk += std::string(1 << 20, '7');
  junk += std::string("\0\r\x80x", 4);
  const std::string path = temp_file(junk);
  const std::string message = error_of([&] { read_partition(path, 10); });
  EXPECT_EQ(message.rfind(path + ":2: ", 0), 0u) << message.substr(0, 200);
  EXPECT_LT(message.size(), path.size() + 200) << message.substr(0, 200);
  EXPECT_NE(message.find("\\x01"), std::string::npos) << message;
  EXPECT_NE(message.find("...'"), std::string::npos) << message;
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);

  // A NUL after a number is not cut at (the message goes on, escaped).
  const std::string nul = temp_file(std::string("3\n4\0x\n", 7));
  EXPECT_EQ(error_of([&] { read_partition(nul, 7); }),
            nul + ":2: expected a positive integer block size, got '4\\x00x'");

  // A file name with a control byte is quoted escaped.
  const std::string odd = ::testing::TempDir() + "ldlpgs_no\nsuch.blocks";
  EXPECT_EQ(error_of([&] { read_partition(odd, 3); }),
            ::testing::TempDir() + "ldlpgs_no\\x0asuch.blocks: cannot open file: No such file or directory");
}

// Sizes past n: named at the line where they exceed it, and neither stored nor summed further
// (a file of 2^31 - 1 on every line would overflow any sum).
TEST(ReadPartition, SizesBeyondTheMatrixAreNamedAtTheirLine) {
  const std::string path = temp_file("# c\n4\n4\n4\n2147483647\n2147483647\n");
  EXPECT_EQ(error_of([&] { read_partition(path, 10); }),
            path + ":4: block sizes reach 12, more than the matrix's 10 rows");
}

// --- parse_partition -------------------------------------------------------------------------

TEST(ParsePartition, Auto) {
  EXPECT_EQ(parse_partition("auto", hand_built()), (Sizes{3, 2, 1, 4}));
  EXPECT_EQ(parse_partition("auto", hand_built(), 3), (Sizes{3, 2, 1, 3, 1}));
}

TEST(ParsePartition, Uniform) {
  EXPECT_EQ(parse_partition("4", hand_built()), (Sizes{4, 4, 2}));
  EXPECT_EQ(parse_partition("10", hand_built()), (Sizes{10}));
}

TEST(ParsePartition, File) {
  const std::string path = temp_file("5\n5\n");
  EXPECT_EQ(parse_partition(path, hand_built()), (Sizes{5, 5}));
}

TEST(ParsePartition, ZeroAndNegativeAreErrors) {
  EXPECT_NE(error_of([] { parse_partition("0", hand_built()); }).find("positive"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_partition("-2", hand_built()); }).find("positive"),
            std::string::npos);
  EXPECT_THROW(parse_partition("99999999999", hand_built()), InputError);
}

TEST(ParsePartition, MissingFileIsAnError) {
  const std::string path = ::testing::TempDir() + "ldlpgs_no_such_blocks";
  EXPECT_EQ(error_of([&] { parse_partition(path, hand_built()); }), path + ": cannot open file: No such file or directory");
}

TEST(ParsePartition, MaxSizeBelowOneIsAnError) {
  EXPECT_THROW(parse_partition("auto", hand_built(), 0), InputError);
  EXPECT_THROW(parse_partition("4", hand_built(), 0), InputError);
}

}  // namespace
}  // namespace ldlpgs
