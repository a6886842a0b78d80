// The command-line vocabulary (docs/cli.md, "Command-line vocabulary"): every subcommand's JSON
// speaks it, usage, misspelt and old option names, progress lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "ldlpgs/version.h"
#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

namespace vocabulary_test {

struct Field {
  std::string name, type;                // name: dotted for a member of an object (inertia.positive)
  std::vector<std::string> in, was;      // commands that must print it; the names it replaces
};

std::string strip(std::string s) {
  std::erase(s, '`');
  const size_t b = s.find_first_not_of(' '), e = s.find_last_not_of(' ');
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char by) {
  std::vector<std::string> parts;
  std::stringstream ss(s);
  for (std::string part; std::getline(ss, part, by);)
    if (!strip(part).empty()) parts.push_back(strip(part));
  return parts;
}

// The field table of docs/cli.md's vocabulary section: rows | `field` | type | in | was |.
std::vector<Field> read_vocabulary() {
  std::ifstream in(std::string(LDLPGS_TESTDATA) + "/../../docs/cli.md");
  std::vector<Field> fields;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("## ")) inside = line == "## Command-line vocabulary";
    if (!inside || !line.starts_with("| `")) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string cell; std::getline(ss, cell, '|');) cells.push_back(cell);
    if (cells.size() != 4) continue;  // the table of old option spellings has two columns
    fields.push_back({strip(cells[0]), strip(cells[1]), split(cells[2], ' '), split(cells[3], ',')});
  }
  return fields;
}

bool has_type(const nlohmann::json& v, const std::string& type) {
  if (type == "integer") return v.is_number_integer();
  if (type == "integer?") return v.is_number_integer() || v.is_null();
  if (type == "number") return v.is_number();
  if (type == "number?") return v.is_number() || v.is_null();
  if (type == "string") return v.is_string();
  if (type == "string?") return v.is_string() || v.is_null();
  if (type == "boolean") return v.is_boolean();
  if (type == "object") return v.is_object();
  ADD_FAILURE() << "the vocabulary names an unknown type " << type;
  return false;
}

// The output and the records of its lists (order's results, peers' engines, sweep's points).
std::vector<const nlohmann::json*> records(const nlohmann::json& j) {
  std::vector<const nlohmann::json*> all = {&j};
  for (const auto& [key, value] : j.items())
    if (value.is_array())
      for (const nlohmann::json& x : value)
        if (x.is_object()) all.push_back(&x);
  return all;
}

const nlohmann::json* lookup(const nlohmann::json& o, const std::string& dotted) {
  const nlohmann::json* at = &o;
  for (const std::string& key : split(dotted, '.')) {
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
  }
  return at;
}

void expect_vocabulary(const std::string& command, const nlohmann::json& j, const std::vector<Field>& vocabulary) {
  ASSERT_TRUE(j.is_object()) << command;
  EXPECT_EQ(j.value("ldlpgs_version", ""), ldlpgs::kVersion) << command;
  for (const Field& f : vocabulary) {
    bool found = false;
    for (const nlohmann::json* r : records(j)) {
      if (const nlohmann::json* v = lookup(*r, f.name)) {
        found = true;
        EXPECT_TRUE(has_type(*v, f.type)) << command << ": " << f.name << " = " << v->dump() << ", not " << f.type;
      }
      for (const std::string& old : f.was) EXPECT_FALSE(r->contains(old)) << command << ": " << old << " is now " << f.name;
    }
    if (std::find(f.in.begin(), f.in.end(), command) != f.in.end()) {
      EXPECT_TRUE(found) << command << " has no " << f.name << " (docs/cli.md says it does)";
    }
  }
}

TEST(LdlpgsVocabulary, TheReadmeStatesIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  ASSERT_GT(vocabulary.size(), 30u);
  for (const Field& f : vocabulary) {
    EXPECT_FALSE(f.in.empty()) << f.name;
    nlohmann::json probe = nullptr;
    has_type(probe, f.type);  // fails on a type the test does not know
  }
}

TEST(LdlpgsVocabulary, EverySubcommandsJsonSpeaksIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  ASSERT_FALSE(vocabulary.empty());
  const std::string m = kMatrices + "/bcsstk01.mtx", mtx = temp_path("v.mtx"), blocks = temp_path("v.blocks");
  const std::pair<std::string, std::string> runs[] = {
      {"order", "order " + m + " --cholmod --ordering meca,amd-scalar --certify --json"},
      {"verify", "verify " + m + " --json"},
      {"bench", "bench chain:10 --dense-max 100 --json"},
      {"step", "step four-bar --steps 20 --json"},
      {"export", "export four-bar --matrix-file " + mtx + " --blocks-file " + blocks + " --json"},
      {"spy", "spy four-bar --json"},
      {"sweep", "sweep --cases four-bar --iterations 1 --seconds 0.1 --json"},
      {"peers", "peers pendulum --seconds 0.05 --json"},
      {"models", "models " + kGymnasium + "/hopper.xml " + temp_file("refused.xml", "<mujoco>") + " --steps 3 --json"},
  };
  for (const auto& [command, args] : runs) {
    const nlohmann::json j = json_of(args);
    EXPECT_EQ(j.value("command", ""), command);
    expect_vocabulary(command, j, vocabulary);
  }
  // report: its tables as data, one record per row
  const std::string dir = temp_path("vocabulary-report"), empty = temp_path("no-matrices");
  std::filesystem::create_directories(empty);
  const Result r = run("report --sizes 10 --cases four-bar --ordering meca,amd --matrices " + empty + " --out-dir " + dir +
                       " --no-figures");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* table : {"orderings", "verification", "sweep", "stability"}) {
    std::ifstream in(dir + "/data/" + table + ".json");
    expect_vocabulary("report", nlohmann::json::parse(in), vocabulary);
  }
}

// A matrix the solvers refuse: the same fields, null where nothing was measured.
TEST(LdlpgsVocabulary, ASingularMatrixSpeaksIt) {
  const std::vector<Field> vocabulary = read_vocabulary();
  const std::string f = temp_file("singular.mtx", kSingular);
  for (const char* command : {"bench", "verify"}) {
    const Result r = run(std::string(command) + " " + f + " --json");
    EXPECT_EQ(r.code, 1) << command << ": " << r.err;
    expect_vocabulary(command, nlohmann::json::parse(r.out), vocabulary);
  }
}

TEST(LdlpgsVocabulary, Version) {
  const Result r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find(ldlpgs::kVersion), std::string::npos) << r.out;
}

TEST(LdlpgsVocabulary, NoOrUnknownSubcommandPrintsTheUsage) {
  const Result none = run("");
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("Usage"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("no subcommand given"), std::string::npos) << none.err;
  const Result unknown = run("verfy x.mtx");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("Usage"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("unknown subcommand 'verfy'; did you mean verify?"), std::string::npos) << unknown.err;
}

TEST(LdlpgsVocabulary, MisspeltOptionNamesTheNearest) {
  expect_input_error("verify " + kMatrices + "/bcsstk01.mtx --orderin amd",
                     {"ldlpgs verify: unknown option --orderin; did you mean --ordering?"});
  expect_input_error("step pendulum --jsn", {"ldlpgs step: unknown option --jsn; did you mean --json?"});
}

TEST(LdlpgsVocabulary, ListsAreCommaSeparated) {
  expect_input_error("sweep --cases four-bar chain-10", {"comma-separated", "--cases four-bar,chain-10"});
}

TEST(LdlpgsVocabulary, OldSpellings) {
  // kept: the same output as the new name
  EXPECT_EQ(json_of("order " + kMatrices + "/can___24.mtx --orderings amd --json")["results"][0]["ordering"], "amd");
  const std::string spy = temp_path("old-spy.json");
  ASSERT_EQ(run("spy four-bar --out " + spy).code, 0);
  std::ifstream in(spy);
  EXPECT_EQ(nlohmann::json::parse(in)["scene"], "four-bar");
  // refused, naming the new one: their meaning changed
  expect_input_error("export four-bar --matrix-file " + temp_path("o.mtx") + " --blocks " + temp_path("o.blocks"),
                     {"--blocks is now --blocks-file"});
  expect_input_error("sweep --cases four-bar --json " + temp_path("o.json"), {"--json-file"});
}

TEST(LdlpgsVocabulary, OrderTakesAGeneratedMechanism) {
  const nlohmann::json j = json_of("order grid:20 --ordering meca --json");
  EXPECT_EQ(j["matrix"], "grid-20");
  EXPECT_EQ(j["blocks"], 20);
}

TEST(LdlpgsVocabulary, OrderOnALargeMatrixPrintsProgress) {
  const Result r = run("order chain:1400 --ordering meca,amd");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("ldlpgs order: chain-1400: meca"), std::string::npos) << r.err;
}

TEST(LdlpgsVocabulary, BenchOnALargeMatrixPrintsProgress) {
  const Result r = run("bench chain:1400 --dense-max 10 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* solver : {"ldlpgs", "cholmod", "eigen-simplicial"})
    EXPECT_NE(r.err.find(std::string("ldlpgs bench: chain-1400: ") + solver), std::string::npos) << r.err;
}

}  // namespace vocabulary_test

}  // namespace
}  // namespace ldlpgs::testing
