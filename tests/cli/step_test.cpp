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
  EXPECT_EQ(r.err, "") << "nothing dropped: its geoms, joint dynamics and 21 actuators are converted";
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["bodies"], 17) << "16 bodies and the world";
  EXPECT_EQ(j["actuators"], 21);
  EXPECT_LT(j["position_error_max_m"].get<double>(), 1e-6) << "falling at rest";
}

// --controls and --controls-file drive the actuators: the inverted pendulum's cart (its one
// motor) pushed one way moves that way, and the other way the other; bad controls exit 2 naming
// what is wrong.
TEST(LdlpgsStep, ControlsDriveTheActuators) {
  const std::string model = kGymnasium + "/inverted_pendulum.xml";
  const auto cart_x = [&](const std::string& controls) {
    const std::string trace = temp_path("controls_trace.csv");
    const Result r = run("step " + model + " --steps 25 --json --trace-file " + trace + " " + controls);
    EXPECT_EQ(r.code, 0) << controls << ": " << r.err;
    std::ifstream in(trace);
    std::string line, last;
    while (std::getline(in, line))
      if (line.find(",cart,") != std::string::npos) last = line;
    // step,time,body,x,...
    size_t at = 0;
    for (int field = 0; field < 3; ++field) at = last.find(',', at) + 1;
    return std::stod(last.substr(at));
  };
  const double free = cart_x("");  // the pole's fall alone moves the cart a little
  EXPECT_LT(std::abs(free), 0.01);
  EXPECT_GT(cart_x("--controls 2"), free + 0.05);
  EXPECT_LT(cart_x("--controls -2"), free - 0.05);
  const std::string csv = temp_file("controls.csv", "time,slide\n0,0\n0.2,2\n");
  const double later = cart_x("--controls-file " + csv);  // pushed from 0.2 s of 0.5 on
  EXPECT_GT(later, free + 0.01);
  EXPECT_LT(later, cart_x("--controls 2") - 0.01);

  const auto refused = [&](const std::string& controls, const std::string& named) {
    const Result r = run("step " + model + " --steps 2 " + controls);
    EXPECT_EQ(r.code, 2) << controls;
    EXPECT_NE(r.err.find(named), std::string::npos) << controls << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
  };
  refused("--controls 1,2", "2 given, the model has 1 actuators");
  refused("--controls 4", "actuator \"slide\" (0): 4 outside its ctrlrange [-3, 3]");
  refused("--controls nan", "actuator \"slide\" (0): not a finite number");
  refused("--controls-file " + temp_file("bad.csv", "time,u\n0,1\n0.1,x\n"), "bad.csv:3: not a row of numbers");
  refused("--controls-file " + temp_file("back.csv", "0,1\n0.2,1\n0.1,1\n"), "back.csv:3: time 0.1");
  refused("--controls-file " + temp_file("range.csv", "0,9\n"), "range.csv:1: actuator \"slide\"");
  refused("--controls 1 --controls-file " + csv, "excludes");
}

// A model with something unmodelled that changes its dynamics: exit 2 naming it, unless
// --allow-dropped, which steps it with the list on standard error.
TEST(LdlpgsStep, UnmodelledDynamicsAreRefusedUnlessAllowed) {
  const std::string model = temp_file("tendon.xml", "<mujoco><worldbody><body><joint name=\"j\"/><geom size=\".1\"/>"
                                                    "</body></worldbody><tendon><fixed name=\"t\" limited=\"true\" "
                                                    "range=\"-1 1\"><joint joint=\"j\" coef=\"1\"/></fixed></tendon></mujoco>");
  const Result refused = run("step " + model + " --steps 2");
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("tendon \"t\""), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--allow-dropped"), std::string::npos) << refused.err;
  const Result allowed = run("step " + model + " --steps 2 --allow-dropped");
  EXPECT_EQ(allowed.code, 0) << allowed.err;
  EXPECT_NE(allowed.err.find("dropped: 1 tendons"), std::string::npos) << allowed.err;
  EXPECT_NE(allowed.err.find("tendon \"t\": its range"), std::string::npos) << allowed.err;
}

#endif

}  // namespace
}  // namespace ldlpgs::testing
