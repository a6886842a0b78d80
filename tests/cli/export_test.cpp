// `ldlpgs export`: the matrix and blocks it writes verify against CHOLMOD, shattered or not,
// from built-in scenes and MJCF models.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsExport, MatrixVerifiesAgainstCholmod) {
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  const Result r = run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const SymmetricCsc h = read_matrix_market(mtx);
  const std::vector<int> sizes = read_partition(blocks, h.n);
  EXPECT_EQ(h.n, 200);  // the talk's tracked vehicle: 40 hinges, dim(H) = 200
  EXPECT_EQ(sizes.size(), 40u);
  const Result v = run("verify " + mtx + " --blocks " + blocks + " --json");
  ASSERT_EQ(v.code, 0) << v.err << v.out;
  EXPECT_TRUE(nlohmann::json::parse(v.out)["ok"].get<bool>());
}

// export writes the H that step factors: shattered by default, the talk's 142 with --shards 10,
// the dense 88 x 88 with --no-shatter; each verifies against CHOLMOD.
TEST(LdlpgsExport, ShatterOptions) {
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  for (auto [options, dim] : std::vector<std::pair<std::string, int>>{{"--no-shatter", 88}, {"--shards 10", 142}, {"", -1}}) {
    const Result r = run("export multi-wheeled-vehicle " + options + " --matrix-file " + mtx + " --blocks-file " + blocks);
    ASSERT_EQ(r.code, 0) << r.err;
    const SymmetricCsc h = read_matrix_market(mtx);
    const std::vector<int> sizes = read_partition(blocks, h.n);
    if (dim > 0) {
      EXPECT_EQ(h.n, dim) << options;
    } else {
      EXPECT_EQ(h.n, 88 + 6 * (static_cast<int>(sizes.size()) - 20)) << "default: 20 constraints and welds";
    }
    const Result v = run("verify " + mtx + " --blocks " + blocks + " --json");
    ASSERT_EQ(v.code, 0) << v.err << v.out;
    EXPECT_TRUE(nlohmann::json::parse(v.out)["ok"].get<bool>()) << options;
  }
}

#ifdef LDLPGS_HAVE_MUJOCO

TEST(LdlpgsExport, MjcfHumanoid) {
  ASSERT_TRUE(std::filesystem::exists(kHumanoid)) << kHumanoid << " missing (libmujoco-samples)";
  const std::string mtx = temp_path("humanoid.mtx"), blocks = temp_path("humanoid.blocks");
  const Result r = run("export " + kHumanoid + " --no-shatter --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  // The equality rows: 6 x 16 bodies - 27 degrees of freedom (MuJoCo's nv) = 69 joint rows, and
  // a dof_drive row for each of the 21 hinges (their armature and damping: physics/actuation.h).
  EXPECT_EQ(read_matrix_market(mtx).n, 69 + 21);
}

#endif

}  // namespace
}  // namespace ldlpgs::testing
