// Fuzz target: the blocks file reader (read_partition, sparse/partition.h). The first two bytes
// are the matrix's row count, the rest the file. Bad input must be an InputError; what it
// accepts must be positive sizes summing to n.
#include <cstdint>
#include <numeric>

#include "fuzz/fuzz_common.h"
#include "ldlpgs/sparse/partition.h"

using namespace ldlpgs;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::MemoryFile in;
  if (size < 2) return 0;
  const int n = data[0] | data[1] << 8;
  const std::string path = in.write(data + 2, size - 2);
  std::vector<int> blocks;
  if (!fuzz::accepted([&] { blocks = read_partition(path, n); })) return 0;
  int64_t sum = 0;
  for (const int b : blocks) {
    if (b < 1) fuzz::finding("a block size below 1 was accepted");
    sum += b;
  }
  if (sum != n) fuzz::finding("accepted block sizes that do not sum to n");
  return 0;
}
