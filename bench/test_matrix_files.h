#pragma once
// The symmetric test matrices the benchmarks run on: every .mtx in dir except the unsymmetric
// Pd.mtx, sorted by name. Prints the reason and returns nothing when dir cannot be read.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace ldlpgs {

inline std::vector<std::filesystem::path> test_matrix_files(const std::filesystem::path& dir, const char* program) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() == ".mtx" && e.path().filename() != "Pd.mtx") files.push_back(e.path());
  }
  if (ec) {
    std::fprintf(stderr, "%s: %s: %s\n", program, dir.c_str(), ec.message().c_str());
    return {};
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace ldlpgs
