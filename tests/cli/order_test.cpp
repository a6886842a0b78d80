// `ldlpgs order`: its table, JSON and permutations against the library and CHOLMOD, block
// partitions, and --certify.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

TEST(LdlpgsOrder, JsonEqualsLibraryAndCholmod) {
  const std::string file = kMatrices + "/bcsstk01.mtx";
  const Result r = run("order " + file + " --json --cholmod --ordering mda,meca,amd-scalar");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["matrix"], "bcsstk01.mtx");
  EXPECT_EQ(j["n"], 48);
  const SymmetricCsc a = read_matrix_market(file);
  const BlockPattern blocks = BlockPattern::from_scalar(a, partition_auto(a));
  EXPECT_EQ(j["blocks"], blocks.num_blocks());
  ASSERT_EQ(j["results"].size(), 3u);
  Cholmod cm;
  for (const auto& row : j["results"]) {
    const Ordering o = compute_ordering(find_ordering(row["ordering"].get<std::string>()), blocks, a);
    const CholmodCounts c = cholmod_counts(a, o.perm, cm);
    EXPECT_EQ(row["nnz_L"].get<double>(), c.lnz);
    EXPECT_EQ(row["flops"].get<double>(), c.fl);
    EXPECT_EQ(row["cholmod_nnz_L"].get<double>(), c.lnz);
    EXPECT_EQ(row["cholmod_flops"].get<double>(), c.fl);
    for (const char* key : {"block_fill_edges", "block_flops", "ordering_ms"}) EXPECT_TRUE(row.contains(key)) << key;
  }
  EXPECT_TRUE(j["results"][2]["block_flops"].is_null()) << "a scalar ordering has no block costs";
}

// --split-blocks (papers/orderings.md, "Block partitions that see inside blocks"): an exported
// scene stores its coupling blocks dense, about half of them exact zeros; the flag orders the
// matrix without them on refined blocks. Checked against the library's own pieces and CHOLMOD's
// counts, and verify agrees with CHOLMOD on it.
TEST(LdlpgsOrder, SplitBlocksOrdersTheNonzeroPatternOnRefinedBlocks) {
  const std::string mtx = temp_path("split.mtx"), blocks = temp_path("split.blocks");
  ASSERT_EQ(run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks).code, 0);
  const nlohmann::json whole = json_of("order " + mtx + " --blocks " + blocks + " --ordering meca-w --json");
  const nlohmann::json split = json_of("order " + mtx + " --blocks " + blocks + " --split-blocks --ordering meca-w --json");
  const SymmetricCsc stored = read_matrix_market(mtx);
  const SymmetricCsc a = without_zeros(stored);
  ASSERT_LT(a.nnz(), stored.nnz()) << "the export stores no exact zero: nothing to split";
  const BlockPattern refined = BlockPattern::from_scalar(a, partition_refine(a, read_partition(blocks, a.n)));
  EXPECT_EQ(split["blocks"], refined.num_blocks());
  EXPECT_GT(split["blocks"].get<int>(), whole["blocks"].get<int>());
  Cholmod cm;
  const CholmodCounts c = cholmod_counts(a, compute_ordering(find_ordering("meca-w"), refined, a).perm, cm);
  EXPECT_EQ(split["results"][0]["flops"].get<double>(), c.fl);
  EXPECT_LT(c.fl, whole["results"][0]["flops"].get<double>());
  const Result v = run("verify " + mtx + " --blocks " + blocks + " --split-blocks");
  EXPECT_EQ(v.code, 0) << v.out << v.err;
}

TEST(LdlpgsOrder, PermOutWritesEachPermutation) {
  const std::string dir = temp_path("perms");
  const Result r = run("order " + kMatrices + "/can___24.mtx --blocks 2 --ordering natural,metis --perm-dir " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"natural", "metis"}) {
    std::ifstream in(dir + "/" + name + ".perm");
    std::vector<int> perm;
    for (int x; in >> x;) perm.push_back(x);
    std::vector<int> sorted = perm;
    std::sort(sorted.begin(), sorted.end());
    ASSERT_EQ(sorted.size(), 24u) << name;
    for (int i = 0; i < 24; ++i) EXPECT_EQ(sorted[i], i);
    if (std::string(name) == "natural") {
      EXPECT_EQ(perm, sorted);
    }
    // Uniform blocks of 2: each block's rows stay together, in order.
    for (size_t k = 0; k < perm.size(); k += 2) EXPECT_EQ(perm[k] + 1, perm[k + 1]);
  }
}

TEST(LdlpgsOrder, TablePrintsEveryOrdering) {
  const Result r = run("order " + kMatrices + "/LFAT5.mtx");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const OrderingInfo& o : orderings()) {
    std::string line = "\n";  // (not "\n" + string: GCC 12 -O3 warns falsely there, bug 105329)
    line += o.name;
    line += " ";
    EXPECT_NE(r.out.find(line), std::string::npos) << o.name;
  }
}

TEST(LdlpgsOrder, HelpOnEverySubcommand) {
  for (const char* sub : {"", "order", "report", "verify", "bench", "step", "export", "spy", "sweep"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

// On the talk's tracked vehicle meca gives 41,400 block flops; best chooses meca-w's
// 38,300, and --certify proves no block order has fewer.
TEST(LdlpgsOrder, CertifiesTheTrackedVehicle) {
  const std::string mtx = temp_path("tracked.mtx"), blocks = temp_path("tracked.blocks");
  ASSERT_EQ(run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks).code, 0);
  const std::string order = "order " + mtx + " --blocks " + blocks + " --orderings best,meca --certify";
  const nlohmann::json j = json_of(order + " --json");
  ASSERT_EQ(j["results"].size(), 2u);
  const nlohmann::json& best = j["results"][0];
  EXPECT_EQ(best["ordering"], "best");
  EXPECT_EQ(best["chosen"], "meca-w");
  EXPECT_EQ(best["block_flops"], 38300);
  EXPECT_TRUE(best["certified_optimal"].get<bool>());
  EXPECT_EQ(best["lower_bound_block_flops"], 38300);
  EXPECT_EQ(j["results"][1]["block_flops"], 41400);
  EXPECT_FALSE(j["results"][1]["certified_optimal"].get<bool>());
  EXPECT_TRUE(j["optimum_proved"].get<bool>());
  const Result text = run(order);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("certificate: optimum 38300 block flops"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("optimal: best (meca-w)\n"), std::string::npos) << text.out;
}

// On a closed loop of 40 constraints the certificate's optimum is below every ordering's: its
// order is a row of its own, written by --perm-dir like the others.
TEST(LdlpgsOrder, CertifyAddsTheOptimalOrderNoOrderingReached) {
  const std::string dir = temp_path("loop-perms");
  const nlohmann::json j = json_of("order loop:40 --ordering best,meca --certify --json --perm-dir " + dir);
  ASSERT_EQ(j["results"].size(), 3u);
  const nlohmann::json& optimal = j["results"][2];
  EXPECT_EQ(optimal["ordering"], "optimal");
  EXPECT_EQ(optimal["chosen"], "certify");
  EXPECT_TRUE(optimal["certified_optimal"].get<bool>());
  EXPECT_TRUE(j["optimum_proved"].get<bool>());
  EXPECT_EQ(optimal["block_flops"], j["lower_bound_block_flops"]);
  EXPECT_LT(optimal["block_flops"].get<double>(), j["results"][0]["block_flops"].get<double>());
  EXPECT_FALSE(j["results"][0]["certified_optimal"].get<bool>());
  std::ifstream perm(dir + "/optimal.perm");
  std::vector<int> rows;
  for (int r; perm >> r;) rows.push_back(r);
  EXPECT_NO_THROW(check_permutation(rows, j["n"].get<int>(), "optimal.perm"));
  const Result text = run("order loop:40 --ordering best --certify");
  EXPECT_NE(text.out.find("optimal: optimal (certify)\n"), std::string::npos) << text.out;
}

// Out of time: a lower bound, below the orderings' flops, and nothing certified.
TEST(LdlpgsOrder, CertifyOutOfTimeGivesALowerBound) {
  const nlohmann::json j = json_of("order grid:200 --ordering best --certify --certify-time-limit-s 0 --json");
  EXPECT_FALSE(j["optimum_proved"].get<bool>());
  EXPECT_LT(j["lower_bound_block_flops"].get<double>(), j["results"][0]["block_flops"].get<double>());
  EXPECT_FALSE(j["results"][0]["certified_optimal"].get<bool>());
}

}  // namespace
}  // namespace ldlpgs::testing
