// `ldlpgs verify`: agreement with CHOLMOD, a disagreement beyond the tolerance, a singular matrix.
#include <gtest/gtest.h>

#include <string>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsVerify, JsonAgreesWithCholmod) {
  const Result r = run("verify " + kMatrices + "/bcsstk01.mtx --ordering amd --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"nnz_L", "cholmod_nnz_L", "flops", "cholmod_flops", "L_rel_diff", "D_rel_diff", "x_rel_diff",
                          "backward_error", "cholmod_backward_error", "ok"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["ok"].get<bool>());
  EXPECT_EQ(j["nnz_L"], j["cholmod_nnz_L"]);  // auto blocks of bcsstk01 are single rows
  EXPECT_EQ(j["ordering"], "amd");
  EXPECT_LE(j["L_rel_diff"].get<double>(), 1e-10);
  EXPECT_LE(j["backward_error"].get<double>(), 1e-14);
}

TEST(LdlpgsVerify, GeneratedMechanismTable) {
  const Result r = run("verify heavy:10");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("agree"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("heavy-10"), std::string::npos) << r.out;
}

TEST(LdlpgsVerify, DisagreementBeyondToleranceExitsOne) {
  // No tolerance at all: rounding alone makes the factors differ.
  const Result r = run("verify " + kMatrices + "/bcsstk02.mtx --tolerance 0 --per-condition 0");
  EXPECT_EQ(r.code, 1) << r.err << r.out;
  EXPECT_NE(r.out.find("DISAGREE"), std::string::npos) << r.out;
}

TEST(LdlpgsVerify, SingularMatrixIsNotVerified) {
  const std::string f = temp_file("singular.mtx", kSingular);
  const Result r = run("verify " + f);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "");  // CHOLMOD's own warning is its status, not a line on stderr
  EXPECT_NE(r.out.find("NOT VERIFIED: ours failed (above); CHOLMOD stopped at a zero pivot in row 1"), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << "differences of nothing compared: " << r.out;
  const Result json = run("verify " + f + " --json");
  EXPECT_EQ(json.code, 1);
  const nlohmann::json j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["status"], "zero pivot");
  EXPECT_EQ(j["cholmod_row"], 1);
  EXPECT_FALSE(j["ok"].get<bool>());
}

}  // namespace
}  // namespace ldlpgs::testing
