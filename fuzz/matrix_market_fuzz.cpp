// Fuzz target: the Matrix Market reader (sparse/matrix_market.h). Bad input must be an
// InputError; what it accepts must be a valid, finite lower triangle that the writer and the
// reader reproduce exactly.
#include <cmath>

#include "fuzz/fuzz_common.h"
#include "ldlpgs/sparse/matrix_market.h"

using namespace ldlpgs;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::fuzz_size_limits();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::MemoryFile in, out;
  const std::string path = in.write(data, size);
  SymmetricCsc a;
  if (!fuzz::accepted([&] { a = read_matrix_market(path); })) return 0;
  try {
    check_symmetric_csc(a, "read_matrix_market");
  } catch (const ArgumentError& e) {
    fuzz::finding(std::string("the reader returned an invalid matrix: ") + e.what());
  }
  for (const double v : a.values)
    if (!std::isfinite(v)) fuzz::finding("the reader returned a non-finite value");
  // The writer's file (full precision) reads back to the same matrix.
  const std::string copy = out.write(nullptr, 0);
  SymmetricCsc b;
  if (!fuzz::accepted([&] {
        write_matrix_market(copy, a);
        b = read_matrix_market(copy);
      }))
    fuzz::finding("the reader refused what the writer wrote of an accepted matrix");
  if (b.n != a.n || b.col_ptr != a.col_ptr || b.row_idx != a.row_idx || b.values != a.values)
    fuzz::finding("write then read changed the matrix");
  return 0;
}
