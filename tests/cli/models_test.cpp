// `ldlpgs models`: MJCF files and folders, one row per model beside MuJoCo's own step.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <nlohmann/json.hpp>

#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

#ifdef LDLPGS_HAVE_MUJOCO

// A joint equality (two hinges geared): refused by the conversion, a row that says why.
const std::string kCoupled = R"(<mujoco><worldbody><body name="arm"><joint name="a"/><geom size=".1"/>
  <body name="hand"><joint name="b"/><geom size=".1"/></body></body></worldbody>
  <equality><joint name="gear" joint1="a" joint2="b"/></equality></mujoco>)";

TEST(LdlpgsModels, ARowPerModelLoadedOrRefused) {
  const std::string refused = temp_file("coupled.xml", kCoupled);
  const nlohmann::json j = json_of("models " + kGymnasium + "/hopper.xml " + refused + " --steps 20 --json");
  ASSERT_EQ(j["models"].size(), 2u) << j.dump();
  const nlohmann::json& hopper = j["models"][0];
  EXPECT_EQ(hopper["loaded"], true);
  EXPECT_EQ(hopper["scene"], "hopper");
  EXPECT_EQ(hopper["steps"], 20);
  EXPECT_EQ(hopper["dropped"], "") << "its actuators and joint dynamics are converted: " << hopper.dump();
  EXPECT_GT(hopper["step_us"].get<double>(), 0);
  EXPECT_GT(hopper["mujoco_step_us"].get<double>(), 0);
  EXPECT_LT(hopper["position_error_max_m"].get<double>(), 1e-6);
  EXPECT_TRUE(hopper["failure"].is_null());
  const nlohmann::json& coupled = j["models"][1];
  EXPECT_EQ(coupled["loaded"], false);
  const std::string why = coupled["refused"];
  EXPECT_NE(why.find("coupled.xml"), std::string::npos) << why;
  EXPECT_NE(why.find("equality \"gear\" (joint)"), std::string::npos) << why;
  EXPECT_FALSE(coupled.contains("step_us"));
}

TEST(LdlpgsModels, AFolderIsSearchedInOrder) {
  const std::string dir = temp_path("models-dir");
  std::filesystem::create_directories(dir + "/sub");
  std::filesystem::copy_file(kGymnasium + "/reacher.xml", dir + "/sub/reacher.xml");
  std::filesystem::copy_file(kGymnasium + "/point.xml", dir + "/point.xml");
  const Result r = run("models " + dir + " --steps 5");
  ASSERT_EQ(r.code, 0) << r.err;
  const size_t point = r.out.find("point.xml"), reacher = r.out.find("reacher.xml");
  ASSERT_NE(point, std::string::npos) << r.out;
  ASSERT_NE(reacher, std::string::npos) << r.out;
  EXPECT_LT(point, reacher) << "sorted by path: " << r.out;
}

#endif

}  // namespace
}  // namespace ldlpgs::testing
