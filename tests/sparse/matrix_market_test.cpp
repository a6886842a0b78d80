// read_matrix_market against CHOLMOD's own reader on the collection's matrices, one named test
// per kind of bad input (each checking that the message names the file and line), and write/read
// round trips.
#include "ldlpgs/sparse/matrix_market.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/limits.h"
#include "tests/support/bytes_read.h"
#include "tests/support/temp_files.h"
#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

namespace fs = std::filesystem;

const std::string kMatrices = LDLPGS_MATRICES;

using testing::expect_valid;
using testing::temp_file;

// The message read_matrix_market throws for path (a test failure if it does not throw).
std::string error_of(const std::string& path) {
  try {
    read_matrix_market(path);
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
    return message;
  }
  ADD_FAILURE() << path << " was accepted";
  return {};
}

// Checks that reading content fails with "PATH:LINE: ..." containing every one of words.
void expect_error(const std::string& content, int line, const std::vector<std::string>& words) {
  const std::string path = temp_file("bad.mtx", content);
  const std::string message = error_of(path);
  const std::string prefix = path + ":" + std::to_string(line) + ": ";
  EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
  for (const std::string& w : words) {
    EXPECT_NE(message.find(w), std::string::npos) << "'" << w << "' not in: " << message;
  }
}

SymmetricCsc read_text(const std::string& content) {
  return read_matrix_market(temp_file("good.mtx", content));
}

// The lower triangle as a map (row, col) -> value, 0-based, for readable comparisons.
std::map<std::pair<int, int>, double> entries(const SymmetricCsc& a) {
  std::map<std::pair<int, int>, double> m;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) m[{a.row_idx[p], j}] = a.values[p];
  }
  return m;
}

void expect_same(const SymmetricCsc& a, const SymmetricCsc& b, double rel_tol) {
  ASSERT_EQ(a.n, b.n);
  ASSERT_EQ(a.col_ptr, b.col_ptr);
  ASSERT_EQ(a.row_idx, b.row_idx);
  for (size_t p = 0; p < a.values.size(); ++p) {
    if (a.values[p] == b.values[p]) continue;
    EXPECT_LE(std::abs(a.values[p] - b.values[p]), rel_tol * std::abs(b.values[p]))
        << "entry " << p << ": " << a.values[p] << " vs " << b.values[p];
  }
}

bool is_pattern_file(const std::string& path) {
  std::ifstream in(path);
  std::string banner;
  std::getline(in, banner);
  return banner.find("pattern") != std::string::npos;
}

// --- the collection's matrices --------------------------------------------------------------

TEST(MatrixMarket, MatchesCholmodOnEveryTestMatrix) {
  Cholmod cm;
  int compared = 0, patterns = 0;
  for (const auto& file : fs::directory_iterator(kMatrices)) {
    const std::string path = file.path().string();
    if (file.path().extension() != ".mtx" || file.path().filename() == "Pd.mtx") continue;
    SCOPED_TRACE(path);
    const SymmetricCsc ours = read_matrix_market(path);
    const SymmetricCsc theirs = cholmod_read(path, cm);
    expect_valid(ours);
    expect_same(ours, theirs, 1e-15);
    ++compared;
    if (is_pattern_file(path)) {
      ++patterns;
      // The values of a pattern matrix are made up: check them against the rule directly too,
      // so that this test does not rest on CHOLMOD alone.
      std::vector<int> degree(ours.n, 0);
      for (const auto& [ij, v] : entries(ours)) {
        if (ij.first == ij.second) continue;
        EXPECT_EQ(v, -1.0);
        ++degree[ij.first];
        ++degree[ij.second];
      }
      const auto m = entries(ours);
      for (int r = 0; r < ours.n; ++r) EXPECT_EQ(m.at({r, r}), 1.0 + degree[r]) << "row " << r;
    }
  }
  EXPECT_GE(compared, 11);
  EXPECT_GE(patterns, 5);
}

TEST(MatrixMarket, GeneralFileWithSymmetricValuesIsAccepted) {
  // pts5ldd03: 161 rows, 745 entries of which 161 diagonal: 292 pairs, each stored twice.
  const SymmetricCsc a = read_matrix_market(kMatrices + "/pts5ldd03.mtx");
  EXPECT_EQ(a.n, 161);
  EXPECT_EQ(a.nnz(), 161 + 292);
  EXPECT_EQ(entries(a).at({0, 0}), 256.0);
}

TEST(MatrixMarket, Bcsstk01KnownEntries) {
  // Independent of CHOLMOD: numbers copied from the file by eye.
  const SymmetricCsc a = read_matrix_market(kMatrices + "/bcsstk01.mtx");
  EXPECT_EQ(a.n, 48);
  EXPECT_EQ(a.nnz(), 224);
  EXPECT_EQ(entries(a).at({0, 0}), 2832268.51852);
}

TEST(MatrixMarket, UnsymmetricPdIsRefused) {
  const std::string path = kMatrices + "/Pd.mtx";
  const std::string message = error_of(path);
  EXPECT_NE(message.find("Pd.mtx"), std::string::npos) << message;
  EXPECT_NE(message.find("not symmetric"), std::string::npos) << message;
  // Found by a separate script: line 70 holds "61 55 -.9999999999999999" and the file has no
  // (55,61); it is the first entry in file order without an equal partner.
  EXPECT_EQ(message, path + ":70: matrix is not symmetric: entry (61,55) = -0.9999999999999999 "
                            "has no symmetric partner (55,61)");
}

// --- well-formed variations -------------------------------------------------------------------

TEST(MatrixMarket, BannerIsCaseInsensitiveAndCommentsAndBlankLinesAreSkipped) {
  const SymmetricCsc a = read_text(
      "%%matrixmarket MATRIX Coordinate REAL Symmetric\n"
      "% a comment\n"
      "\n"
      "   \n"
      "%another\n"
      "2 2 3\n"
      "1 1 4\n"
      "2 1 -1.5e0\n"
      "\n"
      "2 2 +5\n");
  const std::map<std::pair<int, int>, double> expected{{{0, 0}, 4}, {{1, 0}, -1.5}, {{1, 1}, 5}};
  EXPECT_EQ(entries(a), expected);
}

TEST(MatrixMarket, WindowsLineEndings) {
  const SymmetricCsc a =
      read_text("%%MatrixMarket matrix coordinate real symmetric\r\n2 2 2\r\n1 1 1\r\n2 2 2\r\n");
  const std::map<std::pair<int, int>, double> expected{{{0, 0}, 1}, {{1, 1}, 2}};
  EXPECT_EQ(entries(a), expected);
}

TEST(MatrixMarket, UpperEntryInSymmetricFileIsStoredTransposed) {
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate real symmetric\n3 3 4\n1 1 2\n1 3 7\n2 2 3\n3 3 4\n");
  const std::map<std::pair<int, int>, double> expected{
      {{0, 0}, 2}, {{2, 0}, 7}, {{1, 1}, 3}, {{2, 2}, 4}};
  EXPECT_EQ(entries(a), expected);
  expect_valid(a);
}

TEST(MatrixMarket, IntegerFieldIsReadAsReal) {
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate integer symmetric\n3 3 3\n1 1 3\n2 1 -2\n3 3 "
      "+123456789012345678901234\n");
  const std::map<std::pair<int, int>, double> expected{
      {{0, 0}, 3}, {{1, 0}, -2}, {{2, 2}, 123456789012345678901234.0}};
  EXPECT_EQ(entries(a), expected);
}

TEST(MatrixMarket, ExactValuesSurvive) {
  // Values that differ only in the last bit, and a tiny one that underflows to a denormal.
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 0.1\n2 2 "
      "0.10000000000000002\n3 3 4.9406564584124654e-324\n");
  const auto m = entries(a);
  EXPECT_EQ(m.at({0, 0}), 0.1);
  EXPECT_EQ(m.at({1, 1}), 0.10000000000000002);
  EXPECT_NE(m.at({0, 0}), m.at({1, 1}));
  EXPECT_EQ(m.at({2, 2}), 4.9406564584124654e-324);
}

TEST(MatrixMarket, PatternValuesAndMissingDiagonalAdded) {
  // Full pattern: edges 1-2, 1-3, 2-3, 3-4, diagonal given for rows 1 and 3 only. Degrees
  // 2, 2, 3, 1; the header (and the README) promise 1 + degree on every diagonal.
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate pattern symmetric\n4 4 6\n1 1\n2 1\n3 1\n3 2\n3 3\n"
      "4 3\n");
  const std::map<std::pair<int, int>, double> expected{
      {{0, 0}, 3},  {{1, 0}, -1}, {{2, 0}, -1}, {{1, 1}, 3},
      {{2, 1}, -1}, {{2, 2}, 4},  {{3, 2}, -1}, {{3, 3}, 2}};
  EXPECT_EQ(entries(a), expected);
}

TEST(MatrixMarket, PatternMissingDiagonalIsWhereCholmodDiffers) {
  // CHOLMOD (SuiteSparse 5.12) gives a file's diagonal entries 1 + degree but adds none that
  // are missing; we add them (the header's promise). Everything CHOLMOD has, we have equal.
  const std::string path = temp_file(
      "p.mtx", "%%MatrixMarket matrix coordinate pattern symmetric\n3 3 3\n1 1\n2 1\n3 2\n");
  Cholmod cm;
  const auto ours = entries(read_matrix_market(path));
  const auto theirs = entries(cholmod_read(path, cm));
  for (const auto& [ij, v] : theirs) EXPECT_EQ(ours.at(ij), v);
  const std::map<std::pair<int, int>, double> expected{
      {{0, 0}, 2}, {{1, 0}, -1}, {{1, 1}, 3}, {{2, 1}, -1}, {{2, 2}, 2}};
  EXPECT_EQ(ours, expected);
}

TEST(MatrixMarket, GeneralPatternFileWithSymmetricPattern) {
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate pattern general\n3 3 4\n2 1\n1 2\n3 2\n2 3\n");
  const std::map<std::pair<int, int>, double> expected{
      {{0, 0}, 2}, {{1, 0}, -1}, {{1, 1}, 3}, {{2, 1}, -1}, {{2, 2}, 2}};
  EXPECT_EQ(entries(a), expected);
}

TEST(MatrixMarket, EmptyMatrix) {
  const SymmetricCsc a = read_text("%%MatrixMarket matrix coordinate real symmetric\n3 3 0\n");
  EXPECT_EQ(a.n, 3);
  EXPECT_EQ(a.nnz(), 0);
}

TEST(MatrixMarket, LargeBandedFileReads) {
  // 100k rows with a tridiagonal pattern: ~200k entries, to show size is not a problem.
  const int n = 100000;
  std::string text = "%%MatrixMarket matrix coordinate real symmetric\n" + std::to_string(n) +
                     " " + std::to_string(n) + " " + std::to_string(2 * n - 1) + "\n";
  for (int i = 1; i <= n; ++i) {
    text += std::to_string(i) + " " + std::to_string(i) + " 4\n";
    if (i > 1) text += std::to_string(i) + " " + std::to_string(i - 1) + " -1\n";
  }
  const SymmetricCsc a = read_text(text);
  EXPECT_EQ(a.n, n);
  EXPECT_EQ(a.nnz(), 2 * n - 1);
  EXPECT_EQ(a.values[a.col_ptr[n - 2] + 1], -1.0);
}

// --- bad input: one test per kind ------------------------------------------------------------

const std::string kBanner = "%%MatrixMarket matrix coordinate real symmetric\n";

TEST(MatrixMarketError, MissingFile) {
  const std::string path = ::testing::TempDir() + "ldlpgs_no_such_file.mtx";
  EXPECT_EQ(error_of(path), path + ": cannot open file: No such file or directory");
}

TEST(MatrixMarketError, Directory) {
  const std::string path = ::testing::TempDir();
  EXPECT_NE(error_of(path).find(path + ": cannot"), std::string::npos);
}

TEST(MatrixMarketError, EmptyFile) {
  const std::string path = temp_file("empty.mtx", "");
  EXPECT_EQ(error_of(path), path + ": file is empty");
}

TEST(MatrixMarketError, MissingBanner) {
  expect_error("3 3 1\n1 1 1\n", 1, {"%%MatrixMarket"});
}

TEST(MatrixMarketError, BadBanner) {
  expect_error("%%MatrixMarket matrix coordinate real\n3 3 1\n1 1 1\n", 1, {"banner"});
  expect_error("%%MatrixMarket matrix coordinate real symetric\n3 3 1\n1 1 1\n", 1,
               {"symetric"});
  expect_error("%%MatrixMarket vector coordinate real general\n3 3 1\n1 1 1\n", 1, {"vector"});
  expect_error("%%MatrixMarket matrix coordinate double general\n3 3 1\n1 1 1\n", 1, {"double"});
}

TEST(MatrixMarketError, ArrayFormat) {
  expect_error("%%MatrixMarket matrix array real symmetric\n2 2\n1\n2\n3\n", 1,
               {"array", "coordinate"});
}

TEST(MatrixMarketError, Complex) {
  expect_error("%%MatrixMarket matrix coordinate complex symmetric\n1 1 1\n1 1 1 0\n", 1,
               {"complex"});
}

TEST(MatrixMarketError, HermitianAndSkewSymmetric) {
  expect_error("%%MatrixMarket matrix coordinate real hermitian\n1 1 1\n1 1 1\n", 1,
               {"hermitian"});
  expect_error("%%MatrixMarket matrix coordinate real skew-symmetric\n2 2 1\n2 1 1\n", 1,
               {"skew-symmetric"});
}

TEST(MatrixMarketError, MissingSizeLine) {
  expect_error(kBanner + "% only comments\n", 2, {"size line"});
}

TEST(MatrixMarketError, BadSizeLine) {
  expect_error(kBanner + "% c\n3 3\n1 1 1\n", 3, {"size line"});
  expect_error(kBanner + "3 x 1\n1 1 1\n", 2, {"size line"});
  expect_error(kBanner + "3 3 -1\n", 2, {"size line"});
}

TEST(MatrixMarketError, NonSquare) {
  expect_error(kBanner + "% c\n3 4 1\n1 1 1\n", 3, {"3 x 4", "not square"});
}

TEST(MatrixMarketError, MoreEntriesDeclaredThanPositions) {
  expect_error(kBanner + "2 2 4\n1 1 1\n2 1 1\n2 2 1\n1 2 1\n", 2, {"4 entries", "3 positions"});
}

TEST(MatrixMarketError, RowIndexOutOfRange) {
  expect_error(kBanner + "3 3 2\n1 1 1\n4 1 1\n", 4, {"row index 4 out of range 1..3"});
}

TEST(MatrixMarketError, ColumnIndexZero) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 0 1\n", 4, {"column index 0 out of range 1..3"});
}

TEST(MatrixMarketError, HugeIndex) {
  expect_error(kBanner + "3 3 1\n99999999999999999999999 1 1\n", 3, {"row index", "1..3"});
}

TEST(MatrixMarketError, MalformedLineTooFewFields) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1\n", 4, {"malformed", "2 fields"});
}

TEST(MatrixMarketError, MalformedLineTooManyFields) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1 3 4\n", 4, {"malformed", "4 fields"});
}

TEST(MatrixMarketError, MalformedLineNonNumeric) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1 abc\n", 4, {"malformed", "'abc'"});
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1.5 1\n", 4, {"malformed", "column index"});
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1 1.5x\n", 4, {"malformed", "'1.5x'"});
}

// C15: "1 1 1.5" in an integer file was read as 1.5.
TEST(MatrixMarketError, NonIntegerValueInAnIntegerFile) {
  const std::string banner = "%%MatrixMarket matrix coordinate integer symmetric\n";
  expect_error(banner + "2 2 2\n1 1 3\n2 1 1.5\n", 4, {"entry (2,1)", "'1.5'", "not an integer"});
  for (const std::string value : {"3.0", "1e3", "-", "0x10"}) {
    expect_error(banner + "1 1 1\n1 1 " + value + "\n", 3, {"'" + value + "'", "not an integer"});
  }
}

TEST(MatrixMarketError, NanValue) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 1 nan\n", 4, {"(2,1)", "non-finite", "nan"});
}

TEST(MatrixMarketError, InfValue) {
  expect_error(kBanner + "3 3 2\n1 1 -inf\n2 1 1\n", 3, {"(1,1)", "non-finite"});
  expect_error(kBanner + "3 3 2\n1 1 1e400\n2 1 1\n", 3, {"(1,1)", "non-finite", "1e400"});
}

TEST(MatrixMarketError, DuplicateEntry) {
  expect_error(kBanner + "3 3 3\n2 1 1\n3 3 1\n2 1 1\n", 5,
               {"duplicate entry (2,1)", "line 3"});
}

TEST(MatrixMarketError, DuplicateSymmetricPair) {
  expect_error(kBanner + "3 3 3\n3 1 1\n2 2 1\n1 3 1\n", 5, {"(1,3)", "(3,1)", "line 3"});
}

TEST(MatrixMarketError, DuplicateInGeneralFile) {
  expect_error("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 2 1\n2 1 1\n1 2 1\n", 5,
               {"duplicate entry (1,2)", "line 3"});
}

TEST(MatrixMarketError, TruncatedFile) {
  expect_error(kBanner + "3 3 3\n1 1 1\n2 2 1\n", 4, {"truncated", "3 entries", "has 2"});
}

TEST(MatrixMarketError, TooManyEntries) {
  expect_error(kBanner + "3 3 2\n1 1 1\n2 2 1\n3 3 1\n", 5, {"more entries", "2"});
}

TEST(MatrixMarketError, UnsymmetricGeneralPattern) {
  expect_error("%%MatrixMarket matrix coordinate real general\n3 3 4\n1 1 1\n2 1 5\n3 2 1.5\n"
               "1 2 5\n",
               5, {"not symmetric", "(3,2) = 1.5", "no symmetric partner (2,3)"});
}

TEST(MatrixMarketError, UnsymmetricGeneralPatternFile) {
  expect_error("%%MatrixMarket matrix coordinate pattern general\n3 3 3\n1 1\n2 1\n1 3\n", 4,
               {"not symmetric", "(2,1)", "no symmetric partner (1,2)"});
}

TEST(MatrixMarketError, UnsymmetricGeneralValues) {
  expect_error("%%MatrixMarket matrix coordinate real general\n3 3 3\n1 1 1\n2 1 1.5\n1 2 2\n",
               4, {"not symmetric", "(2,1) = 1.5", "(1,2) = 2", "line 5"});
}

TEST(MatrixMarketError, UnsymmetricGeneralValuesInLastBit) {
  expect_error("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 2 0.1\n"
               "2 1 0.10000000000000002\n",
               3, {"not symmetric", "(1,2) = 0.1", "(2,1) = 0.10000000000000002"});
}

// --- writing ------------------------------------------------------------------------------------

void expect_round_trip(const std::string& name) {
  SCOPED_TRACE(name);
  const SymmetricCsc a = read_matrix_market(kMatrices + "/" + name);
  const std::string path = temp_file("rt_" + name, "");
  write_matrix_market(path, a);
  const SymmetricCsc b = read_matrix_market(path);
  expect_same(b, a, 0.0);
  EXPECT_EQ(a.values, b.values);  // bit for bit, not just to a tolerance
  std::ifstream in(path);
  std::string banner;
  std::getline(in, banner);
  EXPECT_EQ(banner, "%%MatrixMarket matrix coordinate real symmetric");
}

TEST(MatrixMarketWrite, RoundTripBcsstk01) { expect_round_trip("bcsstk01.mtx"); }
TEST(MatrixMarketWrite, RoundTripPatternMatrix) { expect_round_trip("can___24.mtx"); }
TEST(MatrixMarketWrite, RoundTripGeneralFile) { expect_round_trip("pts5ldd03.mtx"); }

TEST(MatrixMarketWrite, RoundTripAwkwardValues) {
  const SymmetricCsc a = read_text(
      "%%MatrixMarket matrix coordinate real symmetric\n3 3 4\n1 1 0.1\n2 1 -1e-300\n"
      "2 2 1.7976931348623157e308\n3 3 0\n");
  const std::string path = temp_file("rt.mtx", "");
  write_matrix_market(path, a);
  const SymmetricCsc b = read_matrix_market(path);
  EXPECT_EQ(entries(a), entries(b));
}

TEST(MatrixMarketWrite, CannotWrite) {
  const std::string path = ::testing::TempDir() + "ldlpgs_no_such_dir/out.mtx";
  const SymmetricCsc a = read_matrix_market(kMatrices + "/LFAT5.mtx");
  try {
    write_matrix_market(path, a);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot write file");
  }
}

// Declared sizes are checked against size_limits() before anything is allocated; a
// lifted limit reads the same file.
TEST(MatrixMarket, DeclaredSizesBeyondTheLimitsAreRefused) {
  const std::string content = "%%MatrixMarket matrix coordinate real symmetric\n20 20 2\n1 1 1\n20 20 1\n";
  const SizeLimits saved = size_limits();
  size_limits().rows = 10;
  expect_error(content, 2, {"20 rows", "limit of 10"});
  size_limits() = saved;
  size_limits().entries = 1;
  expect_error(content, 2, {"2 entries", "limit of 1"});
  size_limits() = SizeLimits::none();
  EXPECT_EQ(read_text(content).n, 20);
  size_limits() = saved;
}

// Input bytes in messages are escaped and bounded: a NUL or a control byte inside an entry no
// longer cuts the message short or spills into the terminal.
TEST(MatrixMarket, ControlBytesInAnEntryAreEscapedInTheMessage) {
  static const char kContent[] = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\0x\x1b[2J\n2 2 1\n";
  const std::string message = error_of(temp_file("nul.mtx", std::string(kContent, sizeof(kContent) - 1)));
  EXPECT_NE(message.find("\\x00x\\x1b[2J"), std::string::npos) << message;
  for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c) << " in: " << message;
}

// --- a chunk at a time: bad input is refused having read little of it ------------------------

using ::testing::bytes_read_by;

// path, of `size` bytes: content, then NUL bytes to the end (a sparse file: no disk used).
std::string padded_with_nul(const std::string& name, const std::string& content, uintmax_t size) {
  const std::string path = temp_file(name, content);
  fs::resize_file(path, size);
  return path;
}

// `ldlpgs order /dev/zero` never returned, and a 2 GB file of NUL bytes took 33 s and 4.2 GB:
// the whole file was read before its first line was looked at. Now one chunk (64 KiB) is.
TEST(MatrixMarketError, NulFileIsRefusedAtItsFirstChunk) {
  const std::string path = padded_with_nul("nul.mtx", "", uintmax_t{256} << 20);
  std::string message;
  const int64_t read = bytes_read_by([&] { message = error_of(path); });
  EXPECT_EQ(message.substr(0, path.size() + 3), path + ":1:") << message;
  EXPECT_NE(message.find("not a Matrix Market file"), std::string::npos) << message;
  ASSERT_GE(read, 0) << "no /proc/self/io to count the bytes read";
  EXPECT_LT(read, 1 << 20);
}

// Lines across the reader's 64 KiB chunks: an entry line, and a CRLF split between two chunks,
// at every offset of the boundary; the entries are known here, not read back by the same reader.
TEST(MatrixMarket, LinesAcrossChunkBoundaries) {
  const std::string entries_text = "1 1 4\r\n2 1 1\r\n2 2 5\r\n3 3 6";  // no final newline
  const std::map<std::pair<int, int>, double> expected = {{{0, 0}, 4}, {{1, 0}, 1}, {{1, 1}, 5}, {{2, 2}, 6}};
  const std::string head = "%%MatrixMarket matrix coordinate real symmetric\r\n";
  for (size_t shift = 0; shift <= entries_text.size() + 8; ++shift) {
    // a comment that puts the chunk boundary (byte 65536) `shift` bytes before the entries end
    const std::string size_line = "3 3 4\r\n";
    const size_t before = (size_t{1} << 16) + shift - entries_text.size() - size_line.size() - head.size();
    std::string comment(before, 'c');  // "%ccc...c\r\n"
    comment.front() = '%';
    comment[before - 2] = '\r';
    comment.back() = '\n';
    const std::string text = head + comment + size_line + entries_text;
    ASSERT_EQ(text.size(), (size_t{1} << 16) + shift);
    EXPECT_EQ(entries(read_text(text)), expected) << "boundary " << shift << " bytes before the end";
    EXPECT_EQ(entries(read_text(text + "\n")), expected) << "with a final newline, shift " << shift;
  }
}

// A first line of a megabyte: refused within its first 64 KiB, whether or not it starts with
// the banner (the old reader took the latter for a banner and said the size line was missing).
TEST(MatrixMarketError, FirstLineLongerThanABanner) {
  int64_t read = bytes_read_by([&] {
    expect_error(std::string(1 << 20, 'x'), 1, {"not a Matrix Market file"});
  });
  const std::string spaces = kBanner.substr(0, kBanner.size() - 1) + std::string(1 << 20, ' ');
  read += bytes_read_by([&] { expect_error(spaces + "\n3 3 0\n", 1, {"banner line is longer than 65535"}); });
  ASSERT_GE(read, 0) << "no /proc/self/io to count the bytes read";
  EXPECT_LT(read, 1 << 20);
}

// After a good banner (and size line), bytes without a newline (a banner followed by /dev/zero)
// are refused once past 1 MiB, not read to their end.
TEST(MatrixMarketError, LineLongerThanAMegabyte) {
  for (const auto& [content, line] : {std::pair<std::string, int>{kBanner, 2}, {kBanner + "3 3 1\n", 3}}) {
    const std::string path = padded_with_nul("nul_after.mtx", content, uintmax_t{64} << 20);
    std::string message;
    const int64_t read = bytes_read_by([&] { message = error_of(path); });
    const std::string prefix = path + ":" + std::to_string(line) + ": line is longer than 1048576 bytes";
    EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
    EXPECT_NE(message.find("'\\x00\\x00"), std::string::npos) << message;
    ASSERT_GE(read, 0) << "no /proc/self/io to count the bytes read";
    EXPECT_LT(read, 2 << 20);
  }
}

// Comments and blank lines are capped at 64 MiB in all, so that a good header followed by
// endless blank lines (`yes ''`) is not read forever.
TEST(MatrixMarketError, EndlessBlankLines) {
  expect_error(kBanner + "3 3 0\n" + std::string((64 << 20) + 1, '\n'), (64 << 20) + 3,
               {"more than 67108864 bytes of comments and blank lines"});
}

// A named pipe (as bash's <(...) gives) reads as the same file does, over many chunks and the
// pipe's short reads; one of NUL bytes is refused at its first chunk, the writer then stopped by
// EPIPE (or, with the old reader, after writing all of it).
TEST(MatrixMarket, NamedPipeReadsAsAFile) {
  std::signal(SIGPIPE, SIG_IGN);
  auto through_fifo = [](const std::string& content, const std::function<void(const std::string&)>& read) {
    static int count = 0;
    const std::string fifo = testing::temp_path("fifo" + std::to_string(++count) + ".mtx");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
    std::thread writer([&] {
      std::FILE* f = std::fopen(fifo.c_str(), "wb");
      if (!f) return;
      std::fwrite(content.data(), 1, content.size(), f);
      std::fclose(f);
    });
    try {
      read(fifo);
    } catch (...) {
      writer.join();
      throw;
    }
    writer.join();
  };
  const int n = 20000;  // some 500 KB
  std::string text = kBanner + std::to_string(n) + " " + std::to_string(n) + " " + std::to_string(2 * n - 1) + "\n";
  for (int i = 1; i <= n; ++i) {
    text += std::to_string(i) + " " + std::to_string(i) + " 4.25\r\n";
    if (i > 1) text += "% a comment\n" + std::to_string(i) + " " + std::to_string(i - 1) + " -1.5";
    if (i > 1 && i < n) text += "\n";  // the last line without its newline
  }
  through_fifo(text, [&](const std::string& fifo) { expect_same(read_matrix_market(fifo), read_text(text), 0); });
  through_fifo(std::string(64 << 20, '\0'), [&](const std::string& fifo) {
    std::string message;
    const int64_t read = bytes_read_by([&] { message = error_of(fifo); });
    EXPECT_NE(message.find(fifo + ":1: not a Matrix Market file"), std::string::npos) << message;
    ASSERT_GE(read, 0) << "no /proc/self/io to count the bytes read";
    EXPECT_LT(read, 1 << 20);
  });
}

}  // namespace
}  // namespace ldlpgs
