// The numeric block LDL^T. One harness over matrix families x block partitions x orderings
// compares the factor with CHOLMOD's simplicial LDL^T under the same permutation (verify.h) and,
// on small matrices, with dense Eigen; then one named test per hard case.
#include "ldlpgs/factor/numeric.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "ldlpgs/factor/verify.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/families.h"
#include "ldlpgs/sparse/mechanism_matrix.h"
#include "ldlpgs/sparse/partition.h"
#include "tests/support/test_matrices.h"

#include "tests/support/allocation_counter.h"  // (replaces operator new: one per executable)

namespace ldlpgs {
namespace {

struct Case {
  std::string name;      // test matrix file or family-size
  std::string partition; // auto, a uniform size, or "constraints" (the mechanism's own blocks)
  std::string ordering;
  // The supernodes (SymbolicOptions): "default"; "none", every pivot alone; "blas", every run of
  // nested pivots merged and eliminated with dense.h however narrow, so the BLAS path meets
  // every family and partition and not only the few wide fronts the defaults give it; both with
  // RSI runs only. "mapped" and "blas-mapped": the same two with every supernode scattering
  // through relative maps (SymbolicOptions::rsi_max_per_entry = 0). "small-blas": the defaults
  // but blas_min_rows 2, so the small supernodes (runs cut into pieces of up to 6 rows, relaxed
  // as far as they fit: relax_max_zeros 1) run on dense.h too; "relaxed": the same small
  // supernodes on the unrolled kernels.
  std::string supernodes = "default";
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name << " blocks " << c.partition << " " << c.ordering << " supernodes " << c.supernodes;
}

const char* const kSupernodeConfigs[] = {"none", "blas", "mapped", "blas-mapped", "small-blas", "relaxed"};

SymbolicOptions symbolic_options(const Case& c) {
  if (c.supernodes == "none") return {.supernode_min_rows = 0, .rsi_max_per_entry = -1};
  if (c.supernodes == "blas") return {.supernode_min_rows = 1, .supernode_min_front = 0, .blas_min_rows = 1, .rsi_max_per_entry = -1};
  if (c.supernodes == "mapped") return {.supernode_min_rows = 0, .rsi_max_per_entry = 0};
  if (c.supernodes == "blas-mapped") return {.supernode_min_rows = 1, .supernode_min_front = 0, .blas_min_rows = 1, .rsi_max_per_entry = 0};
  if (c.supernodes == "small-blas") return {.relax_max_zeros = 1, .blas_min_rows = 2};
  if (c.supernodes == "relaxed") return {.relax_max_zeros = 1};
  return {};
}

struct Problem {
  SymmetricCsc a;
  BlockPattern blocks;
};

Problem problem(const Case& c) {
  Problem p;
  const size_t dash = c.name.rfind('-');
  if (c.name.ends_with(".mtx")) {
    p.a = read_matrix_market(std::string(LDLPGS_MATRICES) + "/" + c.name);
  } else {
    const BodyGraph g = make_family(c.name.substr(0, dash), std::stoi(c.name.substr(dash + 1)));
    p.a = mechanism_matrix(g);
    if (c.partition == "constraints") {
      p.blocks = constraint_graph(g);
      return p;
    }
  }
  p.blocks = BlockPattern::from_scalar(p.a, parse_partition(c.partition, p.a, 6));
  return p;
}

Eigen::VectorXd to_eigen(const std::vector<double>& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size()); }

// Where the default kernels are the AVX2 ones (factor/passes.h), the baseline's give the same
// factor (values, status, inertia, pivot ratio) and the same solution, bit for bit (each lane
// does the scalar operations in order; the solve is the SSE2 one in both, so x checks only that
// the factors agree where it reads them).
void expect_the_same_with_sse2_kernels(const Symbolic& s, const SymmetricCsc& a, Numeric& f) {
  if (std::string(kernel_isa()) == "sse2") return;
  set_kernel_isa("sse2");
  Numeric baseline(s);
  const bool usable = baseline.factorize(a).usable();
  std::vector<double> x(a.n), x_baseline(a.n);
  for (int i = 0; i < a.n; ++i) x[i] = x_baseline[i] = 1 + std::sin(i);
  if (usable) baseline.solve(x_baseline);
  set_kernel_isa("auto");
  ASSERT_TRUE(usable);
  const FactorInfo& a_info = baseline.info();
  const FactorInfo& b_info = f.info();
  EXPECT_EQ(a_info.status, b_info.status);
  EXPECT_EQ(a_info.inertia.positive, b_info.inertia.positive);
  EXPECT_EQ(a_info.inertia.negative, b_info.inertia.negative);
  EXPECT_EQ(std::bit_cast<uint64_t>(a_info.min_pivot_ratio), std::bit_cast<uint64_t>(b_info.min_pivot_ratio));
  f.solve(x);
  for (size_t q = 0; q < f.values().size(); ++q)
    ASSERT_EQ(std::bit_cast<uint64_t>(baseline.values()[q]), std::bit_cast<uint64_t>(f.values()[q])) << "value " << q;
  for (int i = 0; i < a.n; ++i)
    ASSERT_EQ(std::bit_cast<uint64_t>(x_baseline[i]), std::bit_cast<uint64_t>(x[i])) << "x " << i;
}

class FactorHarness : public ::testing::TestWithParam<Case> {};

TEST_P(FactorHarness, AgreesWithCholmodAndDenseEigen) {
  const Case& c = GetParam();
  const Problem p = problem(c);
  const Ordering o = compute_ordering(find_ordering(c.ordering), p.blocks, p.a);
  const Verification v = verify_against_cholmod(p.a, p.blocks, o, {}, symbolic_options(c));
  EXPECT_EQ(v.info.status, FactorStatus::ok) << v.info.message();
  EXPECT_EQ(v.info.inertia.positive, p.a.n);
  EXPECT_LE(v.backward_error, 1e-14);
  // 1e-10 on well-conditioned matrices, eps * cond_1 beyond (verify.h).
  const double tolerance = std::max(1e-10, 2.2e-16 * v.condition_estimate);
  EXPECT_LE(v.L_rel_diff, tolerance) << "cond " << v.condition_estimate;
  EXPECT_LE(v.D_rel_diff, tolerance);
  EXPECT_LE(v.x_rel_diff, tolerance);
  EXPECT_TRUE(v.ok);
  // Counting dense blocks can only add entries to CHOLMOD's exact pattern.
  EXPECT_GE(v.nnz_L, v.nnz_L_cholmod);
  EXPECT_GE(v.flops, v.flops_cholmod);
  {
    // A factorization leaves nothing behind: factoring another matrix of the pattern first
    // (0.5 (A + diag A), positive definite, other values in every fill block) and then A gives
    // the values a fresh Numeric gives A, bit for bit (load() zeroes only what it must).
    const Symbolic s = Symbolic::analyze(p.a, p.blocks, o, symbolic_options(c));
    SymmetricCsc other = p.a;
    for (int j = 0; j < other.n; ++j)
      for (int q = other.col_ptr[j]; q < other.col_ptr[j + 1]; ++q)
        if (other.row_idx[q] != j) other.values[q] *= 0.5;
    Numeric reused(s), fresh(s);
    ASSERT_TRUE(reused.factorize(other).usable());
    ASSERT_TRUE(reused.factorize(p.a).usable());
    ASSERT_TRUE(fresh.factorize(p.a).usable());
    ASSERT_EQ(reused.values().size(), fresh.values().size());
    for (size_t q = 0; q < fresh.values().size(); ++q)
      ASSERT_EQ(std::bit_cast<uint64_t>(reused.values()[q]), std::bit_cast<uint64_t>(fresh.values()[q])) << "value " << q;
    expect_the_same_with_sse2_kernels(s, p.a, fresh);
  }
  if (p.a.n > 300) return;
  // Dense references: P^T L D L^T P = A, and x = A^-1 b from Eigen's LDLT.
  const Symbolic s = Symbolic::analyze(p.a, p.blocks, o, symbolic_options(c));
  Numeric f(s);
  ASSERT_TRUE(f.factorize(p.a).usable());
  const Eigen::MatrixXd a = testing::dense(p.a), ld = testing::dense(f.scalar_ldl());
  Eigen::MatrixXd l = ld.triangularView<Eigen::StrictlyLower>();
  l += Eigen::MatrixXd::Identity(p.a.n, p.a.n);
  Eigen::MatrixXd pa(p.a.n, p.a.n);
  for (int i = 0; i < p.a.n; ++i)
    for (int j = 0; j < p.a.n; ++j) pa(i, j) = a(s.perm()[i], s.perm()[j]);
  EXPECT_LT((l * ld.diagonal().asDiagonal() * l.transpose() - pa).norm(), 1e-13 * a.norm());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(p.a.n, 1, 2);
  std::vector<double> x(b.data(), b.data() + p.a.n);
  f.solve(x);
  const Eigen::VectorXd dense_x = a.ldlt().solve(b);
  EXPECT_LE((to_eigen(x) - dense_x).norm() / dense_x.norm(), tolerance);
}

std::vector<Case> cases() {
  std::vector<Case> out;
  const std::vector<std::string> orderings = {"natural", "mda", "mda-w", "meca", "meca-w", "amd", "amd-scalar", "metis", "metis-scalar"};
  for (const auto& file : std::filesystem::directory_iterator(LDLPGS_MATRICES)) {
    const std::string name = file.path().filename().string();
    if (file.path().extension() != ".mtx" || name == "Pd.mtx") continue;  // Pd: unsymmetric
    for (const char* partition : {"auto", "1", "3", "6"})
      for (const std::string& o : orderings) {
        if (name == "bcsstk13.mtx" && o == "natural") continue;  // dense fill: minutes, nothing new
        out.push_back({name, partition, o});
        if (o == "meca-w" || o == "amd-scalar")
          for (const char* supernodes : kSupernodeConfigs) out.push_back({name, partition, o, supernodes});
      }
  }
  for (std::string_view family : family_names())
    for (int size : {12, 150})
      for (const char* partition : {"constraints", "2"})
        for (const std::string& o : orderings) {
          const std::string name = std::string(family) + "-" + std::to_string(size);
          out.push_back({name, partition, o});
          if (o == "meca-w" || o == "amd-scalar")
            for (const char* supernodes : kSupernodeConfigs) out.push_back({name, partition, o, supernodes});
        }
  return out;
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.name + "_" + info.param.partition + "_" + info.param.ordering;
  if (info.param.supernodes != "default") s += "_supernodes_" + info.param.supernodes;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(All, FactorHarness, ::testing::ValuesIn(cases()), case_name);

// --- Hard cases -------------------------------------------------------------------------------

Symbolic analyze(const SymmetricCsc& a, const BlockPattern& blocks, const char* ordering = "meca") {
  return Symbolic::analyze(a, blocks, compute_ordering(find_ordering(ordering), blocks, a));
}

// a with f applied to every stored diagonal entry.
template <class F>
SymmetricCsc map_diagonal(SymmetricCsc a, F f) {
  for (int c = 0; c < a.n; ++c)
    for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p)
      if (a.row_idx[p] == c) a.values[p] = f(a.values[p]);
  return a;
}

// A body welded twice to the ground: 12 rows on 6 freedoms, the simplest redundant loop.
BodyGraph double_weld() {
  BodyGraph g;
  g.is_static = {0, 1};
  g.joints = {{0, 1, 6}, {0, 1, 6}};
  return g;
}

TEST(Numeric, SingularRedundantLoopIsReportedAndRegularizationFixesIt) {
  for (const BodyGraph& g : {double_weld(), make_family("ladder", 40)}) {
    const SymmetricCsc h = mechanism_matrix(g, 1, 0.0);
    const BlockPattern blocks = constraint_graph(g);
    const Symbolic s = analyze(h, blocks);
    Numeric f(s);
    const FactorInfo exact = f.factorize(h);
    EXPECT_EQ(exact.status, FactorStatus::zero_pivot) << exact.message();
    EXPECT_GE(exact.block, 0);
    EXPECT_EQ(exact.inertia.zero, 1);
    EXPECT_FALSE(exact.usable());
    // The talk's compliance: H + 1e-8 diag(H), factored without a new symbolic phase, equals
    // CHOLMOD's factor of the explicitly regularized matrix.
    const FactorInfo regularized = f.factorize(h, {.regularization = 1e-8});
    EXPECT_EQ(regularized.status, FactorStatus::ok) << regularized.message();
    EXPECT_LT(regularized.min_pivot_ratio, 1e-6);  // nearly singular, and visible
    const SymmetricCsc hr = map_diagonal(h, [](double x) { return x * (1 + 1e-8); });
    std::vector<double> b(h.n, 1.0), x = b;
    f.solve(x);
    EXPECT_LE(backward_error(hr, x, b), 1e-14);
  }
}

TEST(Numeric, MassRatiosOfAMillion) {
  // A chain whose every other body, and the load at its end, is 1e6 times heavier.
  const BodyGraph g = make_family("chain", 30);
  std::vector<double> mass(g.num_bodies(), 1.0);
  for (int b = 0; b < g.num_bodies(); b += 2) mass[b] = 1e6;
  mass.back() = 1e6;
  const SymmetricCsc h = mechanism_matrix(g, 3, 1e-8, mass);
  const BlockPattern blocks = constraint_graph(g);
  for (const char* name : {"meca", "amd", "natural"}) {
    const Verification v = verify_against_cholmod(h, blocks, compute_ordering(find_ordering(name), blocks, h));
    EXPECT_EQ(v.info.status, FactorStatus::ok) << name;
    EXPECT_GT(v.condition_estimate, 1e5) << name;  // the ratio shows in the condition
    EXPECT_LE(v.backward_error, 1e-14) << name;
    EXPECT_TRUE(v.ok) << name << ": L " << v.L_rel_diff << " x " << v.x_rel_diff << " cond " << v.condition_estimate;
  }
}

TEST(Numeric, OneByOneAndEmpty) {
  const SymmetricCsc one = csc_from_triplets(1, std::vector<Triplet>{{0, 0, 4.0}});
  const BlockPattern blocks = BlockPattern::from_scalar(one, {std::vector<int>{1}});
  const Symbolic s = analyze(one, blocks);
  Numeric f(s);
  EXPECT_EQ(f.factorize(one).status, FactorStatus::ok);
  std::vector<double> x = {2.0};
  f.solve(x);
  EXPECT_EQ(x[0], 0.5);

  const SymmetricCsc empty{0, {0}, {}, {}};
  const BlockPattern none = BlockPattern::from_scalar(empty, {});
  const Symbolic se = analyze(empty, none);
  Numeric fe(se);
  const FactorInfo info = fe.factorize(empty);
  EXPECT_EQ(info.status, FactorStatus::ok);
  EXPECT_EQ(info.inertia.positive + info.inertia.negative + info.inertia.zero, 0);
  std::vector<double> nothing;
  fe.solve(nothing);
}

TEST(Numeric, BlocksOfSizeOneAndTwelve) {
  // 12 runs the generic (not unrolled) kernels; bcsstk02 is completely dense.
  for (const char* partition : {"1", "12"}) {
    for (const auto& m : testing::test_matrices()) {
      if (m.name != "bcsstk02.mtx" && m.name != "bcsstk01.mtx") continue;
      const BlockPattern blocks = BlockPattern::from_scalar(m.a, parse_partition(partition, m.a, 12));
      const Verification v = verify_against_cholmod(m.a, blocks, compute_ordering(find_ordering("meca"), blocks, m.a));
      EXPECT_TRUE(v.ok) << m.name << " blocks " << partition << ": L " << v.L_rel_diff;
      EXPECT_LE(v.backward_error, 1e-14);
    }
  }
}

TEST(Numeric, IndefiniteIsReportedWithSylvestersInertia) {
  // bcsstk01 - sigma I with sigma between eigenvalues: the negative pivots must number the
  // eigenvalues below sigma (Sylvester's law of inertia), and the factor still solves.
  const auto& all = testing::test_matrices();
  const auto it = std::find_if(all.begin(), all.end(), [](const auto& m) { return m.name == "bcsstk01.mtx"; });
  ASSERT_NE(it, all.end());
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(testing::dense(it->a)).eigenvalues();
  const double sigma = 0.5 * (eig(9) + eig(10));
  const SymmetricCsc a = map_diagonal(it->a, [sigma](double x) { return x - sigma; });
  const BlockPattern blocks = BlockPattern::from_scalar(a, partition_auto(a));
  const Symbolic s = analyze(a, blocks);
  Numeric f(s);
  const FactorInfo info = f.factorize(a);
  EXPECT_EQ(info.status, FactorStatus::indefinite) << info.message();
  EXPECT_LT(info.pivot, 0);
  EXPECT_EQ(info.inertia.negative, 10);
  EXPECT_EQ(info.inertia.positive, a.n - 10);
  std::vector<double> b(a.n, 1.0), x = b;
  f.solve(x);
  EXPECT_LE(backward_error(a, x, b), 1e-12);

  const SymmetricCsc small = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 1}, {1, 0, 2}, {1, 1, 1}});
  const Symbolic s2 = analyze(small, BlockPattern::from_scalar(small, {std::vector<int>{1, 1}}), "natural");
  Numeric f2(s2);
  const FactorInfo info2 = f2.factorize(small);
  EXPECT_EQ(info2.status, FactorStatus::indefinite);
  EXPECT_EQ(info2.inertia.positive, 1);
  EXPECT_EQ(info2.inertia.negative, 1);
  EXPECT_EQ(info2.pivot, -3);
}

// Indefinite nodes wide enough for BLAS go by dense.h's LDL^T panels, whose products also land in
// the node block's other triangle, which the load zeroes only in a node that other supernodes
// update. Two fronts of 100 rows, uncoupled, and 130 rows coupled to both: in natural order the
// first front is one BLAS supernode, the second nests into the last rows and makes the other
// (230 rows, folding the first one's updates); negative pivots in both, a dominant diagonal:
// Sylvester's inertia, the solve, and a Numeric that factored another matrix first gives a fresh
// one's values bit for bit.
TEST(Numeric, IndefiniteBlasNodesLeaveNothingBehind) {
  const int front = 100, n = 2 * front + 130;
  std::vector<double> sign(n, 1.0);
  for (const int r : {3, 70, 150, 230, 231, n - 1}) sign[r] = -1;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Triplet> t;
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i)
      if (i >= 2 * front || (i < front) == (j < front)) t.push_back({i, j, i == j ? sign[i] * 2 * n : u(rng)});
  const SymmetricCsc a = csc_from_triplets(n, t);
  const BlockPattern blocks = BlockPattern::from_scalar(a, std::vector<int>(n, 1));
  const Symbolic s = analyze(a, blocks, "natural");
  ASSERT_EQ(s.num_supernodes(), 2);
  EXPECT_EQ(s.supernode_size(0), front);
  for (int k = 0; k < 2; ++k) EXPECT_TRUE(s.supernode_blas(k)) << k;
  Numeric reused(s), fresh(s);
  const FactorInfo info = fresh.factorize(a);
  EXPECT_EQ(info.status, FactorStatus::indefinite) << info.message();
  EXPECT_EQ(info.inertia.negative, 6);
  EXPECT_EQ(info.inertia.positive, n - 6);
  std::vector<double> b(n, 1.0), x = b;
  fresh.solve(x);
  EXPECT_LE(backward_error(a, x, b), 1e-14);
  SymmetricCsc other = a;
  for (int j = 0; j < n; ++j)
    for (int q = other.col_ptr[j]; q < other.col_ptr[j + 1]; ++q)
      if (other.row_idx[q] != j) other.values[q] *= 0.5;
  ASSERT_TRUE(reused.factorize(other).usable());
  ASSERT_TRUE(reused.factorize(a).usable());
  for (size_t q = 0; q < fresh.values().size(); ++q)
    ASSERT_EQ(std::bit_cast<uint64_t>(reused.values()[q]), std::bit_cast<uint64_t>(fresh.values()[q])) << "value " << q;
}

TEST(Numeric, NanInTheInputNamesItsBlock) {
  const BodyGraph g = make_family("chain", 5);
  SymmetricCsc h = mechanism_matrix(g);
  const BlockPattern blocks = constraint_graph(g);
  const Symbolic s = analyze(h, blocks);
  Numeric f(s);
  const int row = blocks.block(3).position + 1;
  h.values[h.col_ptr[row]] = std::numeric_limits<double>::quiet_NaN();  // diagonal of that row
  const FactorInfo info = f.factorize(h);
  EXPECT_EQ(info.status, FactorStatus::not_finite);
  EXPECT_EQ(info.block, 3);
  EXPECT_EQ(info.row, row);
  EXPECT_FALSE(info.usable());
}

// Loading through the load map by hand (what solver/ does to assemble H straight into the
// factor) gives the factor that factorize(matrix) gives, bit for bit, and a NaN loaded that way
// is named by its block and row as in the matrix path (off-diagonal entries included).
TEST(Numeric, LoadedByHandFactorsAsTheMatrixDoes) {
  for (const char* family : {"chain", "grid", "heavy"}) {
    const BodyGraph g = make_family(family, 12);
    SymmetricCsc h = mechanism_matrix(g);
    const BlockPattern blocks = constraint_graph(g);
    const Symbolic s = analyze(h, blocks);
    Numeric by_matrix(s), by_hand(s);
    const auto load = [&](const SymmetricCsc& a) {
      const std::span<double> v = by_hand.begin_load();
      for (int64_t p = 0; p < a.nnz(); ++p) v[s.load_map()[p]] += a.values[p];
      return by_hand.factorize_loaded({.regularization = 1e-9});
    };
    const FactorInfo a = by_matrix.factorize(h, {.regularization = 1e-9}), b = load(h);
    EXPECT_EQ(a.status, b.status) << family;
    EXPECT_TRUE(std::equal(by_matrix.values().begin(), by_matrix.values().end(), by_hand.values().begin())) << family;
    for (int64_t p : {int64_t{0}, h.nnz() / 2, h.nnz() - 1}) {
      SymmetricCsc bad = h;
      bad.values[p] = std::numeric_limits<double>::infinity();
      const FactorInfo x = by_matrix.factorize(bad), y = load(bad);
      EXPECT_EQ(y.status, FactorStatus::not_finite) << family;
      EXPECT_EQ(x.status, FactorStatus::not_finite) << family;
      // The matrix path names the entry's row; by hand, the row or the column of the entry (the
      // packed block holding it is a node block or an edge block of the earlier pivot), and the
      // block holding that row.
      int col = 0;
      while (h.col_ptr[col + 1] <= p) ++col;
      EXPECT_TRUE(y.row == col || y.row == h.row_idx[p]) << family << " entry " << p << ": row " << y.row;
      const Block& named = blocks.block(y.block);
      EXPECT_TRUE(y.row >= named.position && y.row < named.position + named.size) << family << " entry " << p;
      EXPECT_TRUE(std::isinf(y.pivot)) << family;
    }
  }
}

TEST(Numeric, SeveralRightHandSidesAndReuse) {
  const BodyGraph g = make_family("tree", 40);
  const BlockPattern blocks = constraint_graph(g);
  const SymmetricCsc h1 = mechanism_matrix(g, 1), h2 = mechanism_matrix(g, 2);
  const Symbolic s = analyze(h1, blocks);
  Numeric f(s);
  for (const SymmetricCsc* h : {&h1, &h2}) {  // one symbolic phase, two matrices
    ASSERT_EQ(f.factorize(*h).status, FactorStatus::ok);
    const int n = h->n, nrhs = 3, ld = n + 2;
    std::vector<double> b(static_cast<size_t>(ld) * nrhs);
    for (size_t i = 0; i < b.size(); ++i) b[i] = std::sin(0.37 * i);
    std::vector<double> x = b;
    f.solve(x.data(), nrhs, ld);
    for (int j = 0; j < nrhs; ++j) {
      const std::span<const double> xj(x.data() + j * ld, n), bj(b.data() + j * ld, n);
      EXPECT_LE(backward_error(*h, xj, bj), 1e-14);
      EXPECT_EQ(x[j * ld + n], b[j * ld + n]);  // padding untouched
    }
  }
}

TEST(Numeric, FactorizeAndSolveAllocateNothing) {
  for (const char* family : {"grid", "heavy"}) {
    const BodyGraph g = make_family(family, 30);
    const BlockPattern blocks = constraint_graph(g);
    const SymmetricCsc h = mechanism_matrix(g);
    const Symbolic s = analyze(h, blocks);
    Numeric f(s);
    std::vector<double> x(h.n, 1.0), many(3 * h.n, 1.0);
    allocations = 0;
    counting = true;
    const FactorInfo info = f.factorize(h, {.regularization = 1e-9});
    f.solve(x);
    f.solve(many.data(), 3, h.n);
    counting = false;
    EXPECT_EQ(info.status, FactorStatus::ok);
    EXPECT_EQ(allocations, 0) << family;
  }
  // The counter itself works: a vector allocates (its data escapes, so the allocation stays).
  allocations = 0;
  counting = true;
  std::vector<double> v(10);
  [[maybe_unused]] static double* volatile escape;
  escape = v.data();
  counting = false;
  EXPECT_EQ(allocations, 1);
}

// Misuse of the public API, one test per kind, in every build (Release included): each is an
// ArgumentError with a message, never a crash or heap corruption.
SymmetricCsc small_spd() {  // tridiagonal 4 x 4, diagonally dominant
  return csc_from_triplets(4, std::vector<Triplet>{{0, 0, 4}, {1, 1, 4}, {2, 2, 4}, {3, 3, 4}, {1, 0, 1}, {2, 1, 1}, {3, 2, 1}});
}

// A Numeric keeps a pointer to its Symbolic: built from a temporary it would dangle, so that
// does not compile.
static_assert(!std::is_constructible_v<Numeric, Symbolic&&>);
static_assert(std::is_constructible_v<Numeric, const Symbolic&>);

TEST(NumericMisuse, FactorizeOfAnotherPatternThrows) {
  const SymmetricCsc a = small_spd();
  const Symbolic s = Symbolic::analyze(a, BlockPattern::unit(a), std::vector<int>{0, 1, 2, 3});
  Numeric f(s);
  ASSERT_TRUE(f.factorize(a).usable());
  SymmetricCsc other = csc_from_triplets(4, std::vector<Triplet>{{0, 0, 4}, {1, 1, 4}, {2, 2, 4}, {3, 3, 4}, {3, 0, 1}});
  EXPECT_THROW(f.factorize(other), ArgumentError);
  other = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 4}, {1, 1, 4}, {2, 2, 4}});
  EXPECT_THROW(f.factorize(other), ArgumentError);  // another size
  other = a;
  other.row_idx[1] = 9;  // not even a valid matrix
  EXPECT_THROW(f.factorize(other), ArgumentError);
  // The refused calls left the last factorization as it was.
  std::vector<double> b{1, 2, 3, 4};
  f.solve(b);
  EXPECT_LT(backward_error(a, b, std::vector<double>{1, 2, 3, 4}), 1e-15);
}

TEST(NumericMisuse, RightHandSideOfTheWrongSizeThrows) {
  const SymmetricCsc a = small_spd();
  const Symbolic s = Symbolic::analyze(a, BlockPattern::unit(a), std::vector<int>{0, 1, 2, 3});
  Numeric f(s);
  ASSERT_TRUE(f.factorize(a).usable());
  std::vector<double> shorter(3, 1.0), longer(5, 1.0), two(8, 1.0);
  EXPECT_THROW(f.solve(shorter), ArgumentError);
  EXPECT_THROW(f.solve(longer), ArgumentError);
  EXPECT_THROW(f.solve(two, 3), ArgumentError);
  EXPECT_NO_THROW(f.solve(two, 2));
  EXPECT_THROW(f.solve(two.data(), 2, 3), ArgumentError);  // leading dimension below n
}

TEST(NumericMisuse, SolveWithoutAUsableFactorizationThrows) {
  const SymmetricCsc a = small_spd();
  const Symbolic s = Symbolic::analyze(a, BlockPattern::unit(a), std::vector<int>{0, 1, 2, 3});
  Numeric f(s);
  std::vector<double> b(4, 1.0);
  EXPECT_THROW(f.solve(b), ArgumentError);  // nothing factored yet
  SymmetricCsc singular = a;
  std::fill(singular.values.begin(), singular.values.end(), 0.0);
  ASSERT_EQ(f.factorize(singular, {.regularization = 0}).status, FactorStatus::zero_pivot);
  EXPECT_THROW(f.solve(b), ArgumentError);
}

TEST(NumericMisuse, NanEntryIsTheStatusNotFiniteNamingIt) {
  SymmetricCsc a = small_spd();
  const Symbolic s = Symbolic::analyze(a, BlockPattern::unit(a), std::vector<int>{0, 1, 2, 3});
  Numeric f(s);
  a.values[3] = std::numeric_limits<double>::quiet_NaN();  // column 1's off-diagonal (2, 1)
  const FactorInfo info = f.factorize(a);
  EXPECT_EQ(info.status, FactorStatus::not_finite);
  EXPECT_EQ(info.row, 2);
}

TEST(NumericMisuse, UnknownKernelIsaThrows) {
  EXPECT_THROW(set_kernel_isa("avx1024"), ArgumentError);
  EXPECT_THROW(set_kernel_isa(""), ArgumentError);
  const std::string isa = kernel_isa();
  EXPECT_TRUE(isa == "sse2" || isa == "avx2") << isa;
  set_kernel_isa("sse2");
  EXPECT_STREQ(kernel_isa(), "sse2");
  EXPECT_FALSE(kernels_use_avx2());  // (solver/'s contact lanes follow the same choice)
  set_kernel_isa("auto");
  EXPECT_EQ(kernel_isa(), isa);
  EXPECT_EQ(kernels_use_avx2(), isa != "sse2");
}

// A CPU with AVX2 runs the AVX2 kernels by default (x86-64 builds with GCC or clang have them:
// factor/CMakeLists.txt), so that the harness above compares two builds and not one with itself.
TEST(Numeric, AnAvx2CpuRunsTheAvx2Kernels) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2";
  EXPECT_STREQ(kernel_isa(), "avx2");
#else
  GTEST_SKIP() << "not an x86-64 build";
#endif
}

// The AVX-512 kernels (8 lanes; chosen only on request: papers/factor.md, "Eight lanes with
// AVX-512") give the SSE2 values bit for bit, on every family with its constraints as blocks and
// on test matrices in uniform blocks, with each supernode configuration; refused on a CPU
// without AVX-512F.
TEST(Numeric, Avx512KernelsGiveTheSse2ValuesBitForBit) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx512f")) {
    EXPECT_THROW(set_kernel_isa("avx512"), ArgumentError);
    GTEST_SKIP() << "this CPU has no AVX-512F";
  }
  std::vector<Case> cases;
  for (const char* family : {"chain-60", "tree-100", "ladder-60", "loop-60", "heavy-22", "grid-100", "star-40"})
    for (const char* supernodes : {"default", "none", "blas", "relaxed"}) cases.push_back({family, "constraints", "meca", supernodes});
  for (const char* matrix : {"bcsstk01.mtx", "can___24.mtx", "494_bus.mtx"})
    for (const char* partition : {"3", "5", "auto"}) cases.push_back({matrix, partition, "amd", "default"});
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::PrintToString(c));
    const Problem p = problem(c);
    const Symbolic s = Symbolic::analyze(p.a, p.blocks, compute_ordering(find_ordering(c.ordering), p.blocks, p.a),
                                         symbolic_options(c));
    set_kernel_isa("avx512");
    Numeric f(s);
    const bool usable = f.factorize(p.a).usable();
    set_kernel_isa("auto");
    ASSERT_TRUE(usable);
    expect_the_same_with_sse2_kernels(s, p.a, f);
  }
#else
  GTEST_SKIP() << "not an x86-64 build";
#endif
}

TEST(NumericMisuse, PartitionThatDoesNotCoverTheRowsThrows) {
  const SymmetricCsc a = small_spd();
  EXPECT_THROW(BlockPattern::from_scalar(a, std::vector<int>{2, 1}), ArgumentError);
  EXPECT_THROW(BlockPattern::from_scalar(a, std::vector<int>{2, 3}), ArgumentError);
  EXPECT_THROW(BlockPattern::from_scalar(a, std::vector<int>{2, 0, 2}), ArgumentError);
  const SymmetricCsc b = csc_from_triplets(6, std::vector<Triplet>{{0, 0, 1}, {5, 5, 1}});
  EXPECT_THROW(Symbolic::analyze(a, BlockPattern::unit(b), std::vector<int>{0, 1, 2, 3, 4, 5}), ArgumentError);
}

// Readers, numerics and messages

// a with every stored entry times 2^k (ldexp: exact unless it lands among the subnormals).
SymmetricCsc scaled(SymmetricCsc a, int k) {
  for (double& x : a.values) x = std::ldexp(x, k);
  return a;
}

// Factors a with each partition in {unit, one block} and, if the factorization is usable, solves
// A x = b for b = A (1, -1, ...)^T. The reference is dense Eigen on S A S, S = diag(2^-ilogb(a_ii)/2):
// the same matrix equilibrated by powers of two (exact, subnormals scale up without rounding),
// whose diagonal is near 1 where Eigen's LDL^T works; x_ref = S (S A S)^-1 S b. Returns the
// statuses seen.
std::vector<FactorStatus> factor_and_compare(const SymmetricCsc& a, const std::string& what) {
  const Eigen::MatrixXd dense = testing::dense(a);
  Eigen::VectorXd x_true(a.n);
  for (int i = 0; i < a.n; ++i) x_true[i] = i % 2 ? -1.0 : 1.0;
  const Eigen::VectorXd b = dense * x_true;
  std::vector<int> half(a.n);
  for (int i = 0; i < a.n; ++i) half[i] = -std::ilogb(dense(i, i)) / 2;
  Eigen::MatrixXd equilibrated = dense;
  Eigen::VectorXd b_equilibrated = b;
  for (int i = 0; i < a.n; ++i) {
    b_equilibrated[i] = std::ldexp(b[i], half[i]);
    for (int j = 0; j < a.n; ++j) equilibrated(i, j) = std::ldexp(dense(i, j), half[i] + half[j]);
  }
  Eigen::VectorXd x_ref = equilibrated.ldlt().solve(b_equilibrated);
  for (int i = 0; i < a.n; ++i) x_ref[i] = std::ldexp(x_ref[i], half[i]);
  std::vector<FactorStatus> statuses;
  for (const std::vector<int>& sizes : {std::vector<int>(a.n, 1), std::vector<int>{a.n}}) {
    const BlockPattern blocks = BlockPattern::from_scalar(a, sizes);
    const Symbolic s = analyze(a, blocks);
    Numeric f(s);
    const FactorInfo info = f.factorize(a);
    statuses.push_back(info.status);
    if (!info.usable()) continue;
    std::vector<double> x(b.data(), b.data() + a.n);
    f.solve(x);
    const double diff = (to_eigen(x) - x_ref).lpNorm<Eigen::Infinity>() / x_ref.lpNorm<Eigen::Infinity>();
    EXPECT_LE(diff, 1e-12) << what << ", " << sizes.size() << " blocks: " << info.message()
                           << ", x[0] = " << x[0];
  }
  return statuses;
}

// Class 6: 1e-314 (subnormal) factored "ok" and solved to NaN (1/1e-314 overflows); a positive
// definite 2 x 2 at 1e-320 was "not finite, pivot -inf" (1e-12 |H_rr| underflows to 0, the
// reciprocal of the first pivot is inf). The class: any positive definite matrix scaled by any
// power of two whose entries stay finite factors ok and solves to the reference.
TEST(Numeric, PositiveDefiniteAtEveryScaleOfDoubleFactorsAndSolves) {
  const SymmetricCsc one = csc_from_triplets(1, std::vector<Triplet>{{0, 0, 1e-314}});
  EXPECT_EQ(factor_and_compare(one, "1e-314"), std::vector<FactorStatus>(2, FactorStatus::ok));
  const SymmetricCsc two = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 2e-320}, {1, 1, 2e-320}, {1, 0, 1e-320}});
  EXPECT_EQ(factor_and_compare(two, "2x2 at 1e-320"), std::vector<FactorStatus>(2, FactorStatus::ok));
  const SymmetricCsc chain = mechanism_matrix(make_family("chain", 3), 1, 0.0);
  for (const SymmetricCsc& a : {small_spd(), chain}) {
    for (int k : {-1060, -1040, -1000, -700, -300, 300, 700, 1000}) {
      EXPECT_EQ(factor_and_compare(scaled(a, k), std::to_string(a.n) + " rows at 2^" + std::to_string(k)),
                std::vector<FactorStatus>(2, FactorStatus::ok));
    }
  }
}

// A run that writes its target first (Symbolic::rsi) leaves the last factorization's values
// there until it stores, so nothing before the elimination may read them, the scaling of an
// out-of-range matrix included. A loop (whose fill such runs write) with one block's rows and
// columns scaled by 2^-450 leaves fill near 2^450 in that block's column of L; the loop near
// 2^-600 (scaled into range) must then give a fresh Numeric's values bit for bit.
TEST(Numeric, ReuseAcrossScalesLeavesNothingBehind) {
  const BodyGraph g = make_family("loop", 12);
  const SymmetricCsc h = mechanism_matrix(g);
  const Symbolic s = analyze(h, constraint_graph(g));
  std::vector<double> c(h.n, 1.0);
  const int k = s.num_pivots() / 2;
  for (int r = s.row_start(k); r < s.row_start(k) + s.size(k); ++r) c[s.perm()[r]] = std::ldexp(1.0, -450);
  SymmetricCsc before = h;
  for (int j = 0; j < h.n; ++j)
    for (int p = h.col_ptr[j]; p < h.col_ptr[j + 1]; ++p) before.values[p] *= c[h.row_idx[p]] * c[j];
  Numeric reused(s), fresh(s);
  ASSERT_TRUE(reused.factorize(before).usable());
  ASSERT_TRUE(reused.factorize(scaled(h, -600)).usable());
  ASSERT_TRUE(fresh.factorize(scaled(h, -600)).usable());
  for (size_t q = 0; q < fresh.values().size(); ++q)
    ASSERT_EQ(std::bit_cast<uint64_t>(reused.values()[q]), std::bit_cast<uint64_t>(fresh.values()[q])) << "value " << q;
}

// Rows of very different scales in one matrix: diag(1, 2^-1050) is solvable (scaled into range);
// diag(2^1000, 2^-1070) spans more than double's exponent range, and the tiny pivot's reciprocal
// overflows at any scale that keeps 2^1000 finite: reported as a zero pivot, never "ok" with a
// non-finite solution.
// A node whose entries square past the largest double: 1e-200 and 1e200 on the diagonal keep
// the diagonal's binades centred on 1 (no scaling), and a pivot recurrence that squares the
// unscaled 5e199 (2.5e399) returned -inf for this positive definite matrix (found in review).
TEST(Numeric, LargeEntriesOfAPositiveDefiniteNode) {
  const SymmetricCsc a = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 1e-200}, {1, 1, 1e200}, {2, 1, 5e199}, {2, 2, 1e200}});
  EXPECT_EQ(factor_and_compare(a, "3x3 at 1e200"), std::vector<FactorStatus>(2, FactorStatus::ok));
}

TEST(Numeric, SubnormalPivotIsScaledOrReported) {
  const SymmetricCsc mixed = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 1.0}, {1, 1, std::ldexp(1.0, -1050)}});
  EXPECT_EQ(factor_and_compare(mixed, "diag(1, 2^-1050)"), std::vector<FactorStatus>(2, FactorStatus::ok));
  const SymmetricCsc wide = csc_from_triplets(2, std::vector<Triplet>{{0, 0, std::ldexp(1.0, 1000)}, {1, 1, std::ldexp(1.0, -1070)}});
  const Symbolic s = analyze(wide, BlockPattern::unit(wide));
  Numeric f(s);
  const FactorInfo info = f.factorize(wide);
  EXPECT_EQ(info.status, FactorStatus::zero_pivot) << info.message();
  EXPECT_EQ(info.row, 1) << info.message();
  EXPECT_EQ(info.pivot, std::ldexp(1.0, -1070)) << "the pivot at the matrix's own scale";
}

// The condition estimate is ||A||_1 ||A^-1||_1: at 1e-314 the second factor alone overflows
// (1e314), so verify printed cond inf and a tolerance of inf. It is scale-invariant.
TEST(Verify, ConditionEstimateIsScaleInvariant) {
  const SymmetricCsc a = small_spd();
  const BlockPattern blocks = BlockPattern::unit(a);
  const Ordering o = compute_ordering(find_ordering("natural"), blocks, a);
  const double cond = verify_against_cholmod(a, blocks, o).condition_estimate;
  ASSERT_TRUE(std::isfinite(cond) && cond > 1);
  for (int k : {-1060, -1040, -700, 700, 1000}) {
    const Verification v = verify_against_cholmod(scaled(a, k), blocks, o);
    EXPECT_NEAR(v.condition_estimate, cond, 1e-3 * cond) << "2^" << k;
    EXPECT_EQ(v.info.status, FactorStatus::ok) << "2^" << k;
  }
}

// A matrix CHOLMOD refuses: cholmod_row is the original row of the column where it stopped.
// diag(2, 0, 3) in the order 2, 0, 1 stops at column 2, row 1 (the column, or the inverse order,
// would say 2 or 0); ours refuses the same row.
TEST(Verify, CholmodRowIsTheOriginalRow) {
  const SymmetricCsc a = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 2}, {1, 1, 0}, {2, 2, 3}});
  const BlockPattern blocks = BlockPattern::unit(a);
  Ordering o;
  o.name = o.chosen = "given";
  o.pivots = o.perm = {2, 0, 1};
  const Verification v = verify_against_cholmod(a, blocks, o);
  EXPECT_EQ(v.cholmod_row, 1);
  EXPECT_EQ(v.info.status, FactorStatus::zero_pivot);
  EXPECT_EQ(v.info.row, 1);
  EXPECT_FALSE(v.ok);
  o.pivots = o.perm = {0, 2, 1};
  const SymmetricCsc spd = csc_from_triplets(3, std::vector<Triplet>{{0, 0, 2}, {1, 1, 1}, {2, 2, 3}});
  EXPECT_EQ(verify_against_cholmod(spd, blocks, o).cholmod_row, -1);
}

// Class 6: verify reported agreement on a tolerance it could not compute (cond estimate inf, so
// tolerance inf, "agree" with x 5.27 off); a tolerance of 1 or more (cond_1 >= 4.5e15) verifies
// no digit either. Both are "cannot verify", not agreement.
// A NaN, infinite or negative tolerance is the caller's error: inf had switched the backward check
// off ("agree" whatever the error), nan failed everything.
TEST(Verify, NonFiniteOrNegativeToleranceIsRefused) {
  const SymmetricCsc a = csc_from_triplets(2, std::vector<Triplet>{{0, 0, 2}, {1, 1, 3}});
  const BlockPattern blocks = BlockPattern::unit(a);
  Ordering o;
  o.name = o.chosen = "given";
  o.pivots = o.perm = {0, 1};
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const VerifyTolerance t : {VerifyTolerance{.backward = inf}, VerifyTolerance{.factor = nan},
                                  VerifyTolerance{.per_condition = -1}})
    EXPECT_THROW(verify_against_cholmod(a, blocks, o, t), ArgumentError);
  EXPECT_TRUE(verify_against_cholmod(a, blocks, o, VerifyTolerance{.factor = 0}).ok);
}

TEST(Verify, NoAgreementOnAToleranceThatVerifiesNothing) {
  // cond = 2^1000 (finite, > 1 / eps) and cond = 2^1500 (estimate overflows).
  for (int e : {1000, 1500}) {
    const double big = std::ldexp(1.0, e / 2);
    const SymmetricCsc a = csc_from_triplets(2, std::vector<Triplet>{{0, 0, big}, {1, 1, 1 / big}});
    const BlockPattern blocks = BlockPattern::unit(a);
    const Verification v = verify_against_cholmod(a, blocks, compute_ordering(find_ordering("natural"), blocks, a));
    EXPECT_FALSE(v.ok) << "cond 2^" << e << ", tolerance " << v.factor_tolerance;
    EXPECT_FALSE(v.verifiable) << "cond 2^" << e;
  }
  const SymmetricCsc a = small_spd();
  const BlockPattern blocks = BlockPattern::unit(a);
  const Verification v = verify_against_cholmod(a, blocks, compute_ordering(find_ordering("meca"), blocks, a));
  EXPECT_TRUE(v.verifiable && v.ok);
}
}  // namespace
}  // namespace ldlpgs
