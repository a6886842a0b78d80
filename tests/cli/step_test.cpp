// `ldlpgs step`: its JSON, the trace, applied loads, shattered scenes and MJCF models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsStep, JsonFieldsOnABuiltInScene) {
  const Result r = run("step heavy-chain-10-1000 --steps 50 --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"steps", "solver", "iterations", "solve_us", "position_error_max_m", "angular_error_max_rad",
                          "velocity_residual_max", "energy_initial_j", "energy_final_j"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["steps"], 50);
  EXPECT_EQ(j["solver"], "ldl-pgs");
  EXPECT_GT(j["solve_us"].get<double>(), 0);
  EXPECT_LT(j["position_error_max_m"].get<double>(), 1e-3);
}

TEST(LdlpgsStep, TraceHasOneRowPerStepAndBody) {
  const std::string trace = temp_path("trace.csv");
  const Result r = run("step pendulum --steps 7 --solver direct --trace-file " + trace);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  std::ifstream in(trace);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "step,time,body,x,y,z,qw,qx,qy,qz,fx,fy,fz,tx,ty,tz");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  const Result j = run("step pendulum --steps 1 --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(rows, 8 * nlohmann::json::parse(j.out)["bodies"].get<int>());  // steps 0..7, every body
}

// A driven scene says what drives it: the crank's torque in the text, the JSON and the trace.
TEST(LdlpgsStep, PrintsAndTracesTheScenesLoads) {
  const Result text = run("step driven-crank --steps 3");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("applied loads         1 bodies, largest force 0 N, largest torque 1 N m"), std::string::npos)
      << text.out;
  const Result j = run("step driven-crank --steps 3 --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(nlohmann::json::parse(j.out)["loaded_bodies"], 1);
  EXPECT_EQ(nlohmann::json::parse(j.out)["applied_torque_max_nm"], 1.0);
  const std::string trace = temp_path("crank.csv");
  ASSERT_EQ(run("step driven-crank --steps 1 --trace-file " + trace).code, 0);
  std::ifstream in(trace);
  std::string line;
  bool torque = false;
  while (std::getline(in, line)) torque = torque || line.find(",0,0,0,0,0,1") != std::string::npos;
  EXPECT_TRUE(torque) << "no trace row carries the crank's torque (0, 0, 1) N m";
}

// The trace names the scene's own bodies, shattered or not, and they move alike: the shards'
// whole_body against the whole body, 0.2 s of direct steps. Bound: 1e-4 m, what
// tests/physics/shatter_test.cpp measures and bounds for this vehicle over a whole second (6.5e-5 m).
TEST(LdlpgsStep, ShatteredSceneTracesTheScenesBodies) {
  const std::string whole = temp_path("whole.csv"), shattered = temp_path("shattered.csv");
  const Result a = run("step multi-wheeled-vehicle --solver direct --steps 20 --no-shatter --trace-file " + whole + " --json");
  const Result b = run("step multi-wheeled-vehicle --solver direct --steps 20 --trace-file " + shattered + " --json");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  const nlohmann::json ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja["shattered_bodies"], 0);
  EXPECT_EQ(jb["shattered_bodies"], 1);  // the chassis
  EXPECT_EQ(jb["bodies"].get<int>(), 21 + jb["welds"].get<int>());
  std::ifstream ta(whole), tb(shattered);
  std::string la, lb;
  int rows = 0;
  double largest = 0;
  while (std::getline(ta, la)) {
    ASSERT_TRUE(std::getline(tb, lb)) << "the shattered trace is shorter";
    if (rows++ == 0) continue;  // header
    std::vector<std::string> fa, fb;
    std::stringstream sa(la), sb(lb);
    for (std::string f; std::getline(sa, f, ',');) fa.push_back(f);
    for (std::string f; std::getline(sb, f, ',');) fb.push_back(f);
    ASSERT_EQ(fa.size(), 16u);
    ASSERT_EQ(fb.size(), 16u);
    EXPECT_EQ(fa[2], fb[2]);  // the same body
    for (int x = 3; x < 6; ++x) largest = std::max(largest, std::abs(std::stod(fa[x]) - std::stod(fb[x])));
  }
  EXPECT_FALSE(std::getline(tb, lb)) << "the shattered trace is longer";
  EXPECT_EQ(rows, 1 + 21 * 21);  // steps 0..20, the scene's 21 bodies
  std::printf("largest coordinate difference of a body, shattered against whole, 20 steps: %.3e m\n", largest);
  EXPECT_LT(largest, 1e-4);
}

#ifdef LDLPGS_HAVE_MUJOCO

TEST(LdlpgsStep, MjcfHumanoid) {
  ASSERT_TRUE(std::filesystem::exists(kHumanoid)) << kHumanoid << " missing (libmujoco-samples)";
  const Result r = run("step " + kHumanoid + " --no-shatter --steps 50 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line of what was dropped: " << r.err;
  EXPECT_NE(r.err.find("dropped: 21 actuators"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("geoms"), std::string::npos) << "every geom of the humanoid is a shape: " << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["bodies"], 17) << "16 bodies and the world";
  EXPECT_LT(j["position_error_max_m"].get<double>(), 1e-6) << "falling at rest";
}

#endif

}  // namespace
}  // namespace ldlpgs::testing
