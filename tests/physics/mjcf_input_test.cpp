// The MJCF input check (physics/io/mjcf_input.h) against MuJoCo 2.2.2's own loader (Debian's
// libmujoco-dev), the reference: what MuJoCo loads with finite numbers passes (every <option>
// attribute and <flag> keyword of its schema, every shipped and Gymnasium model, numbers written
// as MuJoCo and tinyxml2 read them, includes found where MuJoCo finds them), and a non-finite
// number in a numeric attribute is refused, naming file, line, element and attribute.
#include "ldlpgs/physics/io/mjcf_input.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"
#include "tests/support/temp_files.h"

#ifdef LDLPGS_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace ldlpgs {
namespace {

using testing::temp_file;

// A body on a hinge: the smallest world MuJoCo loads.
const std::string kWorld =
    R"(<worldbody><body><joint axis="1 0 0"/><geom type="sphere" size=".1"/></body></worldbody>)";

// The message of the InputError the check throws ("" if the file passes).
std::string check_error(const std::string& path) {
  try {
    check_mjcf_numbers(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Non-finite numbers in <option>: each real-valued attribute of MuJoCo 2.2.2's <option>, next to a
// <flag> whose gravity and frictionloss are keywords, is refused on its own line and named.
TEST(MjcfInput, NonFiniteOptionNumbersAreRefused) {
  struct Case {
    std::string attribute, value, problem;
  };
  const Case cases[] = {{"timestep", "nan", "not a finite number"},
                        {"apirate", "inf", "not a finite number"},
                        {"impratio", "-inf", "not a finite number"},
                        {"tolerance", "NaN", "not a finite number"},
                        {"noslip_tolerance", "1e999", "not a finite number"},
                        {"mpr_tolerance", "-nan", "not a finite number"},
                        {"gravity", "0 0 inf", "not a finite number"},
                        {"wind", "nan 0 0", "not a finite number"},
                        {"magnetic", "0 -1e400 0", "not a finite number"},
                        {"density", "+inf", "not a finite number"},
                        {"viscosity", "INF", "not a finite number"},
                        {"o_margin", "nan", "not a finite number"},
                        {"o_solref", "0.02 nan", "not a finite number"},
                        {"o_solimp", "0.9 0.95 0.001 0.5 inf", "not a finite number"},
                        {"gravity", "&#110;an 0 0", "not a finite number"},  // tinyxml2 reads "nan"
                        {"timestep", "0.01s", "not a number"}};
  for (const Case& c : cases) {
    const std::string attribute = c.attribute + "=\"" + c.value + "\"";
    SCOPED_TRACE(attribute);
    const std::string path =
        temp_file("option.xml", "<mujoco>\n<option " + attribute +
                                    "><flag gravity=\"disable\" frictionloss=\"disable\"/></option>\n" + kWorld +
                                    "</mujoco>");
    const std::string message = check_error(path);
    EXPECT_EQ(message.rfind(path + ":2: <option> " + attribute + ": " + c.problem, 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

#ifdef LDLPGS_HAVE_MUJOCO

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

// MuJoCo's model of the file, or null with its message in *error.
ModelPtr mujoco_load(const std::string& path, std::string* error) {
  char text[1024] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, text, sizeof text));
  *error = text;
  return m;
}

// MuJoCo warns on stdout of every nan it reads ("XML contains a 'NaN'"); these tests give it nan
// on purpose.
[[maybe_unused]] const auto quiet_warnings = [] {
  mju_user_warning = [](const char*) {};
  return 0;
}();

// MuJoCo 2.2.2's <flag> keywords (the MJCF[] schema table of src/xml/xml_native_reader.cc, read by
// Option() with enable_map: "disable" or "enable"), in the order of their bits: those that disable
// (mjtDisableBit), then those that enable (mjtEnableBit).
const char* const kDisableFlags[] = {"constraint", "equality", "frictionloss", "limit",     "contact",
                                     "passive",    "gravity",  "clampctrl",    "warmstart", "filterparent",
                                     "actuation",  "refsafe",  "sensor"};
const char* const kEnableFlags[] = {"override", "energy", "fwdinv", "sensornoise", "multiccd"};
static_assert(std::size(kDisableFlags) == mjNDISABLE && std::size(kEnableFlags) == mjNENABLE);

// Every <option> attribute of MuJoCo 2.2.2's schema, each with a value other than its default
// (and each keyword attribute through all its values, one a file) and every <flag> keyword set to
// "disable" and to "enable": the check passes each file, MuJoCo loads it, and the model holds what
// the file says, so that MuJoCo read every attribute. MuJoCo refuses an attribute it does not know,
// and the flags' bits must fill mjNDISABLE and mjNENABLE: a list with a wrong name or a missing
// one fails.
TEST(MjcfInput, EveryOptionAttributeAndFlagPassesAndLoads) {
  const std::vector<std::string> integrators = {"Euler", "RK4", "implicit"};
  const std::vector<std::string> collisions = {"all", "predefined", "dynamic"};
  const std::vector<std::string> cones = {"pyramidal", "elliptic"};
  const std::vector<std::string> jacobians = {"dense", "sparse", "auto"};
  const std::vector<std::string> solvers = {"PGS", "CG", "Newton"};
  for (int round = 0; round < 3; ++round) {
    const bool enable = round == 1;
    std::string flags;
    for (const char* flag : kDisableFlags) flags += cat(" ", flag, "=\"", enable ? "enable" : "disable", "\"");
    for (const char* flag : kEnableFlags) flags += cat(" ", flag, "=\"", enable ? "enable" : "disable", "\"");
    const std::string option =
        "<option timestep=\"0.005\" apirate=\"50\" impratio=\"2\" tolerance=\"1e-9\" noslip_tolerance=\"1e-7\" "
        "mpr_tolerance=\"1e-5\" gravity=\"0 -1 -9\" wind=\"1 2 3\" magnetic=\"0 -0.4 0.1\" density=\"1.2\" "
        "viscosity=\"2e-5\" o_margin=\"0.01\" o_solref=\"0.03 1.1\" o_solimp=\"0.8 0.9 0.002 0.4 3\" "
        "integrator=\"" + integrators[round % 3] + "\" collision=\"" + collisions[round % 3] + "\" cone=\"" +
        cones[round % 2] + "\" jacobian=\"" + jacobians[round % 3] + "\" solver=\"" + solvers[round % 3] +
        "\" iterations=\"60\" noslip_iterations=\"3\" mpr_iterations=\"40\">\n<flag" + flags + "/>\n</option>";
    SCOPED_TRACE(option);
    const std::string path = temp_file("option.xml", "<mujoco>\n" + option + "\n" + kWorld + "\n</mujoco>");
    EXPECT_EQ(check_error(path), "");
    std::string error;
    const ModelPtr m = mujoco_load(path, &error);
    ASSERT_TRUE(m) << error;
    const mjOption& o = m->opt;
    EXPECT_EQ(o.timestep, 0.005);
    EXPECT_EQ(o.apirate, 50);
    EXPECT_EQ(o.impratio, 2);
    EXPECT_EQ(o.tolerance, 1e-9);
    EXPECT_EQ(o.noslip_tolerance, 1e-7);
    EXPECT_EQ(o.mpr_tolerance, 1e-5);
    EXPECT_EQ(std::vector<mjtNum>(o.gravity, o.gravity + 3), (std::vector<mjtNum>{0, -1, -9}));
    EXPECT_EQ(std::vector<mjtNum>(o.wind, o.wind + 3), (std::vector<mjtNum>{1, 2, 3}));
    EXPECT_EQ(std::vector<mjtNum>(o.magnetic, o.magnetic + 3), (std::vector<mjtNum>{0, -0.4, 0.1}));
    EXPECT_EQ(o.density, 1.2);
    EXPECT_EQ(o.viscosity, 2e-5);
    EXPECT_EQ(o.o_margin, 0.01);
    EXPECT_EQ(std::vector<mjtNum>(o.o_solref, o.o_solref + mjNREF), (std::vector<mjtNum>{0.03, 1.1}));
    EXPECT_EQ(std::vector<mjtNum>(o.o_solimp, o.o_solimp + mjNIMP), (std::vector<mjtNum>{0.8, 0.9, 0.002, 0.4, 3}));
    EXPECT_EQ(o.integrator, round % 3);  // the keywords in the order of their enums (mjtIntegrator, ...)
    EXPECT_EQ(o.collision, round % 3);
    EXPECT_EQ(o.cone, round % 2);
    EXPECT_EQ(o.jacobian, round % 3);
    EXPECT_EQ(o.solver, round % 3);
    EXPECT_EQ(o.iterations, 60);
    EXPECT_EQ(o.noslip_iterations, 3);
    EXPECT_EQ(o.mpr_iterations, 40);
    EXPECT_EQ(o.disableflags, enable ? 0 : (1 << mjNDISABLE) - 1);
    EXPECT_EQ(o.enableflags, enable ? (1 << mjNENABLE) - 1 : 0);
  }
}

// Every model MuJoCo ships (libmujoco-samples) and every Gymnasium model in tests/data: MuJoCo
// loads each, and the check passes each.
TEST(MjcfInput, ShippedAndGymnasiumModelsPass) {
  std::vector<std::string> paths;
  std::error_code ec;
  for (const auto& entry : std::filesystem::recursive_directory_iterator("/usr/share/mujoco/model", ec))
    if (entry.path().extension() == ".xml") paths.push_back(entry.path().string());
  const size_t shipped = paths.size();
  for (const auto& entry : std::filesystem::directory_iterator(LDLPGS_TESTDATA "/mjcf/gymnasium"))
    if (entry.path().extension() == ".xml") paths.push_back(entry.path().string());
  EXPECT_GE(shipped, 18u);  // Debian's 2.2.2: 18 models
  EXPECT_GE(paths.size() - shipped, 13u);
  for (const std::string& path : paths) {
    std::string error;
    EXPECT_TRUE(mujoco_load(path, &error)) << path << ": " << error;
    EXPECT_EQ(check_error(path), "") << path;
  }
}

// Numbers as MuJoCo reads them: tinyxml2 decodes entities and character references (tinyxml2's
// own way: an unknown entity's '&' leaves a byte behind, a reference to 0 ends the value, its
// multiplier wraps at 2^32), then MuJoCo splits at any C whitespace and reads each token with
// operator>>. For every value MuJoCo loads, the check refuses it exactly when a number MuJoCo read
// is not finite; values MuJoCo refuses are MuJoCo's to report.
TEST(MjcfInput, NumbersAreReadAsMuJoCoReadsThem) {
  struct Case {
    std::string attribute, value;
  };
  const Case cases[] = {
      // numbers operator>> reads, and what it does not
      {"timestep", "1e-400"}, {"timestep", "+.5"}, {"timestep", "5."}, {"timestep", "-0"}, {"timestep", "1E+05"},
      {"timestep", ".5e1"}, {"timestep", "0x1"}, {"timestep", "5e"}, {"timestep", "1,5"}, {"timestep", "1e400"},
      {"timestep", "inf"}, {"timestep", "-nan"},
      // references and entities
      {"timestep", "&#48;.01"}, {"timestep", "&#x30;.01"}, {"timestep", "&#110;an"}, {"timestep", "&#x69;nf"},
      {"timestep", "0.01&#0;junk"}, {"timestep", "&#32;&#32;&"}, {"timestep", "&amp;"}, {"timestep", "1&#"},
      {"timestep", "&#;1"}, {"timestep", "&lt;1"}, {"timestep", "0.0&#x31;"}, {"timestep", "0.0&#49"},
      {"timestep", "0&#x2e;01"}, {"gravity", "0 0 &#45;9"}, {"gravity", "&#110;&#97;&#110; 0 0"},
      {"gravity", "0 0 &#x2D;inf"},
      // references past 2^32: "&#x100000030;" is '0'
      {"timestep", "&#x100000030;.5"}, {"timestep", "&#x10000006E;an"}, {"timestep", "-&#x100000031;"},
      {"gravity", "0 0&#x100000020;-9"},
      // whitespace
      {"gravity", "0\v0\f-9"}, {"gravity", "0&#32;0&#9;-9"}, {"gravity", "\t0 0 -9\n"}, {"gravity", "0 0 -9 "},
      {"gravity", "0&#10;0&#13;-9"}};
  int finite = 0, not_finite = 0;
  for (const Case& c : cases) {
    const std::string attribute = c.attribute + "=\"" + c.value + "\"";
    SCOPED_TRACE(attribute);
    const std::string path = temp_file("number.xml", "<mujoco><option " + attribute + "/>" + kWorld + "</mujoco>");
    std::string error;
    const ModelPtr m = mujoco_load(path, &error);
    if (!m) continue;
    const mjtNum* read = c.attribute == "timestep" ? &m->opt.timestep : m->opt.gravity;
    const int n = c.attribute == "timestep" ? 1 : 3;
    const bool all_finite = std::all_of(read, read + n, [](mjtNum x) { return std::isfinite(x); });
    ++(all_finite ? finite : not_finite);
    const std::string message = check_error(path);
    if (all_finite)
      EXPECT_EQ(message, "");
    else
      EXPECT_NE(message.find("<option> " + c.attribute + "=\""), std::string::npos) << message;
  }
  EXPECT_GE(finite, 21);  // MuJoCo 2.2.2 loads 21 with finite numbers, 7 with nan or inf
  EXPECT_GE(not_finite, 7);
}

// MuJoCo resolves every <include file> against the top file's folder (mjuu_getfiledir), nested ones
// too, and matches the element's name in any case: the check reads the files MuJoCo reads.
TEST(MjcfInput, IncludesAreReadWhereMuJoCoReadsThem) {
  const std::filesystem::path dir = testing::temp_path("includes");
  std::filesystem::create_directories(dir / "sub" / "sub");
  const std::string good = "<mujocoinclude>" + kWorld + "</mujocoinclude>";
  const std::string bad = R"(<mujocoinclude><option gravity="0 0 nan"/>)" + kWorld + "</mujocoinclude>";
  auto write = [&](const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
  };
  const std::string top = (dir / "top.xml").string();
  write(top, R"(<mujoco><INCLUDE file="sub/a.xml"/></mujoco>)");
  write(dir / "sub" / "a.xml", R"(<mujocoinclude><include file="sub/b.xml"/></mujocoinclude>)");
  for (const bool bad_where_mujoco_reads : {true, false}) {
    SCOPED_TRACE(bad_where_mujoco_reads ? "sub/b.xml has nan" : "sub/sub/b.xml has nan");
    write(dir / "sub" / "b.xml", bad_where_mujoco_reads ? bad : good);          // what MuJoCo reads
    write(dir / "sub" / "sub" / "b.xml", bad_where_mujoco_reads ? good : bad);  // next to a.xml
    std::string error;
    const ModelPtr m = mujoco_load(top, &error);
    ASSERT_TRUE(m) << error;
    EXPECT_EQ(std::isnan(m->opt.gravity[2]), bad_where_mujoco_reads);
    const std::string message = check_error(top);
    const std::string refusal =
        (dir / "sub" / "b.xml").string() + ":1: <option> gravity=\"0 0 nan\": not a finite number";
    if (bad_where_mujoco_reads)
      EXPECT_EQ(message.rfind(refusal, 0), 0u) << message;
    else
      EXPECT_EQ(message, "");
  }
}

// MuJoCo reads the root element's children only: what follows the root, and the root of an
// included file, it ignores, and so does the check.
TEST(MjcfInput, WhatMuJoCoIgnoresIsNotChecked) {
  const std::string included = temp_file("root.xml", R"(<option timestep="nan">)" + kWorld + "</option>");
  const std::string paths[] = {
      temp_file("after.xml", "<mujoco>" + kWorld + "</mujoco>\n<mujoco><option timestep=\"nan\"/></mujoco>"),
      temp_file("top.xml", "<mujoco><include file=\"" + std::filesystem::path(included).filename().string() +
                               "\"/></mujoco>")};
  for (const std::string& path : paths) {
    std::string error;
    const ModelPtr m = mujoco_load(path, &error);
    ASSERT_TRUE(m) << path << ": " << error;
    EXPECT_EQ(m->opt.timestep, 0.002);  // MuJoCo's default
    EXPECT_EQ(check_error(path), "");
  }
}

#endif

}  // namespace
}  // namespace ldlpgs
