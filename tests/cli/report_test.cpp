// `ldlpgs report`: the report directory's sections, tables and data, and a matrix a solver refuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsReport, WritesTheReportDirectory) {
  const std::string dir = temp_path("report"), matrices = temp_path("matrices");
  std::filesystem::create_directories(matrices);
  std::filesystem::copy_file(kMatrices + "/bcsstk01.mtx", matrices + "/bcsstk01.mtx",
                             std::filesystem::copy_options::overwrite_existing);
  const Result r = run("report --sizes 12 --cases chain-10,four-bar --matrices " + matrices + " --out-dir " + dir +
                       " --no-figures");
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(dir + "/index.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string index = ss.str();
  for (const char* section : {"## 1. Orderings", "## 2. The block LDL^T against CHOLMOD", "## 3. The talk's figures",
                              "## 4. Speed against error", "## 5. Where each solver breaks", "## 6. Watch it move",
                              "## 7. The field's own models", "| humanoid |", "| walker2d |",
                              "bcsstk01.mtx", "chain-12", "| four-bar | ldl-pgs |"})
    EXPECT_NE(index.find(section), std::string::npos) << section;
  EXPECT_NE(r.err.find("report [7/7]"), std::string::npos) << "no progress line: " << r.err;
  // The two viewer pages, embedded: each a page of the recorded run (its data block and three.js)
  // with frames, the one on the ground with its contacts (the browser test checks what a page draws).
  for (const char* scene : {"tracked-vehicle", "multi-wheeled-vehicle-on-ground"}) {
    const std::string page = std::string("view-") + scene + ".html";
    EXPECT_NE(index.find("<iframe src=\"" + page + "\""), std::string::npos) << page;
    std::ifstream html(dir + "/" + page);
    std::stringstream text;
    text << html.rdbuf();
    EXPECT_NE(text.str().find("THREE.WebGLRenderer"), std::string::npos) << page << ": no three.js";
    EXPECT_NE(text.str().find("\"scene\":\"" + std::string(scene) + "\""), std::string::npos) << page << ": not its run";
  }
  EXPECT_EQ(index.find("came apart"), std::string::npos) << "a viewer run came apart";
  EXPECT_LT(index.find("## Key findings"), index.find("## 1. Orderings")) << "the findings open the report";
  for (const char* paper : {"papers/orderings.md", "papers/factor.md", "papers/speed-vs-error.md"})
    EXPECT_NE(index.find(paper), std::string::npos) << paper;
  for (const char* table : {"orderings", "verification", "sweep", "stability", "models"}) {
    std::ifstream json(dir + "/data/" + table + ".json");
    const nlohmann::json rows = nlohmann::json::parse(json)["records"];
    EXPECT_FALSE(rows.empty()) << table;
    // the CSV: a header and one line per row
    std::ifstream csv(dir + "/data/" + table + ".csv");
    int lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, static_cast<int>(rows.size()) + 1) << table;
  }
}

// A matrix a solver refuses is not verified, and said so: not a disagreement, no NaN in the table.
TEST(LdlpgsReport, ARefusedMatrixIsNotVerified) {
  const std::string dir = temp_path("report-refused"), matrices = temp_path("matrices-refused");
  std::filesystem::create_directories(matrices);
  std::filesystem::copy_file(temp_file("singular.mtx", kSingular), matrices + "/singular.mtx",
                             std::filesystem::copy_options::overwrite_existing);
  const Result r = run("report --sizes 10 --cases four-bar --ordering meca --matrices " + matrices + " --out-dir " +
                       dir + " --no-figures");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.out.find("NOT ALL AGREE: 1 not verified (a solver refused the matrix)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("disagree"), std::string::npos) << r.out;
  const size_t row = r.out.find("singular.mtx     best");
  ASSERT_NE(row, std::string::npos) << r.out;
  const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
  EXPECT_NE(line.find("NOT VERIFIED"), std::string::npos) << line;
  EXPECT_EQ(line.find("nan"), std::string::npos) << line;
  std::ifstream in(dir + "/index.md");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("| singular.mtx | best | - | - | - | - | - | - | - | **not verified** |"), std::string::npos);
  EXPECT_NE(ss.str().find("problems agree within max(1e-10, eps cond_1); the largest relative difference of L, D or x is "), std::string::npos);
  EXPECT_NE(ss.str().find("; 1 not verified (a solver refused the matrix) (`"), std::string::npos);
}

}  // namespace
}  // namespace ldlpgs::testing
