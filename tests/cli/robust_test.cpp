// Robustness of the program, one test per class of finding. Each failed on the main of 0c33819;
// the physics-side classes, on the main of 0241fc1 (the old program: exit 0 with a negative
// timestep, NaN in the trace and in H.mtx, a scene spy wrote that step refused, exit 0 on a chain
// 48.9 m apart).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <utility>
#include <nlohmann/json.hpp>

#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

// Class 1: matrices without stored entries aborted in CHOLMOD (terminate, status -4).
TEST(LdlpgsRobust, MatricesWithoutEntriesDoNotAbort) {
  const std::string empty0 = temp_file("empty0.mtx", "%%MatrixMarket matrix coordinate real symmetric\n0 0 0\n");
  const std::string empty5 = temp_file("empty5.mtx", "%%MatrixMarket matrix coordinate real symmetric\n5 5 0\n");
  for (const char* command : {"verify", "bench", "order --cholmod"}) {
    expect_input_error(std::string(command) + " " + empty0, {empty0, "0 x 0"});
    // All zero: singular, so verify and bench report it (exit 1 or 0), never abort.
    const Result r = run(std::string(command) + " " + empty5);
    EXPECT_TRUE(r.code == 0 || r.code == 1) << command << ": exit " << r.code << "\n" << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  }
}

// Class 3: a size line declaring 2^31 - 1 rows overflowed n + 1 and ended in length_error; 30M
// rows took 1.6 GB; a family size of 2e9 ended in bad_alloc. Now refused before allocating.
TEST(LdlpgsRobust, DeclaredSizesBeyondTheLimitsAreRefusedBeforeAllocating) {
  const std::string huge = temp_file("huge.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2147483647 2147483647 1\n1 1 1\n");
  const std::string big = temp_file("big.mtx", "%%MatrixMarket matrix coordinate real symmetric\n30000000 30000000 1\n1 1 1\n");
  for (const char* command : {"order", "verify"}) {
    expect_input_error(std::string(command) + " " + huge, {huge + ":2", "rows", "limit", "--no-size-limits"});
    expect_input_error(std::string(command) + " " + big, {big + ":2", "30000000 rows"});
  }
  expect_input_error("verify chain:2000000000", {"chain", "2000000000 constraints", "limit"});
  // The global flag is accepted (matrix_market_test checks that lifted limits read the file).
  EXPECT_EQ(run("--no-size-limits order " + kMatrices + "/can___24.mtx --ordering natural").code, 0);
}

// Class 8: a JSON syntax error echoed the whole token (a 1 MB line, a 1 MB message) and raw
// control bytes; a NUL inside a matrix entry cut the message short.
TEST(LdlpgsRobust, MessagesAreOneBoundedPrintableLine) {
  std::string token(1 << 20, 'x');
  token[5] = '\x01';
  const std::string json = temp_file("long.json", "{\"name\": \"" + token);  // unterminated string
  Result r = run("step " + json);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 600);
  for (char c : r.err.substr(0, r.err.size() - 1)) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);

  static const char kNul[] = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\0x\n2 2 1\n";
  const std::string nul = temp_file("nul.mtx", std::string(kNul, sizeof(kNul) - 1));
  r = run("order " + nul);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("\\x00"), std::string::npos) << r.err;  // escaped, and the message goes on after it
}

// Readers, numerics and messages

// Class 8: order printed nnz(A) as 2 nnz - n, which assumes a stored diagonal: -5 for an empty
// 5 x 5, 1 for a 3 x 3 with one diagonal and one off-diagonal entry (it has 3).
TEST(LdlpgsRobust, OrderCountsTheEntriesOfTheFullMatrix) {
  const std::string empty5 = temp_file("empty5.mtx", "%%MatrixMarket matrix coordinate real symmetric\n5 5 0\n");
  Result r = run("order " + empty5 + " --ordering natural");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nnz(A) = 0\n"), std::string::npos) << r.out;
  const std::string partial = temp_file("partial.mtx", "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 2\n3 1 1\n");
  r = run("order " + partial + " --ordering natural");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("nnz(A) = 3\n"), std::string::npos) << r.out;
  // A full diagonal: bcsstk01 stores 224 entries below and on its 48-entry diagonal.
  r = run("order " + kMatrices + "/bcsstk01.mtx --ordering natural");
  const SymmetricCsc a = read_matrix_market(kMatrices + "/bcsstk01.mtx");
  EXPECT_NE(r.out.find("nnz(A) = " + std::to_string(2 * a.nnz() - a.n) + "\n"), std::string::npos) << r.out;
}

// Class 8: the blocks file reader copied the offending line raw and whole into its message, which
// main's last-resort cut ended mid-quote at 400 characters; the reader quotes it escaped and
// bounded itself, and main keeps those escapes (it doubled their backslashes: \\x01).
TEST(LdlpgsRobust, BlocksFileMessagesAreOneBoundedPrintableLine) {
  std::string junk = "6\n\x01\x02" + std::string(100000, '9') + std::string("\0\x80\r", 3) + "\n";
  const std::string blocks = temp_file("junk.blocks", junk);
  const Result r = run("order " + kMatrices + "/bcsstk01.mtx --blocks " + blocks);
  EXPECT_EQ(r.code, 2) << r.err.substr(0, 300);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_LT(r.err.size(), 600u) << r.err.substr(0, 600);
  EXPECT_NE(r.err.find(blocks + ":2: "), std::string::npos) << r.err.substr(0, 600);
  EXPECT_NE(r.err.find("got '\\x01\\x02999"), std::string::npos) << r.err;
  EXPECT_TRUE(r.err.ends_with("...'\n")) << r.err;  // the reader's own cut, the quote closed
  for (char c : r.err.substr(0, r.err.size() - 1)) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c);
}

// A diagonal or 2 x 2 matrix as a Matrix Market file, values to full precision.
std::string small_matrix(const std::string& name, std::initializer_list<std::array<double, 3>> entries, int n) {
  std::string text = "%%MatrixMarket matrix coordinate real symmetric\n" + std::to_string(n) + " " +
                     std::to_string(n) + " " + std::to_string(entries.size()) + "\n";
  for (const auto& [i, j, v] : entries) {
    char line[80];
    std::snprintf(line, sizeof line, "%d %d %.17g\n", static_cast<int>(i), static_cast<int>(j), v);
    text += line;
  }
  return temp_file(name, text);
}

// Class 6: 1e-314 factored "ok" and solved to NaN, a positive definite 2 x 2 at 1e-320 was "not
// finite, pivot -inf"; CHOLMOD solves both, and verify now agrees with it.
TEST(LdlpgsRobust, VerifyAtTheEdgesOfDouble) {
  for (const std::string& m : {small_matrix("tiny1.mtx", {{1, 1, 1e-314}}, 1),
                               small_matrix("tiny2.mtx", {{1, 1, 2e-320}, {2, 2, 2e-320}, {2, 1, 1e-320}}, 2),
                               small_matrix("huge2.mtx", {{1, 1, 2e307}, {2, 2, 2e307}, {2, 1, 1e307}}, 2)}) {
    const Result r = run("verify " + m + " --json");
    EXPECT_EQ(r.code, 0) << m << "\n" << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["status"], "ok") << m;
    EXPECT_TRUE(j["verifiable"].get<bool>()) << m;
    // cond_1 is 1 and 3 (Hager's estimate is a lower bound): not inf as ||A^-1|| alone is at 1e-314.
    const double cond = j["condition_estimate"].get<double>();
    EXPECT_TRUE(cond >= 1 && cond <= 3 + 1e-12) << m << ": " << cond;
  }
}

// Class 6: a condition estimate that overflowed made the tolerance inf, and verify printed "agree"
// (x 5.27 off); a finite one above 1 / eps makes a tolerance of 1 or more that checks no digit.
TEST(LdlpgsRobust, VerifyNeverAgreesOnAToleranceThatChecksNothing) {
  for (int e : {500, 750}) {  // cond_1 = 2^1000 (tolerance 2e285), 2^1500 (estimate inf)
    const double big = std::ldexp(1.0, e);
    const std::string m = small_matrix("cond" + std::to_string(e) + ".mtx", {{1, 1, big}, {2, 2, 1 / big}}, 2);
    Result r = run("verify " + m);
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("CANNOT VERIFY"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("agree"), std::string::npos) << r.out;
    r = run("verify " + m + " --json");
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_FALSE(j["verifiable"].get<bool>());
  }
}

// Physics-side classes.
#ifdef LDLPGS_HAVE_MUJOCO
// Class 4: MJCF is checked before and after MuJoCo: a negative timestep was stepped ("5 steps of
// -0.01 s", exit 0); MuJoCo's massless world body was written as -nan in the trace.
TEST(LdlpgsRobust, MjcfTimestepAndTraceOfTheWorld) {
  const std::string body = R"(<worldbody><body name="arm"><joint axis="1 0 0" pos="0 0 1"/><geom size=".1"/></body></worldbody>)";
  const std::string negative = temp_file("negative.xml", "<mujoco><option timestep=\"-0.01\"/>" + body + "</mujoco>");
  expect_input_error("step " + negative + " --steps 5", {"negative.xml: option timestep", "-0.01"});
  const std::string trace = temp_path("world.csv");
  const std::string model = temp_file("model.xml", "<mujoco>" + body + "</mujoco>");
  ASSERT_EQ(run("step " + model + " --steps 2 --trace-file " + trace).code, 0);
  std::ifstream in(trace);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\n0,0,world,0,0,0,1,0,0,0"), std::string::npos) << text.substr(0, 300);
  EXPECT_EQ(text.find("nan"), std::string::npos) << text.substr(0, 300);
}
#endif

// Class 5: export wrote NaN and inf into H.mtx with exit 0 (a mass of 1e-320, an anchor at
// 1e155, a coordinate of 1e308), which verify then refused. Now exit 2 naming the body or
// constraint, and no matrix written.
TEST(LdlpgsRobust, ExportNeverWritesNonFiniteEntries) {
  auto scene = [](const char* mass, const char* position, const char* anchor) {
    std::string s = R"({"bodies": [{"name": "ground", "static": true, "position": [0, 0, 0]}, {"name": "bob", "mass": )";
    s += mass;
    s += R"(, "inertia": [1, 1, 1], "position": [)";
    s += position;
    s += R"(, 0, 0]}], "constraints": [{"type": "ball", "bodies": ["ground", "bob"], "anchor": [)";
    s += anchor;
    s += ", 0, 0]}]}";
    return s;
  };
  const std::pair<std::string, std::string> cases[] = {
      {scene("1e-320", "1", "0"), "body \"bob\": mass 1e-320"},
      {scene("1", "1", "1e155"), "constraint 0 (ball between body \"ground\" and body \"bob\"): anchor 1e+155"},
      {scene("1", "1e308", "0"), "body \"bob\": position 1e+308"}};
  for (const auto& [text, words] : cases) {
    const std::string path = temp_file("overflow.json", text), mtx = temp_path("overflow.mtx");
    expect_input_error("export " + path + " --matrix-file " + mtx + " --blocks-file " + temp_path("o.blocks"),
                       {"overflow.json: " + words});
    EXPECT_FALSE(std::filesystem::exists(mtx));
  }
}

// Class 7: a user's body named "chassis#1" shared its name with a shard, so the scene spy
// --scene-out wrote was refused by step ("duplicate body name").
TEST(LdlpgsRobust, SpySceneOfAShatteredMechanismSteps) {
  std::ifstream in(std::string(LDLPGS_TESTDATA) + "/../../physics/scenes/multi-wheeled-vehicle.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  for (const char* name : {"chassis#1", "chassis#2"})
    scene["bodies"].push_back({{"name", name}, {"mass", 1}, {"inertia", {1, 1, 1}}, {"position", {0, 9, 0}}});
  const std::string path = temp_file("named.json", scene.dump()), out = temp_path("shattered.json");
  const Result spy = run("spy " + path + " --scene-out " + out + " --json-file " + temp_path("spy.json"));
  ASSERT_EQ(spy.code, 0) << spy.err;
  const Result step = run("step " + out + " --no-shatter --steps 3");
  EXPECT_EQ(step.code, 0) << step.err;
}

// Class 10: a mass ratio of 1e12 ended every solver's 5 m heavy chain 48.9 m apart in 1000
// steps, and PGS's 100-link chain 5.15 m (6e17 m later on), all with exit 0. Now exit 1 naming
// the step and the error against the mechanism's size; within the supported range, exit 0.
TEST(LdlpgsRobust, MassRatioBeyondTheSupportedRangeExitsOne) {
  for (const char* solver : {"direct", "ldl-pgs", "pgs", "block-gs"}) {
    const Result r = run(std::string("step heavy-chain-10-1e12 --steps 1000 --json --solver ") + solver);
    EXPECT_EQ(r.code, 1) << solver << ": " << r.err;
    EXPECT_NE(r.err.find("it came apart"), std::string::npos) << r.err;
    EXPECT_NE(nlohmann::json::parse(r.out)["failure"].get<std::string>().find("size 4.75 m"), std::string::npos);
  }
  const Result hundred = run("step heavy-chain-100-1e12 --steps 200 --solver pgs");
  EXPECT_EQ(hundred.code, 1) << hundred.err;
  EXPECT_NE(hundred.err.find("it came apart"), std::string::npos) << hundred.err;
  const Result supported = run("step heavy-chain-10-1e6 --steps 1000 --json");
  EXPECT_EQ(supported.code, 0) << supported.err;
  EXPECT_TRUE(nlohmann::json::parse(supported.out)["failure"].is_null());
}

}  // namespace
}  // namespace ldlpgs::testing
