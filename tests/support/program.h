#pragma once
// The `ldlpgs` program run as a user runs it (LDLPGS_BIN, this build's program): its exit code,
// standard output and standard error. For the tests of the program (tests/cli/) and of its peers
// subcommand (tests/peers/peers_test.cpp).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/support/temp_files.h"

namespace ldlpgs::testing {

struct Result {
  int code;
  std::string out, err;
};

// `ldlpgs ARGS` through the shell (so ARGS may redirect); standard error through a temporary file.
inline Result run(const std::string& args) {
  const std::string err_path = temp_path("stderr.txt");
  const std::string cmd = std::string(LDLPGS_BIN) + " " + args + " 2>" + err_path;
  Result r{};
  FILE* pipe = popen(cmd.c_str(), "r");
  std::array<char, 4096> buf;
  while (size_t got = fread(buf.data(), 1, buf.size(), pipe)) r.out.append(buf.data(), got);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream in(err_path);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

// Bad input: exit code 2, one line on stderr that contains every fragment.
inline void expect_input_error(const std::string& args, std::initializer_list<std::string> fragments) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not one line: " << r.err;
  for (const std::string& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "'" << f << "' not in: " << r.err;
}

// The JSON the program printed, expecting exit code 0 (an empty object otherwise).
inline nlohmann::json json_of(const std::string& args) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

inline const std::string kMatrices = LDLPGS_MATRICES;
inline const std::string kGymnasium = std::string(LDLPGS_TESTDATA) + "/mjcf/gymnasium";  // MJCF models

// A singular matrix is a numerical failure, not bad input (exit 1, not 2): diag(2, 0, 3) stops
// every sparse solver at row 1 whatever the order, and each says so in its own words (ours and
// CHOLMOD naming the row; tests/peers/competitors_test.cpp and tests/factor/numeric_test.cpp
// check the row in an order that is not the identity).
inline constexpr char kSingular[] = "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 2\n2 2 0\n3 3 3\n";

// A MuJoCo sample model (libmujoco-samples), for the tests built with MuJoCo.
inline const std::string kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";

}  // namespace ldlpgs::testing
