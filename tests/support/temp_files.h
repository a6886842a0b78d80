#pragma once
// Temporary files for tests: unique per test and process (ctest runs tests in parallel, each
// in its own process), removed when the test program ends so that runs leave nothing behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace ldlpgs::testing {

inline std::vector<std::string>& temp_files() {
  static std::vector<std::string> files;
  return files;
}

struct RemoveTempFiles : ::testing::Environment {
  void TearDown() override {
    std::error_code ec;
    for (const std::string& path : temp_files()) std::filesystem::remove_all(path, ec);
  }
};
[[maybe_unused]] inline const auto* const remove_temp_files =
    ::testing::AddGlobalTestEnvironment(new RemoveTempFiles);

// A path in the test temp dir named after the current test; it is removed at exit.
inline std::string temp_path(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string path = ::testing::TempDir() + "ldlpgs_" + (info ? info->name() : "global") + "_" +
                           std::to_string(getpid()) + "_" + name;
  temp_files().push_back(path);
  return path;
}

// Writes content to temp_path(name) and returns the path.
inline std::string temp_file(const std::string& name, const std::string& content) {
  const std::string path = temp_path(name);
  std::ofstream out(path, std::ios::binary);
  out << content;
  EXPECT_TRUE(out.good()) << path;
  return path;
}

}  // namespace ldlpgs::testing
