#pragma once
// Caps on the sizes an input may declare, checked before anything is allocated for them: a file
// of a few bytes may declare millions of rows, and a family size may exceed memory
// (papers/factor.md, "Verification"). The defaults are far above the matrices and mechanisms this
// library is measured on (tests/data/matrices: 2003 rows at most; mechanisms of 1e6 rows fit)
// and far below what exhausts a 24 GB machine. Process-wide; the program's global flag
// `--no-size-limits` lifts them, a library user sets size_limits() itself.
#include <cstdint>
#include <limits>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

struct SizeLimits {
  int64_t rows = int64_t{1} << 24;         // 16.8M rows of a matrix read from a file
  int64_t entries = int64_t{1} << 28;      // 268M stored entries of a matrix read from a file
  int64_t constraints = int64_t{1} << 22;  // 4.2M constraints of a generated mechanism (FAMILY:N)

  static SizeLimits none() {
    constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
    return {kMax, kMax, kMax};
  }
};

inline SizeLimits& size_limits() {
  static SizeLimits limits;
  return limits;
}

// InputError "<what>: <value> <unit>, more than the limit of <limit> (...)" unless value <= limit.
inline void check_limit(const std::string& what, int64_t value, int64_t limit, const char* unit) {
  if (value <= limit) return;
  throw InputError(what + ": " + std::to_string(value) + " " + unit + ", more than the limit of " +
                   std::to_string(limit) + " (ldlpgs --no-size-limits, or ldlpgs::size_limits(), raises it)");
}

}  // namespace ldlpgs
