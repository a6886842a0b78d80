// `ldlpgs spy`: its JSON checked against itself, a brute-force elimination game, the exported
// matrix and CHOLMOD, on the talk's scenes, shattered or not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/matrix_market.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/program.h"

// In the helpers' namespace (tests/support/program.h, temp_files.h): run, json_of, temp_path...
namespace ldlpgs::testing {
namespace {

namespace spy_test {

// `ldlpgs spy ARGS --json-file FILE`, FILE parsed.
nlohmann::json spy(const std::string& args) {
  const std::string out = temp_path("spy.json");
  const Result r = run("spy " + args + " --json-file " + out);
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  EXPECT_NE(r.out.find("dim(H)"), std::string::npos) << r.out;
  std::ifstream in(out);
  return nlohmann::json::parse(in);
}

using BlockSet = std::set<std::pair<int, int>>;  // (row, column) block pairs, pivot order

BlockSet h_blocks(const nlohmann::json& j) {
  BlockSet h;
  for (const auto& b : j["H_blocks"]) h.insert({b[0].get<int>(), b[1].get<int>()});
  return h;
}

// The file checked against itself and against a brute-force elimination game on its own H:
// pivots, sizes, density, L = H plus fill (a fill block is exactly a block of L not in H), and nnz(L)
// and flops as metrics.h counts them for dense blocks, column by column.
void expect_consistent(const nlohmann::json& j) {
  const std::vector<int> sizes = j["block_sizes"].get<std::vector<int>>();
  const int np = static_cast<int>(sizes.size()), dim = j["n"].get<int>();
  // a scalar ordering (amd-scalar, metis-scalar) pivots on single rows
  EXPECT_EQ(j["ordering"].get<std::string>().ends_with("-scalar") ? dim : j["constraints"].get<int>(), np);
  int rows = 0;
  for (int size : sizes) rows += size;
  EXPECT_EQ(rows, dim);
  std::vector<int> pivots = j["pivots"].get<std::vector<int>>();
  std::sort(pivots.begin(), pivots.end());
  for (int k = 0; k < np; ++k) EXPECT_EQ(pivots[k], k) << "pivots is not a permutation";

  const BlockSet h = h_blocks(j);
  EXPECT_EQ(h.size(), j["H_blocks"].size()) << "duplicate H blocks";
  int64_t entries = 0;
  std::vector<std::set<int>> below(np);  // row blocks below the diagonal, per column
  for (int k = 0; k < np; ++k) EXPECT_TRUE(h.count({k, k})) << "no diagonal block " << k;
  for (const auto& [i, k] : h) {
    ASSERT_TRUE(i >= k && i < np) << i << ", " << k;
    entries += (i == k ? 1 : 2) * int64_t{sizes[i]} * sizes[k];
    if (i != k) below[k].insert(i);
  }
  EXPECT_NEAR(j["density"].get<double>(), static_cast<double>(entries) / (double(dim) * dim), 1e-15);

  BlockSet expected;  // the elimination game: a pivot's neighbours after it become a clique
  int64_t nnz = 0;
  double flops = 0;
  for (int k = 0; k < np; ++k) {
    expected.insert({k, k});
    int64_t height = 0;
    for (int i : below[k]) {
      expected.insert({i, k});
      height += sizes[i];
      for (int l : below[k])
        if (l > i) below[i].insert(l);
    }
    const int64_t d = sizes[k];
    nnz += d * (d + 1) / 2 + height * d;
    flops += static_cast<double>(d * (d + 1) * (2 * d + 1) / 6 + height * d * (d + 1) + d * height * height);
  }
  BlockSet l;
  int64_t fill = 0;
  for (const auto& b : j["L_blocks"]) {
    const int i = b[0].get<int>(), k = b[1].get<int>();
    const bool is_fill = b[2].get<bool>();
    l.insert({i, k});
    EXPECT_EQ(is_fill, !h.count({i, k})) << "L block " << i << ", " << k;
    fill += is_fill;
  }
  EXPECT_EQ(l.size(), j["L_blocks"].size()) << "duplicate L blocks";
  for (const auto& b : h) EXPECT_TRUE(l.count(b)) << "H block " << b.first << ", " << b.second << " not in L";
  EXPECT_EQ(l, expected);
  EXPECT_EQ(j["fill_blocks"].get<int64_t>(), fill);
  EXPECT_EQ(j["nnz_L"].get<int64_t>(), nnz);
  EXPECT_EQ(j["flops"].get<double>(), flops);
}

}  // namespace spy_test

TEST(LdlpgsSpy, FieldsAndConsistencyOnEveryTalkScene) {
  for (const char* args : {"mechanism-50 --no-shatter", "mechanism-50", "tracked-vehicle", "multi-wheeled-vehicle",
                           "multi-wheeled-vehicle --no-shatter", "multi-wheeled-vehicle --shards 10",
                           "tracked-vehicle --ordering amd", "four-bar --ordering amd-scalar"}) {
    SCOPED_TRACE(args);
    const nlohmann::json j = spy_test::spy(args);
    for (const char* key : {"scene", "shattered", "constraints", "n", "density", "flops", "nnz_L", "ordering",
                            "pivots", "block_sizes", "H_blocks", "L_blocks"})
      EXPECT_TRUE(j.contains(key)) << key;
    spy_test::expect_consistent(j);
  }
}

TEST(LdlpgsSpy, MechanismFiftyHasTheTalksSize) {
  const nlohmann::json j = spy_test::spy("mechanism-50 --no-shatter");
  EXPECT_EQ(j["scene"], "mechanism-50");
  EXPECT_FALSE(j["shattered"].get<bool>());
  EXPECT_EQ(j["constraints"], 50);  // the talk's: 50 constraints, dim(H) = 246, 12% dense
  EXPECT_EQ(j["n"], 246);
  EXPECT_NEAR(j["density"].get<double>(), 0.12, 0.005);
  EXPECT_EQ(j["ordering"], "best");
  EXPECT_TRUE(j["chosen"].is_string());
}

TEST(LdlpgsSpy, TrackedVehicleAgainstExportAndCholmod) {
  // H's blocks are those of the exported matrix, renumbered by the pivots; nnz(L) and flops are
  // CHOLMOD's for the scalar permutation they expand to (H's blocks are dense).
  const nlohmann::json j = spy_test::spy("tracked-vehicle --no-shatter");
  const std::string mtx = temp_path("h.mtx"), blocks = temp_path("h.blocks");
  const Result r = run("export tracked-vehicle --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  const SymmetricCsc a = read_matrix_market(mtx);
  const std::vector<int> sizes = read_partition(blocks, a.n);
  ASSERT_EQ(j["n"].get<int>(), a.n);
  std::vector<int> block_of_row, first_row;
  for (size_t b = 0; b < sizes.size(); ++b) {
    first_row.push_back(static_cast<int>(block_of_row.size()));
    block_of_row.insert(block_of_row.end(), sizes[b], static_cast<int>(b));
  }
  const std::vector<int> pivots = j["pivots"].get<std::vector<int>>();
  ASSERT_EQ(pivots.size(), sizes.size());
  std::vector<int> position(pivots.size()), perm;
  for (size_t k = 0; k < pivots.size(); ++k) {
    position[pivots[k]] = static_cast<int>(k);
    EXPECT_EQ(j["block_sizes"][k].get<int>(), sizes[pivots[k]]);
    for (int r = 0; r < sizes[pivots[k]]; ++r) perm.push_back(first_row[pivots[k]] + r);
  }
  spy_test::BlockSet from_matrix;
  int64_t full = 0;
  for (int c = 0; c < a.n; ++c)
    for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p) {
      const int i = position[block_of_row[a.row_idx[p]]], k = position[block_of_row[c]];
      from_matrix.insert({std::max(i, k), std::min(i, k)});
      full += a.row_idx[p] == c ? 1 : 2;
    }
  EXPECT_EQ(spy_test::h_blocks(j), from_matrix);
  EXPECT_DOUBLE_EQ(j["density"].get<double>(), static_cast<double>(full) / (double(a.n) * a.n));
  Cholmod cm;
  const CholmodCounts c = cholmod_counts(a, perm, cm);
  EXPECT_EQ(j["nnz_L"].get<double>(), c.lnz);
  EXPECT_EQ(j["flops"].get<double>(), c.fl);
}

TEST(LdlpgsSpy, WholeMultiWheeledVehicleIsDense) {
  const nlohmann::json j = spy_test::spy("multi-wheeled-vehicle --no-shatter");
  EXPECT_FALSE(j["shattered"].get<bool>());
  EXPECT_TRUE(j["shatter_threshold"].is_null());
  EXPECT_EQ(j["constraints"], 20);
  EXPECT_EQ(j["n"], 88);
  EXPECT_EQ(j["density"].get<double>(), 1.0);
  EXPECT_EQ(j["H_blocks"].size(), 20u * 21 / 2);  // every pair of wheels shares the chassis
  EXPECT_EQ(j["fill_blocks"], 0);                  // a dense matrix has nothing to fill
}

TEST(LdlpgsSpy, ShatteringTheMultiWheeledVehicle) {
  const nlohmann::json whole = spy_test::spy("multi-wheeled-vehicle --no-shatter");
  const nlohmann::json chosen = spy_test::spy("multi-wheeled-vehicle");  // --shatter 20: k by flops
  EXPECT_TRUE(chosen["shattered"].get<bool>());
  EXPECT_EQ(chosen["shatter_threshold"], 20);
  EXPECT_EQ(chosen["shattered_bodies"], 1);  // the chassis, of 88 rows; a wheel has 4 or 5
  const int welds = chosen["welds"].get<int>();
  EXPECT_EQ(chosen["constraints"].get<int>(), 20 + welds);
  EXPECT_EQ(chosen["n"].get<int>(), 88 + 6 * welds);
  EXPECT_LT(chosen["density"].get<double>(), 1.0);
  EXPECT_LT(chosen["flops"].get<double>(), whole["flops"].get<double>() / 4);
  // the talk's shattered vehicle: 29 constraints, dim(H) 142, density 17.5%: ten shards
  const nlohmann::json ten = spy_test::spy("multi-wheeled-vehicle --shards 10");
  EXPECT_EQ(ten["welds"], 9);
  EXPECT_EQ(ten["constraints"], 29);
  EXPECT_EQ(ten["n"], 142);
  EXPECT_NEAR(ten["density"].get<double>(), 0.175, 0.0005);
}

TEST(LdlpgsSpy, SceneOutIsTheMechanismSpied) {
  const std::string scene = temp_path("shattered.json"), mtx = temp_path("s.mtx"), blocks = temp_path("s.blocks");
  const nlohmann::json j = spy_test::spy("multi-wheeled-vehicle --shards 10 --scene-file " + scene);
  const Result r = run("export " + scene + " --no-shatter --matrix-file " + mtx + " --blocks-file " + blocks);
  ASSERT_EQ(r.code, 0) << r.err;
  const SymmetricCsc a = read_matrix_market(mtx);
  EXPECT_EQ(a.n, j["n"].get<int>());
  EXPECT_EQ(read_partition(blocks, a.n).size(), j["block_sizes"].size());
  const Result help = run("spy --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--no-shatter"), std::string::npos);
}

}  // namespace
}  // namespace ldlpgs::testing
