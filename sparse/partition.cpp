#include "ldlpgs/sparse/partition.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <string_view>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {
namespace {

void check_max_size(int max_size) {
  if (max_size < 1) {
    throw InputError("maximum block size must be at least 1, got " + std::to_string(max_size));
  }
}

std::string_view trim(std::string_view s) {
  auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

// Rows r and r+1 are merged when (column set of row r) + {r} == (column set of row r+1) + {r+1}.
// For that, each must contain the other (they are adjacent) and all other neighbours must match,
// so comparing N(r) \ {r+1} with N(r+1) \ {r} is enough.
bool same_pattern(const Graph& g, int r) {
  const auto a = g.neighbors(r);
  const auto b = g.neighbors(r + 1);
  if (!std::binary_search(a.begin(), a.end(), r + 1)) return false;
  if (a.size() != b.size()) return false;
  size_t i = 0, k = 0;
  while (i < a.size() || k < b.size()) {
    if (i < a.size() && a[i] == r + 1) {
      ++i;
    } else if (k < b.size() && b[k] == r) {
      ++k;
    } else if (i < a.size() && k < b.size() && a[i] == b[k]) {
      ++i;
      ++k;
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace

std::vector<int> partition_uniform(int n, int size) {
  if (size < 1) throw InputError("block size must be positive, got " + std::to_string(size));
  std::vector<int> blocks(n / size, size);
  if (n % size != 0) blocks.push_back(n % size);
  return blocks;
}

std::vector<int> partition_auto(const SymmetricCsc& a, int max_size) {
  check_max_size(max_size);
  const Graph g = graph_of(a);
  std::vector<int> blocks;
  int start = 0;  // first row of the current run of identical rows
  for (int r = 0; r < a.n; ++r) {
    if (r + 1 < a.n && same_pattern(g, r)) continue;
    // Rows start..r form a maximal run: cut it into full blocks and the remainder.
    const int length = r + 1 - start;
    blocks.insert(blocks.end(), length / max_size, max_size);
    if (length % max_size != 0) blocks.push_back(length % max_size);
    start = r + 1;
  }
  return blocks;
}

std::vector<int> partition_refine(const SymmetricCsc& a, std::span<const int> blocks) {
  int64_t sum = 0;
  for (int size : blocks) {
    if (size < 1) throw ArgumentError("partition_refine: block size " + std::to_string(size) + " is not positive");
    sum += size;
  }
  if (sum != a.n) {
    throw ArgumentError("partition_refine: block sizes sum to " + std::to_string(sum) + ", the matrix has " +
                        std::to_string(a.n) + " rows");
  }
  const Graph g = graph_of(without_zeros(a));
  std::vector<int> refined;
  int first = 0;  // first row of the current given block
  for (int size : blocks) {
    int start = first;  // first row of the current run of identical rows
    for (int r = first; r < first + size; ++r) {
      if (r + 1 < first + size && same_pattern(g, r)) continue;
      refined.push_back(r + 1 - start);
      start = r + 1;
    }
    first += size;
  }
  return refined;
}

std::vector<int> read_partition(const std::string& path, int n) {
  // Every message quotes the file name and the line through printable(): one bounded line of
  // printable characters whatever the file holds (binary, a NUL, a megabyte-long line).
  LineReader lines(path);
  const std::string& name = lines.name();
  std::vector<int> blocks;
  int64_t sum = 0;
  int64_t over_at = 0;  // the line at which the sizes first exceeded n (0: not yet)
  // A size is a few bytes; a megabyte is for comments. Past it the file is binary (/dev/zero).
  constexpr size_t kMaxLineLength = size_t{1} << 20;
  std::string_view text;
  for (LineReader::Got got; (got = lines.next(text, kMaxLineLength)) != LineReader::Got::end;) {
    const int64_t line = lines.number();
    const std::string where = name + ":" + std::to_string(line) + ": ";
    const std::string_view s = trim(text);
    const bool comment = s.empty() || s.front() == '#' || s.front() == '%';
    // (a line the reader cut is never a size: what it starts with is named, unless a comment)
    if (got == LineReader::Got::too_long && comment)
      throw InputError(where + "a line longer than 1 MiB: not a block partition");
    if (comment) continue;
    int size = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), size);
    if (ec != std::errc() || end != s.data() + s.size() || got == LineReader::Got::too_long) {
      std::string message = where + "expected a positive integer block size, got '";
      message += printable(s, 40);
      throw InputError(message + "'");
    }
    if (size < 1) {
      throw InputError(where + "block size must be positive, got " + std::to_string(size));
    }
    // Past n the file is wrong whatever follows: the rest is still checked line by line, but not
    // stored nor summed, so a huge file of 1s takes neither memory nor an overflowing sum.
    if (over_at) continue;
    blocks.push_back(size);
    sum += size;
    if (sum > n) over_at = line;
  }
  if (over_at) {
    throw InputError(name + ":" + std::to_string(over_at) + ": block sizes reach " + std::to_string(sum) +
                     ", more than the matrix's " + std::to_string(n) + " rows");
  }
  if (sum != n) {
    throw InputError(name + ": block sizes sum to " + std::to_string(sum) + ", the matrix has " +
                     std::to_string(n) + " rows");
  }
  return blocks;
}

std::vector<int> parse_partition(const std::string& spec, const SymmetricCsc& a, int max_size) {
  check_max_size(max_size);
  if (spec == "auto") return partition_auto(a, max_size);
  // An optional sign then digits is meant as a block size, never as a file name: "-3" or "0"
  // deserve "must be positive" rather than "cannot open file".
  const std::string_view digits = std::string_view(spec).substr(
      !spec.empty() && (spec[0] == '-' || spec[0] == '+') ? 1 : 0);
  const bool numeric = !digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
  if (numeric) {
    int size = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), size);
    if (spec[0] == '-' || ec != std::errc() || end != digits.data() + digits.size() || size < 1) {
      throw InputError("--blocks " + spec + ": block size must be a positive integer");
    }
    return partition_uniform(a.n, size);
  }
  return read_partition(spec, a.n);
}

}  // namespace ldlpgs
