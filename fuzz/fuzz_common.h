#pragma once
// What every fuzz target shares: the fuzzed bytes as a file the readers open by name, and the
// rule that InputError and ArgumentError are the library's normal answers to bad input
// (DEVELOPERS.md, kinds of error) while anything else is a finding.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/limits.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs::fuzz {

// A finding: say what and abort, so that libFuzzer keeps the input.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FINDING: %s\n", printable(what, 2000).c_str());
  std::abort();
}

// The bytes as a file in memory (memfd: no disk, no file left behind), reached by the path
// /proc/self/fd/N that fopen and ifstream accept; rewritten in place on every run.
class MemoryFile {
 public:
  MemoryFile() : fd_(memfd_create("ldlpgs-fuzz", 0)) {
    if (fd_ < 0) finding("memfd_create failed");
  }
  ~MemoryFile() { close(fd_); }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;

  std::string write(const uint8_t* data, size_t size) {
    if (ftruncate(fd_, 0) != 0 || pwrite(fd_, data, size, 0) != static_cast<ssize_t>(size)) finding("memfd write failed");
    return "/proc/self/fd/" + std::to_string(fd_);
  }

 private:
  int fd_;
};

// Runs f; InputError and ArgumentError are normal outcomes (false), any other exception is a
// finding. True when f returned.
template <class F>
bool accepted(F&& f) {
  try {
    f();
    return true;
  } catch (const InputError&) {
    return false;
  } catch (const ArgumentError&) {
    return false;
  } catch (const std::exception& e) {
    finding(std::string("unexpected exception: ") + e.what());
  } catch (...) {
    finding("unexpected non-standard exception");
  }
}

// Declared sizes within what a fuzzer's 2 GB can hold while allocating for them (the caps are
// the library's own protection, sparse/limits.h; the defaults allow 16.8M rows).
inline void fuzz_size_limits() {
  size_limits() = SizeLimits{int64_t{1} << 16, int64_t{1} << 20, int64_t{1} << 12};
}

}  // namespace ldlpgs::fuzz
