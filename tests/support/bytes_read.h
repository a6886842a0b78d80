#pragma once
// What a test reads: the readers that refuse binary or endless input at their first chunk are
// checked by the bytes the process read (matrix_market_test, scene_test).
#include <cstdint>
#include <fstream>
#include <functional>
#include <string>

namespace testing {

// The bytes the process reads (Linux's /proc/self/io rchar) while fn runs; -1 if unknown.
inline int64_t bytes_read_by(const std::function<void()>& fn) {
  auto rchar = []() -> int64_t {
    std::ifstream io("/proc/self/io");
    std::string key;
    int64_t value;
    while (io >> key >> value) {
      if (key == "rchar:") return value;
    }
    return -1;
  };
  const int64_t before = rchar();
  fn();
  const int64_t after = rchar();
  return before < 0 || after < 0 ? -1 : after - before;
}

}  // namespace testing
