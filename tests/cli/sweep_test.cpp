// `ldlpgs sweep`: its runs are the step command's; failures and the stability table.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

nlohmann::json sweep_points(const std::string& args) {
  const std::string file = temp_path("sweep.json");
  const Result r = run("sweep " + args + " --json-file " + file);
  EXPECT_EQ(r.code, 0) << r.err;
  std::ifstream in(file);
  return nlohmann::json::parse(in)["points"];
}

const nlohmann::json& point(const nlohmann::json& points, const std::string& solver, int iterations) {
  for (const auto& p : points)
    if (p["solver"] == solver && p["iterations"] == iterations) return p;
  ADD_FAILURE() << solver << " " << iterations << " not in the sweep";
  return points[0];
}

// The sweep's runs are the step command's: the same scene, solver and steps (1 s of 10 ms steps)
// give the same largest error; a run the sweep calls an energy blow-up gains energy in the step
// command too (one PGS sweep a step pumps energy into the chain: -245 J to 8114 J). More PGS
// sweeps bring the error down.
TEST(LdlpgsSweep, PointsAreTheStepCommandsRuns) {
  const nlohmann::json points = sweep_points("--cases chain-10 --iterations 1,64");
  ASSERT_EQ(points.size(), 7u);  // pgs, block-gs, ldl-pgs at two counts, direct
  for (const auto& p : points) {
    const std::string solver = p["solver"].get<std::string>(), iterations = std::to_string(p["iterations"].get<int>());
    const Result r = run("step chain-10 --no-shatter --steps 100 --json --solver " + solver + " --iterations " + iterations);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const double e0 = j["energy_initial_j"].get<double>(), e1 = j["energy_final_j"].get<double>();
    if (p["failure"] == "energy") {
      EXPECT_GT(e1 - e0, 100) << solver << " " << iterations;
    }
    if (!p["failed"].get<bool>()) {
      EXPECT_DOUBLE_EQ(p["position_error_max_m"].get<double>(), j["position_error_max_m"].get<double>()) << solver << " " << iterations;
    }
  }
  EXPECT_TRUE(point(points, "pgs", 1)["failed"].get<bool>());
  EXPECT_LT(point(points, "pgs", 64)["position_error_m"].get<double>(), 1e-6);
  EXPECT_LT(point(points, "ldl-pgs", 1)["position_error_m"].get<double>(), 1e-6);
}

// A 1:1000 load tears a PGS chain apart at 4 sweeps (energy blow-up: the sweep marks it failed)
// and LDL-PGS holds it at one; raising the ratio breaks PGS first.
TEST(LdlpgsSweep, FailuresAndStability) {
  const nlohmann::json points = sweep_points("--cases heavy-chain-10-1000 --iterations 1,4");
  EXPECT_TRUE(point(points, "pgs", 4)["failed"].get<bool>());
  EXPECT_TRUE(point(points, "pgs", 4)["position_error_m"].is_null());
  EXPECT_FALSE(point(points, "ldl-pgs", 1)["failed"].get<bool>());
  EXPECT_LT(point(points, "ldl-pgs", 1)["position_error_m"].get<double>(), 1e-6);
  const Result r = run("sweep --cases chain-10 --iterations 1 --seconds 0.5 --stability");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| chain-10 | ldl-pgs | 10 |"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ldlpgs::testing
