// The kernels of factor/kernels.h against dense Eigen, for every unrolled size 1..6 and the
// generic path (7, 12), through the same switch the numeric phase uses.
#include "ldlpgs/factor/kernels.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <bit>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace ldlpgs {
namespace {

#if defined(LDLPGS_KERNELS_AVX512)
// kernels_avx512_test.cpp: the same tests on the 8-lane kernels of the AVX-512 passes, all
// skipped on a CPU without AVX-512F.
static_assert(kernels::kLanes == 8);
class RequireAvx512 : public ::testing::Environment {
  void SetUp() override {
    if (!__builtin_cpu_supports("avx512f")) GTEST_SKIP() << "this CPU has no AVX-512F";
  }
};
const ::testing::Environment* const kRequireAvx512 = ::testing::AddGlobalTestEnvironment(new RequireAvx512);
#elif defined(LDLPGS_KERNELS_AVX2)
// kernels_avx2_test.cpp: the same tests on the 4-lane kernels the AVX2 passes run (passes.h),
// all skipped on a CPU without AVX2.
static_assert(kernels::kLanes == 4);
class RequireAvx2 : public ::testing::Environment {
  void SetUp() override {
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2";
  }
};
const ::testing::Environment* const kRequireAvx2 = ::testing::AddGlobalTestEnvironment(new RequireAvx2);
#else
static_assert(kernels::kLanes == 2);
#endif

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// A random SPD d x d matrix with condition number in the tens.
RowMatrix random_spd(int d, int seed) {
  std::srand(seed);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(d, d);
  return b * b.transpose() + d * Eigen::MatrixXd::Identity(d, d);
}

class Kernels : public ::testing::TestWithParam<int> {};

TEST_P(Kernels, LdlNodeReconstructsTheBlock) {
  const int d = GetParam();
  const RowMatrix n = random_spd(d, d);
  RowMatrix f = n;
  const std::vector<double> floor(d, 0.0);
  std::vector<double> inv_d(d);
  int bad = 0;
  kernels::dispatch_size(d, [&](auto size) { bad = kernels::ldl_node<decltype(size)::value>(f.data(), floor.data(), inv_d.data(), d); });
  ASSERT_EQ(bad, -1);
  for (int j = 0; j < d; ++j) EXPECT_DOUBLE_EQ(inv_d[j], 1.0 / f(j, j));
  Eigen::MatrixXd l = Eigen::MatrixXd::Identity(d, d);
  l.triangularView<Eigen::StrictlyLower>() = f.triangularView<Eigen::StrictlyLower>();
  const Eigen::MatrixXd dd = f.diagonal().asDiagonal();
  EXPECT_LT((l * dd * l.transpose() - Eigen::MatrixXd(n)).norm(), 1e-13 * n.norm());
}

TEST_P(Kernels, BeginAndEndLSolveAgainstTheNodeBlock) {
  const int d = GetParam(), h = 2 * d + 1;
  const RowMatrix n = random_spd(d, 100 + d);
  const RowMatrix e = RowMatrix::Random(h, d);
  RowMatrix f = n, l = e, w(h, d), y;
  const std::vector<double> floor(d, 0.0);
  std::vector<double> inv_d(d);
  kernels::dispatch_size(d, [&](auto size) {
    constexpr int N = decltype(size)::value;
    kernels::ldl_node<N>(f.data(), floor.data(), inv_d.data(), d);
    kernels::begin_l<N>(l.data(), w.data(), f.data(), inv_d.data(), h, d);
    y = l;
    kernels::end_l<N>(l.data(), f.data(), h, d);
  });
  const Eigen::MatrixXd ninv = Eigen::MatrixXd(n).inverse();
  const Eigen::MatrixXd expected = Eigen::MatrixXd(e) * ninv;
  EXPECT_LT((Eigen::MatrixXd(l) - expected).norm(), 1e-12 * expected.norm());
  // Y, what a column of more than one edge block keeps (numeric.h): the scalar L = E N^-1 L_kk.
  Eigen::MatrixXd lkk = Eigen::MatrixXd::Identity(d, d);
  lkk.triangularView<Eigen::StrictlyLower>() = f.triangularView<Eigen::StrictlyLower>();
  const Eigen::MatrixXd scalar_l = expected * lkk;
  EXPECT_LT((Eigen::MatrixXd(y) - scalar_l).norm(), 1e-12 * scalar_l.norm());
  // The reduction's operands: W Y^T = E N^-1 E^T = E L^T.
  const Eigen::MatrixXd product = Eigen::MatrixXd(e) * ninv * Eigen::MatrixXd(e).transpose();
  EXPECT_LT((Eigen::MatrixXd(w) * Eigen::MatrixXd(y).transpose() - product).norm(), 1e-12 * product.norm());
}

TEST_P(Kernels, ReduceRunsSubtractEachPanelProductAtItsTarget) {
  // Runs of db, 3 and 7 rows of E (from rows 2, 1 and 4) times L_b^T (db rows of L from row 2;
  // db = 1..7 covers every unrolled size of the second dispatch and the generic one) land at
  // offsets 0, 100, 200 with row stride ld: db, as in a target of one block, or db + 3, as in a
  // supernode whose other columns must stay untouched. The first run is block b's own rows
  // landing on the diagonal: only its lower triangle is written. scatter_runs, given the
  // product, must write the same.
  const int d = GetParam();
  for (int db = 1; db <= 7; ++db) {
    for (const int ld : {db, db + 3}) {
      const std::vector<int32_t> runs = {3, ld, 0, 2, db, 100, 1, 3, 200, 4, 7};
      const RowMatrix e = RowMatrix::Random(11, d), l = RowMatrix::Random(11, d);
      const RowMatrix product = e * l.middleRows(2, db).transpose();  // 11 x db
      std::vector<double> values(300, 1.0), scattered(300, 1.0);
      const int32_t* end = nullptr;
      kernels::dispatch_size(d, [&](auto size) {
        constexpr int N = decltype(size)::value;
        kernels::dispatch_size(db, [&](auto size_b) {
          end = kernels::reduce_runs<N, decltype(size_b)::value>(values.data(), e.data(), l.data() + 2 * d, runs.data(), d, db);
        });
      });
      EXPECT_EQ(end, runs.data() + runs.size());
      EXPECT_EQ(kernels::scatter_runs(scattered.data(), product.data(), runs.data(), db, db), runs.data() + runs.size());
      for (size_t run = 0; run < 3; ++run) {
        const int target = runs[2 + 3 * run], row = runs[3 + 3 * run], rows = runs[4 + 3 * run];
        for (int r = 0; r < rows; ++r)
          for (int c = 0; c < ld; ++c) {
            const double expected = c >= db || (run == 0 && c > r) ? 1.0 : 1.0 - product(row + r, c);
            EXPECT_NEAR(values[target + r * ld + c], expected, 1e-14) << run;
            EXPECT_NEAR(scattered[target + r * ld + c], expected, 1e-14) << run;
          }
        EXPECT_EQ(values[target + rows * ld], 1.0);  // nothing beyond the run
      }
    }
  }
}

TEST_P(Kernels, ARunThatWritesFirstStoresWhatSubtractingFromZerosGives) {
  // Runs of db and 7 rows, the second one's rows negated: it writes its target first, so it must
  // store there, bit for bit, what the same run subtracts from zeros, whatever the target held
  // (NaN here); the first run subtracts as always. reduce_runs and scatter_runs alike.
  const int d = GetParam();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int db = 1; db <= 7; ++db) {
    const int ld = db + 3;
    const std::vector<int32_t> subtracting = {2, ld, 0, 2, db, 100, 4, 7}, storing = {2, ld, 0, 2, db, 100, 4, -7};
    const RowMatrix e = RowMatrix::Random(11, d), l = RowMatrix::Random(11, d);
    const RowMatrix product = e * l.middleRows(2, db).transpose();  // 11 x db
    std::vector<double> zeros(200, 1.0), stored(200, 1.0), scattered_zeros(200, 1.0), scattered(200, 1.0);
    for (int r = 0; r < 7; ++r)
      for (int c = 0; c < db; ++c) {
        zeros[100 + r * ld + c] = scattered_zeros[100 + r * ld + c] = 0.0;
        stored[100 + r * ld + c] = scattered[100 + r * ld + c] = nan;
      }
    kernels::dispatch_size(d, [&](auto size) {
      constexpr int N = decltype(size)::value;
      kernels::dispatch_size(db, [&](auto size_b) {
        constexpr int DB = decltype(size_b)::value;
        kernels::reduce_runs<N, DB>(zeros.data(), e.data(), l.data() + 2 * d, subtracting.data(), d, db);
        const int32_t* end = kernels::reduce_runs<N, DB>(stored.data(), e.data(), l.data() + 2 * d, storing.data(), d, db);
        EXPECT_EQ(end, storing.data() + storing.size());
      });
    });
    kernels::scatter_runs(scattered_zeros.data(), product.data(), subtracting.data(), db, db);
    EXPECT_EQ(kernels::scatter_runs(scattered.data(), product.data(), storing.data(), db, db),
              storing.data() + storing.size());
    for (size_t q = 0; q < zeros.size(); ++q) {
      EXPECT_EQ(std::bit_cast<uint64_t>(stored[q]), std::bit_cast<uint64_t>(zeros[q])) << "db " << db << " value " << q;
      EXPECT_EQ(std::bit_cast<uint64_t>(scattered[q]), std::bit_cast<uint64_t>(scattered_zeros[q])) << "db " << db << " value " << q;
    }
  }
}

TEST_P(Kernels, ZeroAndNonFinitePivotsStopTheBlock) {
  const int d = GetParam();
  RowMatrix n = random_spd(d, 7);
  // Row and column d-1 a copy of row 0: the last pivot is zero up to rounding.
  if (d > 1) {
    n.row(d - 1) = n.row(0);
    n.col(d - 1) = n.col(0);
  } else {
    n(0, 0) = 0;
  }
  const std::vector<double> floor(d, 1e-12 * n.diagonal().cwiseAbs().maxCoeff());
  std::vector<double> inv_d(d);
  RowMatrix f = n;
  int bad = 0;
  kernels::dispatch_size(d, [&](auto size) { bad = kernels::ldl_node<decltype(size)::value>(f.data(), floor.data(), inv_d.data(), d); });
  EXPECT_EQ(bad, d - 1);
  f = n;
  f(0, 0) = std::numeric_limits<double>::quiet_NaN();
  kernels::dispatch_size(d, [&](auto size) { bad = kernels::ldl_node<decltype(size)::value>(f.data(), floor.data(), inv_d.data(), d); });
  EXPECT_EQ(bad, 0);
}

TEST_P(Kernels, ColumnSubstitutionsMatchDenseProducts) {
  const int d = GetParam(), h = 5;  // odd: the two-row kernels' pairs and their last row alone
  const RowMatrix l = RowMatrix::Random(h, d);
  const std::vector<int> rows = {d, d + 2, d + 3, d + 5, d + 6};  // rows of y below the pivot's d rows
  Eigen::VectorXd y = Eigen::VectorXd::Random(d + 7), y0 = y;
  kernels::dispatch_size(d, [&](auto size) {
    kernels::forward_column<decltype(size)::value>(y.data(), y.data(), l.data(), rows.data(), h, d);
  });
  for (int r = 0; r < h; ++r) EXPECT_NEAR(y(rows[r]), y0(rows[r]) - l.row(r).dot(y0.head(d)), 1e-14);
  y0 = y;
  kernels::dispatch_size(d, [&](auto size) {
    kernels::backward_column<decltype(size)::value>(y.data(), y.data(), l.data(), rows.data(), h, d);
  });
  Eigen::VectorXd yr(h);
  for (int r = 0; r < h; ++r) yr(r) = y0(rows[r]);
  const Eigen::VectorXd expected = y0.head(d) - Eigen::MatrixXd(l).transpose() * yr;
  EXPECT_LT((y.head(d) - expected).norm(), 1e-14 * (1 + expected.norm()));
}

INSTANTIATE_TEST_SUITE_P(Sizes, Kernels, ::testing::Values(1, 2, 3, 4, 5, 6, 7, 12));

// The kernels work on two rows per instruction (kernels.h, V2) and claim the values of the
// row-by-row scalar loops bit for bit. The reference: those loops, written out here in the
// order the kernels document (products left operand first, sums from 0 with k ascending).
double scalar_dot(const double* x, const double* y, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += x[k] * y[k];
  return s;
}
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(KernelsPairs, MatchTheScalarLoopsBitForBit) {
  for (int d = 1; d <= 6; ++d)
    for (int db = 1; db <= 6; ++db)
      for (int h = db; h <= db + 5; ++h) {  // odd and even row counts
        SCOPED_TRACE("pivot " + std::to_string(d) + ", block " + std::to_string(db) + ", rows " + std::to_string(h));
        const RowMatrix n = random_spd(d, 7 * d + db);
        const RowMatrix e0 = RowMatrix::Random(h, d);
        const std::vector<double> floor(d, 0.0);
        std::vector<double> node(n.data(), n.data() + d * d), inv_d(d);
        kernels::dispatch_size(d, [&](auto size) { kernels::ldl_node<decltype(size)::value>(node.data(), floor.data(), inv_d.data(), d); });
        // Scalar begin_l: w = L_kk^-1 e, y = w D^-1, row by row.
        std::vector<double> y_ref(e0.data(), e0.data() + h * d), w_ref(h * d);
        for (int r = 0; r < h; ++r) {
          double* x = y_ref.data() + r * d;
          for (int i = 1; i < d; ++i)
            for (int k = 0; k < i; ++k) x[i] -= node[i * d + k] * x[k];
          for (int c = 0; c < d; ++c) {
            w_ref[r * d + c] = x[c];
            x[c] *= inv_d[c];
          }
        }
        // Scalar reduction of block b = rows [0, db) of Y into a target of stride ld: the
        // diagonal's lower triangle, then db columns of the rows below; the rest untouched.
        const int ld = db + 2;
        const RowMatrix t0 = RowMatrix::Random(h, ld);
        std::vector<double> t_ref(t0.data(), t0.data() + h * ld);
        for (int r = 0; r < h; ++r)
          for (int c = 0; c < (r < db ? r + 1 : db); ++c)
            t_ref[r * ld + c] -= scalar_dot(w_ref.data() + r * d, y_ref.data() + c * d, d);
        // Scalar end_l, and the solve's column substitutions through the finished L.
        std::vector<double> l_ref = y_ref;
        for (int r = 0; r < h; ++r) {
          double* x = l_ref.data() + r * d;
          for (int i = d - 2; i >= 0; --i)
            for (int k = i + 1; k < d; ++k) x[i] -= node[k * d + i] * x[k];
        }
        std::vector<int> rows(h);
        for (int r = 0; r < h; ++r) rows[r] = d + 2 * r;  // below the pivot's d rows, with gaps
        const Eigen::VectorXd z0 = Eigen::VectorXd::Random(d + 2 * h);
        std::vector<double> z_ref(z0.data(), z0.data() + z0.size());
        for (int r = 0; r < h; ++r) z_ref[rows[r]] -= scalar_dot(l_ref.data() + r * d, z_ref.data(), d);
        std::vector<double> zb_ref = z_ref;
        for (int r = 0; r < h; ++r)
          for (int c = 0; c < d; ++c) zb_ref[c] -= l_ref[r * d + c] * zb_ref[rows[r]];

        std::vector<double> y(e0.data(), e0.data() + h * d), w(h * d), t(t0.data(), t0.data() + h * ld), tm = t;
        std::vector<double> z(z0.data(), z0.data() + z0.size());
        std::vector<int32_t> map(d + 2 * h);
        for (int r = 0; r < h; ++r) map[rows[r]] = r * ld;  // target row r of the mapped form
        const std::vector<int32_t> runs = {1, ld, 0, 0, h};
        kernels::dispatch_size(d, [&](auto size) {
          constexpr int N = decltype(size)::value;
          kernels::begin_l<N>(y.data(), w.data(), node.data(), inv_d.data(), h, d);
          EXPECT_TRUE(same_bits(w, w_ref));
          EXPECT_TRUE(same_bits(y, y_ref));
          kernels::dispatch_size(db, [&](auto size_b) {
            constexpr int DB = decltype(size_b)::value;
            kernels::reduce_runs<N, DB>(t.data(), w.data(), y.data(), runs.data(), d, db);
            kernels::reduce_mapped<N, DB>(tm.data(), w.data(), y.data(), rows.data(), map.data(), 0, h, 0, d, db);
          });
          EXPECT_TRUE(same_bits(t, t_ref));
          EXPECT_TRUE(same_bits(tm, t_ref));
          kernels::end_l<N>(y.data(), node.data(), h, d);
          EXPECT_TRUE(same_bits(y, l_ref));
          kernels::forward_column<N>(z.data(), z.data(), y.data(), rows.data(), h, d);
          EXPECT_TRUE(same_bits(z, z_ref));
          kernels::backward_column<N>(z.data(), z.data(), y.data(), rows.data(), h, d);
          EXPECT_TRUE(same_bits(z, zb_ref));
        });
        if (h == db) {  // one edge block landing on the diagonal: the fused column of a chain
          std::vector<double> node_f(n.data(), n.data() + d * d), e(e0.data(), e0.data() + h * d),
              tf(t0.data(), t0.data() + h * ld), inv_f(d);
          ASSERT_EQ(kernels::kSingle[6 * (d - 1) + db - 1](node_f.data(), e.data(), tf.data(), ld, floor.data(), inv_f.data()), -1);
          EXPECT_TRUE(same_bits(node_f, node));
          EXPECT_TRUE(same_bits(e, l_ref));
          EXPECT_TRUE(same_bits(tf, t_ref));
        }
      }
}

// The fused column of one edge block (a chain's pivot), for every pair of sizes: against dense
// Eigen (L = E N^-1, target -= E N^-1 E^T on its lower triangle), and value for value against
// the general path it replaces (ldl_node, begin_l, reduce_runs, end_l).
TEST(KernelsSingle, FusedColumnMatchesDenseAndTheGeneralPath) {
  for (int d = 1; d <= 6; ++d)
    for (int db = 1; db <= 6; ++db) {
      SCOPED_TRACE("pivot " + std::to_string(d) + ", neighbour " + std::to_string(db));
      const RowMatrix n = random_spd(d, 10 * d + db), e0 = RowMatrix::Random(db, d);
      const int ld = db + 2;  // the target's row stride (a wider target supernode)
      const RowMatrix target0 = RowMatrix::Random(db, ld);
      const std::vector<double> floor(d, 0.0);
      RowMatrix node = n, e = e0, target = target0;
      std::vector<double> inv_d(d);
      ASSERT_EQ(kernels::kSingle[6 * (d - 1) + db - 1](node.data(), e.data(), target.data(), ld, floor.data(), inv_d.data()), -1);
      RowMatrix node_g = n, e_g = e0, target_g = target0;
      std::vector<double> inv_g(d), w(db * d);
      const std::vector<int32_t> runs = {1, ld, 0, 0, db};
      kernels::dispatch_size(d, [&](auto size) {
        constexpr int N = decltype(size)::value;
        ASSERT_EQ(kernels::ldl_node<N>(node_g.data(), floor.data(), inv_g.data(), d), -1);
        kernels::begin_l<N>(e_g.data(), w.data(), node_g.data(), inv_g.data(), db, d);
        kernels::dispatch_size(db, [&](auto size_b) {
          kernels::reduce_runs<N, decltype(size_b)::value>(target_g.data(), w.data(), e_g.data(), runs.data(), d, db);
        });
        kernels::end_l<N>(e_g.data(), node_g.data(), db, d);
      });
      EXPECT_EQ(node, node_g);
      EXPECT_EQ(e, e_g);
      EXPECT_EQ(target, target_g);
      EXPECT_EQ(inv_d, inv_g);
      const Eigen::MatrixXd l = Eigen::MatrixXd(e0) * Eigen::MatrixXd(n).inverse();
      EXPECT_LT((Eigen::MatrixXd(e) - l).norm(), 1e-13 * (1 + l.norm()));
      const Eigen::MatrixXd schur = Eigen::MatrixXd(target0.leftCols(db)) - l * Eigen::MatrixXd(e0).transpose();
      for (int r = 0; r < db; ++r) {
        for (int c = 0; c <= r; ++c) EXPECT_NEAR(target(r, c), schur(r, c), 1e-13 * (1 + schur.norm()));
        for (int c = r + 1; c < ld; ++c) EXPECT_EQ(target(r, c), target0(r, c));  // upper and beyond: untouched
      }
    }
}

TEST(KernelsSingle, FusedColumnStopsAtAZeroPivot) {
  RowMatrix node = random_spd(4, 3), e = RowMatrix::Random(3, 4), target = RowMatrix::Zero(3, 3);
  node.row(2).setZero();
  node.col(2).setZero();
  const std::vector<double> floor(4, 1e-12);
  std::vector<double> inv_d(4);
  EXPECT_EQ(kernels::kSingle[6 * 3 + 2](node.data(), e.data(), target.data(), 3, floor.data(), inv_d.data()), 2);
  EXPECT_EQ(target, RowMatrix::Zero(3, 3));  // nothing reduced past the bad pivot
}

}  // namespace
}  // namespace ldlpgs
