#include "ldlpgs/sparse/matrix_market.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <string_view>
#include <vector>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/limits.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {
namespace {

[[noreturn]] void fail(const std::string& path, int64_t line, const std::string& problem) {
  throw InputError(path + ":" + std::to_string(line) + ": " + problem);
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

// The banner is some 50 bytes; a first line not ended within the first chunk is not one.
constexpr size_t kMaxBannerLength = FileChunks::kChunk - 1;
// A line of an entry is under 100 bytes even written with "%.17g" or padded by Fortran; a
// megabyte is for comments. Past it the file is binary or broken (/dev/zero after a good banner).
constexpr size_t kMaxLineLength = size_t{1} << 20;
// Comments and blank lines together, anywhere in the file (the collection's largest comment
// blocks are a few KB): without a cap, a good header followed by endless blank lines (`yes ''`)
// would be read forever.
constexpr int64_t kMaxSkippedBytes = int64_t{1} << 26;

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }

// Splits on blanks, keeping the first N fields; returns how many fields the line has in all,
// so that a line with too many fields is noticed too.
template <size_t N>
size_t split(std::string_view line, std::array<std::string_view, N>& fields) {
  size_t count = 0, pos = 0;
  while (true) {
    while (pos < line.size() && is_space(line[pos])) ++pos;
    if (pos == line.size()) return count;
    const size_t start = pos;
    while (pos < line.size() && !is_space(line[pos])) ++pos;
    if (count < N) fields[count] = line.substr(start, pos - start);
    ++count;
  }
}

// Blank lines and '%' comments may appear anywhere after the banner.
bool is_skipped(std::string_view line) {
  size_t pos = 0;
  while (pos < line.size() && is_space(line[pos])) ++pos;
  return pos == line.size() || line[pos] == '%';
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Quoted for messages, cut short so that a binary file cannot produce a huge message.
// (Appending rather than "'" + string: GCC 12 at -O3 warns falsely on the latter, bug 105329.)
std::string quoted(std::string_view s) {
  std::string out = "'";
  out += printable(s, 40);
  out += "'";
  return out;
}

// from_chars does not take the '+' sign that Fortran-written files sometimes carry.
std::string_view drop_plus(std::string_view s) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  return s;
}

enum class Parsed { ok, malformed, out_of_range };

Parsed parse_integer(std::string_view s, int64_t& value) {
  s = drop_plus(s);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) return Parsed::out_of_range;
  if (ec != std::errc() || end != s.data() + s.size()) return Parsed::malformed;
  return Parsed::ok;
}

Parsed parse_real(std::string_view s, double& value) {
  s = drop_plus(s);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range && end == s.data() + s.size()) {
    // from_chars reports underflow and overflow alike and leaves value unset; strtod tells them
    // apart. A value too small for a double is a zero, as every C reader (CHOLMOD's) takes it.
    value = std::strtod(std::string(s).c_str(), nullptr);
    return std::isinf(value) ? Parsed::out_of_range : Parsed::ok;
  }
  if (ec != std::errc() || end != s.data() + s.size()) return Parsed::malformed;
  return Parsed::ok;
}

// An integer file's values: digits with an optional sign, read as reals (parse_real) so that
// one beyond 64 bits is still a value, not an error. "1.5" was read as 1.5 (C15).
bool is_integer(std::string_view s) {
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The shortest text that reads back as v, so that two values differing in the last bit print
// differently in a symmetry message.
std::string format(double v) {
  std::array<char, 64> buffer;
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), v);
  return std::string(buffer.data(), result.ptr);
}

std::string position(int64_t i, int64_t j) {
  std::string out = "(";
  out += std::to_string(i);
  out += ",";
  out += std::to_string(j);
  out += ")";
  return out;
}

enum class Field { real, integer, pattern };
enum class Symmetry { symmetric, general };

struct Header {
  Field field;
  Symmetry symmetry;
};

Header parse_banner(const std::string& path, std::string_view line) {
  constexpr std::string_view kBanner = "%%matrixmarket";
  const std::string usage =
      "expected '%%MatrixMarket matrix coordinate real|integer|pattern symmetric|general'";
  std::array<std::string_view, 6> fields;
  const size_t count = split(line, fields);
  if (count == 0 || lower(fields[0]) != kBanner) {
    fail(path, 1, "not a Matrix Market file: the first line must start with %%MatrixMarket");
  }
  if (count < 5) fail(path, 1, "incomplete banner: " + usage);
  if (count > 5) fail(path, 1, "unexpected text after the banner's five words: " + usage);
  const std::string object = lower(fields[1]), format = lower(fields[2]),
                    field = lower(fields[3]), symmetry = lower(fields[4]);
  if (object != "matrix") {
    fail(path, 1, "object " + quoted(fields[1]) + " is not supported, only 'matrix'");
  }
  if (format == "array") {
    fail(path, 1, "array (dense) format is not supported, only 'coordinate' (sparse)");
  }
  if (format != "coordinate") fail(path, 1, "unknown format " + quoted(fields[2]) + ": " + usage);
  Header header{};
  if (field == "real") {
    header.field = Field::real;
  } else if (field == "integer") {
    header.field = Field::integer;
  } else if (field == "pattern") {
    header.field = Field::pattern;
  } else if (field == "complex") {
    fail(path, 1, "complex matrices are not supported, only real, integer or pattern");
  } else {
    fail(path, 1, "unknown field " + quoted(fields[3]) + ": " + usage);
  }
  if (symmetry == "symmetric") {
    header.symmetry = Symmetry::symmetric;
  } else if (symmetry == "general") {
    header.symmetry = Symmetry::general;
  } else if (symmetry == "skew-symmetric" || symmetry == "hermitian") {
    fail(path, 1, symmetry + " matrices are not supported, only symmetric or general");
  } else {
    fail(path, 1, "unknown symmetry " + quoted(fields[4]) + ": " + usage);
  }
  return header;
}

struct Entry {
  int row, col;  // 1-based, as in the file (messages use them)
  double value;
  int64_t line;
};

// The entries in (key, line) order, where key is the position for a general file and the
// lower-triangle position for a symmetric one (so (i,j) and (j,i) meet). Throws on duplicates.
std::vector<int> sorted_by_position(const std::string& path, const std::vector<Entry>& entries,
                                    Symmetry symmetry) {
  auto key = [&](const Entry& e) {
    if (symmetry == Symmetry::symmetric) {
      return std::pair{std::max(e.row, e.col), std::min(e.row, e.col)};
    }
    return std::pair{e.row, e.col};
  };
  std::vector<int> order(entries.size());
  std::iota(order.begin(), order.end(), 0);
  // Stable: entries are in line order, so each group of equal keys stays in line order.
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return key(entries[a]) < key(entries[b]); });
  auto same = [&](int a, int b) { return key(entries[a]) == key(entries[b]); };

  // Report the duplicate that comes first in the file, as a reader going line by line would.
  int first_dup = -1, first_orig = -1;
  for (size_t k = 1; k < order.size(); ++k) {
    if (same(order[k - 1], order[k]) && (k < 2 || !same(order[k - 2], order[k]))) {
      if (first_dup < 0 || entries[order[k]].line < entries[first_dup].line) {
        first_dup = order[k];
        first_orig = order[k - 1];
      }
    }
  }
  if (first_dup >= 0) {
    const Entry& d = entries[first_dup];
    const Entry& o = entries[first_orig];
    std::string problem;
    if (d.row == o.row) {
      problem = "duplicate entry " + position(d.row, d.col) + ", first given on line " +
                std::to_string(o.line);
    } else {
      problem = "entry " + position(d.row, d.col) + " duplicates " + position(o.row, o.col) +
                " on line " + std::to_string(o.line) +
                ": a symmetric file gives each off-diagonal pair once";
    }
    fail(path, d.line, problem);
  }
  return order;
}

// A general file stands for a symmetric matrix only if every (i,j) has a partner (j,i) with
// exactly the same value; the first entry in the file that has none is reported.
void check_symmetric(const std::string& path, const std::vector<Entry>& entries,
                     const std::vector<int>& order) {
  auto before = [&](int k, std::pair<int, int> p) {
    return std::pair{entries[k].row, entries[k].col} < p;
  };
  for (const Entry& e : entries) {
    if (e.row == e.col) continue;
    const std::pair<int, int> partner{e.col, e.row};
    const auto it = std::lower_bound(order.begin(), order.end(), partner, before);
    auto what = [&] {
      return "matrix is not symmetric: entry " + position(e.row, e.col) + " = " + format(e.value);
    };
    if (it == order.end() || entries[*it].row != e.col || entries[*it].col != e.row) {
      fail(path, e.line, what() + " has no symmetric partner " + position(e.col, e.row));
    }
    const Entry& p = entries[*it];
    if (p.value != e.value) {
      fail(path, e.line, what() + " but its symmetric partner " + position(p.row, p.col) + " = " +
                             format(p.value) + " (line " + std::to_string(p.line) + ")");
    }
  }
}

}  // namespace

// Long: the file in reading order (banner, size line, entries), each check failing at its own line.
SymmetricCsc read_matrix_market(const std::string& file) {
  LineReader lines(file);
  const std::string& path = lines.name();  // (through printable(): messages stay one line)
  std::string_view line;
  const LineReader::Got first = lines.next(line, kMaxBannerLength);
  if (first == LineReader::Got::end) fail(path, "file is empty");
  const Header header = parse_banner(path, line);  // a binary file fails here, at its first chunk
  if (first == LineReader::Got::too_long) {
    fail(path, 1, "the banner line is longer than " + std::to_string(kMaxBannerLength) + " bytes");
  }

  // The next line that is neither blank nor a comment; false at the end of the file.
  int64_t skipped_bytes = 0;
  auto next_data_line = [&] {
    while (true) {
      const LineReader::Got got = lines.next(line, kMaxLineLength);
      if (got == LineReader::Got::end) return false;
      if (got == LineReader::Got::too_long) {
        fail(path, lines.number(),
             "line is longer than " + std::to_string(kMaxLineLength) +
                 " bytes, which no Matrix Market line is: " + quoted(line));
      }
      if (!is_skipped(line)) return true;
      skipped_bytes += static_cast<int64_t>(line.size()) + 1;
      if (skipped_bytes > kMaxSkippedBytes) {
        fail(path, lines.number(),
             "more than " + std::to_string(kMaxSkippedBytes) + " bytes of comments and blank lines");
      }
    }
  };

  if (!next_data_line()) fail(path, lines.number(), "file ends before the size line");
  const int64_t size_line = lines.number();
  std::array<std::string_view, 3> fields;
  std::array<int64_t, 3> size{};
  const std::string size_usage = "bad size line " + quoted(line) +
                                 ": expected three non-negative integers 'rows columns entries'";
  if (split(line, fields) != 3) fail(path, size_line, size_usage);
  for (int k = 0; k < 3; ++k) {
    if (parse_integer(fields[k], size[k]) != Parsed::ok || size[k] < 0) {
      fail(path, size_line, size_usage);
    }
  }
  const auto [rows, cols, nnz] = size;
  if (rows != cols) {
    fail(path, size_line,
         "matrix is " + std::to_string(rows) + " x " + std::to_string(cols) + ", not square");
  }
  constexpr int64_t kIntMax = std::numeric_limits<int>::max();
  if (rows > kIntMax) fail(path, size_line, std::to_string(rows) + " rows is too many");
  check_limit(path + ":" + std::to_string(size_line), rows, size_limits().rows, "rows");
  check_limit(path + ":" + std::to_string(size_line), nnz, size_limits().entries, "entries");
  const int n = static_cast<int>(rows);
  // More entries than positions means a duplicate for sure; checking here also keeps a corrupt
  // size line from making us reserve absurd memory.
  const int64_t positions = header.symmetry == Symmetry::symmetric ? rows * (rows + 1) / 2
                                                                   : rows * rows;
  if (nnz > positions) {
    fail(path, size_line,
         std::to_string(nnz) + " entries declared, more than the " + std::to_string(positions) +
             " positions of a " + std::to_string(n) + " x " + std::to_string(n) +
             (header.symmetry == Symmetry::symmetric ? " symmetric" : "") + " matrix");
  }
  if (nnz > kIntMax) fail(path, size_line, std::to_string(nnz) + " entries is too many");

  const bool pattern = header.field == Field::pattern;
  const size_t want = pattern ? 2 : 3;
  const std::string usage = pattern ? "'row column'" : "'row column value'";
  std::vector<Entry> entries;
  entries.reserve(static_cast<size_t>(std::min<int64_t>(nnz, 1 << 22)));
  std::array<std::string_view, 3> f;
  while (next_data_line()) {
    const int64_t at = lines.number();
    if (static_cast<int64_t>(entries.size()) == nnz) {
      fail(path, at,
           "more entries than the " + std::to_string(nnz) + " the size line (line " +
               std::to_string(size_line) + ") declares");
    }
    const size_t count = split(line, f);
    if (count != want) {
      fail(path, at,
           "malformed entry " + quoted(line) + ": expected " + usage + ", got " +
               std::to_string(count) + (count == 1 ? " field" : " fields"));
    }
    std::array<int64_t, 2> index{};
    const char* names[2] = {"row", "column"};
    for (int k = 0; k < 2; ++k) {
      const Parsed p = parse_integer(f[k], index[k]);
      if (p == Parsed::malformed) {
        fail(path, at,
             "malformed entry " + quoted(line) + ": " + names[k] + " index " + quoted(f[k]) +
                 " is not an integer");
      }
      if (p == Parsed::out_of_range || index[k] < 1 || index[k] > n) {
        fail(path, at,
             std::string(names[k]) + " index " + std::string(f[k]) + " out of range 1.." +
                 std::to_string(n));
      }
    }
    double value = 1;
    if (header.field == Field::integer && !is_integer(f[2])) {
      fail(path, at,
           "entry " + position(index[0], index[1]) + " has value " + quoted(f[2]) +
               ", not an integer: the banner declares an integer matrix");
    }
    if (!pattern) {
      const Parsed p = parse_real(f[2], value);
      if (p == Parsed::malformed) {
        fail(path, at, "malformed entry " + quoted(line) + ": value " + quoted(f[2]) +
                           " is not a number");
      }
      if (p == Parsed::out_of_range || !std::isfinite(value)) {
        fail(path, at,
             "entry " + position(index[0], index[1]) + " has a non-finite value " + quoted(f[2]));
      }
    }
    entries.push_back({static_cast<int>(index[0]), static_cast<int>(index[1]), value, at});
  }
  if (static_cast<int64_t>(entries.size()) < nnz) {
    fail(path, lines.number(),
         "file is truncated: the size line (line " + std::to_string(size_line) + ") declares " +
             std::to_string(nnz) + " entries, the file has " + std::to_string(entries.size()));
  }

  const std::vector<int> order = sorted_by_position(path, entries, header.symmetry);
  if (header.symmetry == Symmetry::general) check_symmetric(path, entries, order);

  // From here on every off-diagonal pair is present once (symmetric file) or twice with equal
  // values (general file); the lower member of each pair stands for both.
  auto kept = [&](const Entry& e) {
    return header.symmetry == Symmetry::symmetric || e.row >= e.col;
  };
  std::vector<Triplet> triplets;
  triplets.reserve(entries.size() + (pattern ? static_cast<size_t>(n) : 0));
  if (pattern) {
    // CHOLMOD's convention: -1 off the diagonal and 1 + degree on it makes the matrix strictly
    // diagonally dominant, hence positive definite. Diagonal entries of the file are replaced
    // (not summed), and rows without one get one.
    std::vector<int> degree(n, 0);
    for (const Entry& e : entries) {
      if (!kept(e) || e.row == e.col) continue;
      ++degree[e.row - 1];
      ++degree[e.col - 1];
      triplets.push_back({e.row - 1, e.col - 1, -1.0});
    }
    for (int r = 0; r < n; ++r) triplets.push_back({r, r, 1.0 + degree[r]});
  } else {
    for (const Entry& e : entries) {
      if (kept(e)) triplets.push_back({e.row - 1, e.col - 1, e.value});
    }
  }
  return csc_from_triplets(n, triplets);
}

void write_matrix_market(const std::string& path, const SymmetricCsc& a) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail(path, "cannot write file");
  bool ok = std::fprintf(f, "%%%%MatrixMarket matrix coordinate real symmetric\n%d %d %lld\n", a.n,
                         a.n, static_cast<long long>(a.nnz())) > 0;
  for (int j = 0; j < a.n && ok; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1] && ok; ++p) {
      // %.17g: enough digits that every double reads back exactly.
      ok = std::fprintf(f, "%d %d %.17g\n", a.row_idx[p] + 1, j + 1, a.values[p]) > 0;
    }
  }
  // fclose flushes the buffer, so a full disk may only show up here.
  if (std::fclose(f) != 0) ok = false;
  if (!ok) fail(path, "cannot write file");
}

}  // namespace ldlpgs
