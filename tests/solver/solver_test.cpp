// solver/ against dense references: the exact solve of (H + eps diag H) lambda = R with
// H = J W J^T built densely from the same J and W, and, with inequality rows, the mixed LCP
// solved by enumerating active sets.
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/solver/lanes_sweep.h"
#include "ldlpgs/solver/row_cache.h"
#include "ldlpgs/solver/solver.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace ldlpgs {
namespace {

struct Dense {
  Eigen::MatrixXd j, w;  // J (rows x 6 columns), W (block diagonal)
};

// A chain-like random system: block k couples columns k mod c and (k+1) mod c (or a static
// -1 for every 4th), W = blockdiag(I/m, R diag(1/I) R^T); `coupled`: each W a random symmetric
// positive definite 6x6 instead (nonzero coupling blocks: the general path of the row cache).
System random_system(int num_columns, std::span<const int> sizes, const std::vector<bool>& bounded, uint32_t seed,
                     double compliance = 0, bool coupled = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), pos(0.5, 2);
  System s;
  s.num_columns = num_columns;
  s.inverse_mass.assign(36 * num_columns, 0.0);
  for (int c = 0; c < num_columns; ++c) {
    const Eigen::Matrix3d r = Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    const Eigen::Matrix3d inv_i = r * Eigen::Vector3d(pos(rng), pos(rng), pos(rng)).asDiagonal() * r.transpose();
    const double inv_m = pos(rng);
    double* w = s.inverse_mass.data() + 36 * c;
    for (int i = 0; i < 3; ++i) {
      w[6 * i + i] = inv_m;
      for (int j = 0; j < 3; ++j) w[6 * (3 + i) + 3 + j] = inv_i(i, j);
    }
    if (coupled) {
      Eigen::Matrix<double, 6, 6> a;
      for (int i = 0; i < 36; ++i) a(i / 6, i % 6) = u(rng);
      const Eigen::Matrix<double, 6, 6> spd = a * a.transpose() + Eigen::Matrix<double, 6, 6>::Identity();
      for (int i = 0; i < 36; ++i) w[i] = spd(i / 6, i % 6);
    }
  }
  for (size_t k = 0; k < sizes.size(); ++k) {
    const int a = static_cast<int>(k) % num_columns;
    const int b = k % 4 == 3 ? -1 : (a + 1) % num_columns;
    const int blk = s.add_block(sizes[k], a, b);
    for (int x = 0; x < 12 * sizes[k]; ++x) s.cell_a(blk)[x] = u(rng);
    if (bounded[k]) s.set_bounds(blk, 0, kUnbounded);
  }
  for (double& r : s.rhs) r = u(rng);
  s.set_compliance(compliance);
  return s;
}

Dense dense(const System& s) {
  Dense d{Eigen::MatrixXd::Zero(s.num_rows, 6 * s.num_columns), Eigen::MatrixXd::Zero(6 * s.num_columns, 6 * s.num_columns)};
  for (int k = 0; k < static_cast<int>(s.blocks.size()); ++k) {
    const RowBlock& b = s.blocks[k];
    for (int r = 0; r < b.size; ++r)
      for (int c = 0; c < 6; ++c) {
        if (b.column_a >= 0) d.j(b.position + r, 6 * b.column_a + c) += s.cell_a(k)[6 * r + c];
        if (b.column_b >= 0) d.j(b.position + r, 6 * b.column_b + c) += s.cell_b(k)[6 * r + c];
      }
  }
  for (int c = 0; c < s.num_columns; ++c)
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) d.w(6 * c + i, 6 * c + j) = s.inverse_mass[36 * c + 6 * i + j];
  return d;
}

Eigen::MatrixXd regularized_h(const System& s) {
  const Dense d = dense(s);
  Eigen::MatrixXd h = d.j * d.w * d.j.transpose();
  for (int i = 0; i < s.num_rows; ++i) h(i, i) *= 1 + s.compliance[i];
  return h;
}

// The mixed LCP: equality rows free, bounded rows lambda >= 0, w = H lambda - R >= 0,
// lambda . w = 0, by trying every active set of the bounded rows.
Eigen::VectorXd lcp_by_enumeration(const System& s) {
  const Eigen::MatrixXd h = regularized_h(s);
  const Eigen::Map<const Eigen::VectorXd> rhs(s.rhs.data(), s.num_rows);
  std::vector<int> bounded;
  for (int i = 0; i < s.num_rows; ++i)
    if (s.lower[i] == 0) bounded.push_back(i);
  for (int mask = 0; mask < (1 << bounded.size()); ++mask) {  // bit set: row at its bound (lambda = 0)
    std::vector<int> free;
    std::vector<bool> zero(s.num_rows, false);
    for (size_t t = 0; t < bounded.size(); ++t)
      if (mask >> t & 1) zero[bounded[t]] = true;
    for (int i = 0; i < s.num_rows; ++i)
      if (!zero[i]) free.push_back(i);
    Eigen::MatrixXd hf(free.size(), free.size());
    Eigen::VectorXd rf(free.size());
    for (size_t p = 0; p < free.size(); ++p) {
      rf(p) = rhs(free[p]);
      for (size_t q = 0; q < free.size(); ++q) hf(p, q) = h(free[p], free[q]);
    }
    const Eigen::VectorXd lf = hf.ldlt().solve(rf);
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.num_rows);
    for (size_t p = 0; p < free.size(); ++p) lambda(free[p]) = lf(p);
    const Eigen::VectorXd w = h * lambda - rhs;
    bool ok = true;
    for (int i : bounded) ok = ok && lambda(i) >= -1e-12 && w(i) >= -1e-12;
    if (ok) return lambda;
  }
  ADD_FAILURE() << "no active set solves the LCP";
  return {};
}

struct Outcome {
  std::vector<double> lambda, dv;
  SolveResult result;
};

Outcome run(const System& s, SolverKind kind, int iterations, std::vector<double> warm = {},
            HybridSchedule schedule = HybridSchedule::talk) {
  Solver solver(s, {.kind = kind, .iterations = iterations, .schedule = schedule});
  Outcome r{warm.empty() ? std::vector<double>(s.num_rows, 0.0) : warm, std::vector<double>(6 * s.num_columns, 0.0), {}};
  r.result = solver.solve(s, r.lambda, r.dv);
  return r;
}

double max_diff(std::span<const double> a, const Eigen::VectorXd& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b(i)));
  return m / std::max(1.0, b.cwiseAbs().maxCoeff());
}

const std::vector<int> kSizes = {3, 5, 6, 4, 1, 3, 5, 2, 6, 3, 1, 5};
const std::vector<bool> kAllEquality(kSizes.size(), false);

TEST(Solver, DirectMatchesDenseSolve) {
  for (const auto& [eps, coupled] : {std::pair{0.0, false}, std::pair{1e-6, false}, std::pair{0.0, true}}) {
    const System s = random_system(13, kSizes, kAllEquality, 7, eps, coupled);
    const Eigen::VectorXd expected = regularized_h(s).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(s.rhs.data(), s.num_rows));
    const Outcome r = run(s, SolverKind::direct, 1);
    ASSERT_TRUE(r.result.ok()) << r.result.factor.message();
    EXPECT_LT(max_diff(r.lambda, expected), 1e-10) << "eps " << eps << (coupled ? ", coupled W" : "");
    // dV = W J^T lambda, the impulses' velocity change
    const Dense d = dense(s);
    const Eigen::VectorXd dv = d.w * d.j.transpose() * Eigen::Map<const Eigen::VectorXd>(r.lambda.data(), s.num_rows);
    EXPECT_LT(max_diff(r.dv, dv), 1e-10);
    if (eps == 0) {
      EXPECT_LT(velocity_residual(s, r.lambda, r.dv), 1e-10);
    }
  }
}

TEST(Solver, LdlPgsWithOneIterationIsTheExactSolveOnEqualities) {
  const System s = random_system(13, kSizes, kAllEquality, 8);
  const Eigen::VectorXd expected = regularized_h(s).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(s.rhs.data(), s.num_rows));
  for (const char* ordering : {"natural", "mda", "meca", "amd", "metis"}) {
    Solver solver(s, {.kind = SolverKind::ldl_pgs, .iterations = 1, .ordering = ordering});
    std::vector<double> lambda(s.num_rows, 0.3), dv(6 * s.num_columns);  // any warm start
    ASSERT_TRUE(solver.solve(s, lambda, dv).ok());
    EXPECT_LT(max_diff(lambda, expected), 1e-10) << ordering;
  }
}

TEST(Solver, IterativeSolversConvergeToTheExactSolve) {
  // Well conditioned: one block per column pair, a tree, so PGS converges at a visible rate.
  const std::vector<int> sizes = {3, 3, 3, 3, 3};
  for (bool coupled : {false, true}) {
    const System s = random_system(6, sizes, std::vector<bool>(sizes.size(), false), 9, 0.0, coupled);
    const Eigen::VectorXd expected = regularized_h(s).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(s.rhs.data(), s.num_rows));
    for (SolverKind kind : {SolverKind::pgs, SolverKind::block_gs}) {
      const double few = max_diff(run(s, kind, 5).lambda, expected);
      const double many = max_diff(run(s, kind, 3000).lambda, expected);
      EXPECT_LT(many, 1e-8) << to_string(kind) << (coupled ? ", coupled W" : "");
      EXPECT_LT(many, few) << to_string(kind);
    }
  }
}

// A mixed LCP small enough to enumerate: 7 blocks on 6 columns, every other one a bounded row.
System lcp_system(uint32_t seed) {
  const std::vector<int> sizes = {3, 1, 5, 1, 3, 1, 4};
  const std::vector<bool> bounded = {false, true, false, true, false, true, false};
  return random_system(6, sizes, bounded, seed, 1e-3);
}

TEST(Solver, InequalitiesMatchTheLcpByEnumeration) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const System s = lcp_system(seed);
    const Eigen::VectorXd expected = lcp_by_enumeration(s);
    for (SolverKind kind : {SolverKind::pgs, SolverKind::block_gs, SolverKind::ldl_pgs}) {
      const Outcome r = run(s, kind, 4000);
      ASSERT_TRUE(r.result.ok());
      EXPECT_LT(max_diff(r.lambda, expected), 1e-7) << to_string(kind) << " seed " << seed;
      for (int i = 0; i < s.num_rows; ++i) EXPECT_GE(r.lambda[i], s.lower[i]);
    }
  }
}

// The schur schedule: the equality rows eliminated, PGS on the inequality rows' dense Schur
// complement, which reaches the same LCP's solution in far fewer sweeps than block-gs's iterations.
TEST(Solver, SchurScheduleMatchesTheLcpByEnumeration) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const System s = lcp_system(seed);
    const Eigen::VectorXd expected = lcp_by_enumeration(s);
    const Outcome r = run(s, SolverKind::ldl_pgs, 400, {}, HybridSchedule::schur);
    ASSERT_TRUE(r.result.ok());
    EXPECT_LT(max_diff(r.lambda, expected), 1e-9) << "seed " << seed;
    for (int i = 0; i < s.num_rows; ++i) EXPECT_GE(r.lambda[i], s.lower[i]);
    // dV = W J^T lambda
    const Dense d = dense(s);
    const Eigen::VectorXd dv = d.w * d.j.transpose() * Eigen::Map<const Eigen::VectorXd>(r.lambda.data(), s.num_rows);
    EXPECT_LT(max_diff(r.dv, dv), 1e-12) << "seed " << seed;
  }
}

// Two systems side by side, sharing no column, their blocks interleaved (x's first, then y's,
// alternately): two islands whose rows are not in island order.
System side_by_side(const System& x, const System& y) {
  System s;
  s.num_columns = x.num_columns + y.num_columns;
  s.inverse_mass = x.inverse_mass;
  s.inverse_mass.insert(s.inverse_mass.end(), y.inverse_mass.begin(), y.inverse_mass.end());
  const auto copy = [&](const System& from, int k, int shift) {
    const RowBlock& b = from.blocks[k];
    const int blk = s.add_block(b.size, b.column_a < 0 ? -1 : b.column_a + shift, b.column_b < 0 ? -1 : b.column_b + shift);
    std::copy(from.cell_a(k), from.cell_a(k) + 12 * b.size, s.cell_a(blk));
    if (!b.equality) s.set_bounds(blk, from.lower[b.position], from.upper[b.position]);
    for (int r = 0; r < b.size; ++r) s.rhs[s.blocks[blk].position + r] = from.rhs[b.position + r];
  };
  for (size_t k = 0; k < std::max(x.blocks.size(), y.blocks.size()); ++k) {
    if (k < x.blocks.size()) copy(x, static_cast<int>(k), 0);
    if (k < y.blocks.size()) copy(y, static_cast<int>(k), x.num_columns);
  }
  s.set_compliance(x.compliance.empty() ? 0 : x.compliance[0]);
  return s;
}

// The schur schedule on two islands (its S is kept island by island): the same LCP's solution,
// by enumeration over both.
TEST(Solver, SchurScheduleSolvesIslandsApart) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const System s = side_by_side(lcp_system(seed), lcp_system(seed + 10));
    const Eigen::VectorXd expected = lcp_by_enumeration(s);
    const Outcome r = run(s, SolverKind::ldl_pgs, 400, {}, HybridSchedule::schur);
    ASSERT_TRUE(r.result.ok());
    EXPECT_LT(max_diff(r.lambda, expected), 1e-9) << "seed " << seed;
  }
}

// Bounded rows in the LDL block (RowBlock::factored: contacts in the factor), exactly and with
// the proximal regularization, which must not move the solution: the same LCP.
TEST(Solver, FactoredInequalityRowsMatchTheLcpByEnumeration) {
  for (double regularization : {0.0, 1e-3})
    for (uint32_t seed = 1; seed <= 5; ++seed) {
      System s = lcp_system(seed);
      for (RowBlock& b : s.blocks)
        if (!b.equality) {
          b.factored = true;
          b.regularization = regularization;
        }
      const Eigen::VectorXd expected = lcp_by_enumeration(s);
      for (HybridSchedule schedule : {HybridSchedule::talk, HybridSchedule::block_gs, HybridSchedule::schur}) {
        Solver solver(s, {.kind = SolverKind::ldl_pgs, .iterations = 400, .schedule = schedule});
        std::vector<double> lambda(s.num_rows, 0.0), dv(6 * s.num_columns, 0.0);
        ASSERT_TRUE(solver.solve(s, lambda, dv).ok());
        EXPECT_LT(max_diff(lambda, expected), 1e-7) << to_string(schedule) << " seed " << seed << " r " << regularization;
        for (int i = 0; i < s.num_rows; ++i) EXPECT_GE(lambda[i], s.lower[i]);
      }
    }
}

// block-gs told to stop once dV stops changing (resolve's tolerance) ends at the LCP's solution,
// having stopped before its iterations reach their fixed point.
TEST(Solver, BlockGsStopsOnceTheCorrectionStopsChanging) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const System s = lcp_system(seed);
    const Eigen::VectorXd expected = lcp_by_enumeration(s);
    Solver solver(s, {.kind = SolverKind::ldl_pgs, .iterations = 1});
    std::vector<double> lambda(s.num_rows, 0.0), dv(6 * s.num_columns, 0.0);
    ASSERT_TRUE(solver.factorize(s).ok());
    ASSERT_TRUE(solver.resolve(s, lambda, dv, 4000, HybridSchedule::block_gs, 1e-13).ok());
    EXPECT_LT(max_diff(lambda, expected), 1e-7) << "seed " << seed;
    // The iteration count it stopped at: the first count that gives the same impulses.
    int stopped = 1;
    for (; stopped < 4000; ++stopped) {
      std::vector<double> l(s.num_rows, 0.0), d(dv.size(), 0.0);
      solver.resolve(s, l, d, stopped, HybridSchedule::block_gs);
      if (l == lambda) break;
    }
    std::vector<double> all(s.num_rows, 0.0), d(dv.size(), 0.0);
    solver.resolve(s, all, d, 4000, HybridSchedule::block_gs);
    EXPECT_NE(all, lambda) << "seed " << seed << ": it ran to the fixed point";
    EXPECT_LT(stopped, 4000) << "seed " << seed;
  }
}

// A new set of factored blocks runs the symbolic phase again; a set seen before reuses its own.
TEST(Solver, FactoredSetsReuseTheirSymbolicPhase) {
  const std::vector<int> sizes = {3, 1, 5, 1, 3};
  const std::vector<bool> bounded = {false, true, false, true, false};
  System s = random_system(5, sizes, bounded, 3, 1e-3);
  Solver solver(s, {.kind = SolverKind::ldl_pgs, .iterations = 10});
  std::vector<double> lambda(s.num_rows, 0.0), dv(6 * s.num_columns, 0.0);
  const auto solve_with = [&](bool first, bool second) {
    s.blocks[1].factored = first;
    s.blocks[3].factored = second;
    EXPECT_TRUE(solver.solve(s, lambda, dv).ok());
    return solver.symbolic_stats().analyses;
  };
  EXPECT_EQ(solver.symbolic_stats().analyses, 1);  // the constructor's: equalities only
  EXPECT_EQ(solve_with(false, false), 1);
  EXPECT_EQ(solve_with(true, false), 2);
  EXPECT_EQ(solve_with(true, true), 3);
  EXPECT_EQ(solve_with(true, false), 3);
  EXPECT_EQ(solve_with(false, false), 3);
  EXPECT_EQ(solver.symbolic()->num_rows(), 11);  // the equality blocks. own again (3 + 5 + 3 rows)
}

// A friction block on a disk of radius mu lambda_n (the normal impulse held at 2 by its bounds):
// the solvers' impulse is the minimizer of (1/2) x^T K x - x^T r over the disk. Where the
// unconstrained minimizer lies outside, the reference is the rim point of the KKT conditions,
// (K + nu I) x = r with |x| = radius, nu >= 0 found by bisection on the monotone |x(nu)| (the
// solver uses Newton's method on the secular equation in K's eigenbasis), checked against a scan
// of the rim's angle.
TEST(Solver, FrictionOnTheDiskIsTheConstrainedMinimizer) {
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    System s = random_system(2, std::vector<int>{1, 2}, {false, false}, seed);
    s.set_bounds(0, 2, 2);
    const double mu = 0.05 * seed;
    s.set_friction(1, 0, mu);
    const Eigen::MatrixXd h = regularized_h(s);
    const Eigen::Matrix2d k = h.block(1, 1, 2, 2);
    const Eigen::Vector2d r = Eigen::Vector2d(s.rhs[1], s.rhs[2]) - h.block(1, 0, 2, 1) * 2.0;
    const double radius = 2 * mu;
    Eigen::Vector2d expected = k.ldlt().solve(r);
    if (expected.norm() > radius) {
      const auto x_of = [&](double nu) { return (k + nu * Eigen::Matrix2d::Identity()).ldlt().solve(r).eval(); };
      double low = 0, high = 1;
      while (x_of(high).norm() > radius) high *= 2;
      for (int i = 0; i < 200; ++i) (x_of(0.5 * (low + high)).norm() > radius ? low : high) = 0.5 * (low + high);
      expected = x_of(high);
      const auto energy = [&](double theta) {
        const Eigen::Vector2d x = radius * Eigen::Vector2d(std::cos(theta), std::sin(theta));
        return 0.5 * x.dot(k * x) - x.dot(r);
      };
      const double at = std::atan2(expected.y(), expected.x());
      for (int i = 0; i < 3600; ++i) ASSERT_GE(energy(2 * M_PI * i / 3600), energy(at) - 1e-15);  // the rim's minimum
    }
    for (SolverKind kind : {SolverKind::pgs, SolverKind::block_gs, SolverKind::ldl_pgs})
      for (HybridSchedule schedule : {HybridSchedule::talk, HybridSchedule::schur}) {
        if (kind != SolverKind::ldl_pgs && schedule != HybridSchedule::talk) continue;
        const Outcome o = run(s, kind, 50, {}, schedule);
        EXPECT_NEAR(o.lambda[0], 2, 1e-15);
        EXPECT_LT(std::hypot(o.lambda[1] - expected(0), o.lambda[2] - expected(1)), 1e-9 * std::max(1.0, radius))
            << to_string(kind) << " " << to_string(schedule) << " seed " << seed
            << (expected.norm() < radius * (1 - 1e-9) ? " (inside)" : " (on the rim)");
      }
  }
}

// disk_minimizer on K of every orientation of its eigenvectors (k11 above, equal to and below
// k22; k12 negative, zero and positive) with the minimizer inside and outside the disk, against
// the KKT point (K + nu I) x = -b, |x| = r, nu found by bisection on the monotone |x(nu)|.
TEST(Solver, DiskMinimizerIsTheKktPointForEveryOrientationOfK) {
  for (double k11 : {0.5, 2.0, 3.0})
    for (double k12 : {-0.7, 0.0, 0.7})
      for (double radius : {0.05, 10.0}) {
        const double k22 = 2;
        const Eigen::Matrix2d k{{k11, k12}, {k12, k22}};
        const double b[2] = {1.0, -0.4};
        const auto x_of = [&](double nu) {
          return (k + nu * Eigen::Matrix2d::Identity()).ldlt().solve(-Eigen::Vector2d(b[0], b[1])).eval();
        };
        Eigen::Vector2d expected = x_of(0);
        if (expected.norm() > radius) {
          double low = 0, high = 1;
          while (x_of(high).norm() > radius) high *= 2;
          for (int i = 0; i < 200; ++i) (x_of(0.5 * (low + high)).norm() > radius ? low : high) = 0.5 * (low + high);
          expected = x_of(high);
        }
        double x[2];
        disk_minimizer(k11, k12, k22, b, radius, x);
        EXPECT_LT(std::hypot(x[0] - expected(0), x[1] - expected(1)), 1e-12 * std::max(1.0, expected.norm()))
            << "k11 " << k11 << " k12 " << k12 << " radius " << radius;
      }
}

// Contact points in manifolds of 1-5 points on random pairs of 14 columns (a quarter against a
// static body), among joint blocks, pyramid-friction points and a factored point (swept row by
// row), with normal impulses at zero, inside and on the rim of their disks: three sweeps in lanes
// give what pgs_block gives row by row in the order the lanes take (sweep_order), and the
// baseline's lanes what the AVX2 ones give, bit for bit. The colouring leaves no column twice in
// a group.
TEST(Solver, ContactLanesSweepAsTheRowsOneByOneInTheirOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const int columns = 14;
  System s = random_system(columns, std::vector<int>{3, 5, 2}, {false, false, false}, 3);
  for (int m = 0; m < 60; ++m) {
    const int a = static_cast<int>(rng() % columns), b = rng() % 4 == 0 ? -1 : (a + 1 + static_cast<int>(rng() % (columns - 1))) % columns;
    const int points = 1 + static_cast<int>(rng() % 5);
    const bool pyramid = m % 11 == 5, factored = m % 17 == 3;
    for (int p = 0; p < points; ++p) {
      const int normal = s.add_block(1, a, b), friction = s.add_block(2, a, b);
      s.set_bounds(normal, 0, kUnbounded);
      s.blocks[normal].factored = factored;
      s.blocks[normal].regularization = m % 3 == 0 ? 0.1 : 0;
      s.set_friction(friction, s.blocks[normal].position, m % 7 == 0 ? 0.0 : 0.05 + 0.5 * std::abs(u(rng)), pyramid);
      for (int blk : {normal, friction})
        for (int x = 0; x < 12 * s.blocks[blk].size; ++x) s.cell_a(blk)[x] = u(rng);
    }
  }
  for (double& r : s.rhs) r = u(rng);
  s.compliance.assign(s.num_rows, 0.0);
  for (double& e : s.compliance) e = rng() % 2 ? 1e-3 * std::abs(u(rng)) : 0.0;
  RowCache rows;
  rows.update(s);
  rows.lanes.load(s);
  ASSERT_GE(rows.lanes.groups.size(), 10u);
  for (const ContactLanes::Group& g : rows.lanes.groups)
    for (int side = 0; side < 2; ++side)
      for (int l = 0; l < ContactLanes::kLanes; ++l)
        for (int other = 0; other < ContactLanes::kLanes; ++other)
          for (int other_side = 0; other_side < 2; ++other_side)
            if ((l != other || side != other_side) && g.column[side][l] >= 0) {
              ASSERT_NE(g.column[side][l], g.column[other_side][other]);
            }
  std::vector<int> order;
  rows.lanes.sweep_order(&order);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < static_cast<int>(s.blocks.size()); ++k) ASSERT_EQ(sorted[k], k);  // every block once
  std::vector<double> lambda(s.num_rows), dv(6 * s.num_columns);
  for (double& x : lambda) x = 0.5 * std::abs(u(rng));
  for (double& x : dv) x = u(rng);
  project_onto_bounds(s, lambda);
  std::vector<double> lanes_lambda = lambda, lanes_dv = dv;
  for (int sweep = 0; sweep < 3; ++sweep) {
    pgs_sweep(s, rows, lanes_lambda, lanes_dv);
    for (int k : order) pgs_block(s, rows, k, lambda, dv);
  }
  int rim = 0, zero = 0;
  for (const RowBlock& b : s.blocks) {
    if (b.friction_row < 0 || b.friction_pyramid) continue;
    const double radius = friction_radius(b, lambda), norm = std::hypot(lambda[b.position], lambda[b.position + 1]);
    rim += radius > 0 && norm > radius * (1 - 1e-12);
    zero += radius == 0;
  }
  EXPECT_GE(rim, 10);
  EXPECT_GE(zero, 10);
  for (int i = 0; i < s.num_rows; ++i) EXPECT_EQ(lanes_lambda[i], lambda[i]) << "row " << i;
  for (size_t i = 0; i < dv.size(); ++i) EXPECT_EQ(lanes_dv[i], dv[i]) << "dv " << i;
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx2")) {
    std::vector<double> lambda2 = lambda, dv2 = dv, lambda4 = lambda, dv4 = dv;
    const ContactLanes& l = rows.lanes;
    const auto data = [&](std::vector<double>& x, std::vector<double>& v) {
      return lanes::SweepData{l.groups.data(), static_cast<int>(l.groups.size()), l.slots.data(), s.blocks.data(),
                              s.compliance.data(), x.data(), v.data()};
    };
    lanes::sweep_groups_sse2(data(lambda2, dv2));
    lanes::sweep_groups_avx2(data(lambda4, dv4));
    EXPECT_EQ(lambda2, lambda4);
    EXPECT_EQ(dv2, dv4);
  }
#endif
}

TEST(Solver, LdlPgsBeatsPgsAtTheSameIterationCount) {
  const System s = random_system(13, kSizes, kAllEquality, 10, 1e-6);
  const Eigen::VectorXd expected = regularized_h(s).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(s.rhs.data(), s.num_rows));
  const double pgs = max_diff(run(s, SolverKind::pgs, 10).lambda, expected);
  const double ldl = max_diff(run(s, SolverKind::ldl_pgs, 10).lambda, expected);
  std::printf("max relative impulse error after 10 iterations: pgs %.3g, ldl-pgs %.3g\n", pgs, ldl);
  EXPECT_LT(ldl, 1e-9);
  EXPECT_GT(pgs, 1e3 * ldl);
}

TEST(Solver, WarmStartFromTheSolutionStaysThere) {
  const System s = random_system(13, kSizes, kAllEquality, 11, 1e-6);
  const Outcome exact = run(s, SolverKind::direct, 1);
  for (SolverKind kind : {SolverKind::pgs, SolverKind::block_gs, SolverKind::ldl_pgs}) {
    const Outcome r = run(s, kind, 3, exact.lambda);
    Eigen::VectorXd e = Eigen::Map<const Eigen::VectorXd>(exact.lambda.data(), s.num_rows);
    EXPECT_LT(max_diff(r.lambda, e), 1e-9) << to_string(kind);
  }
}

TEST(Solver, RedundantRowsNeedCompliance) {
  // Two identical blocks on the same columns: H is singular (a redundant loop's rows).
  System s = random_system(2, std::vector<int>{3, 3}, std::vector<bool>{false, false}, 12);
  s.blocks[1].column_a = s.blocks[0].column_a;
  s.blocks[1].column_b = s.blocks[0].column_b;
  std::copy(s.cell_a(0), s.cell_a(0) + 36, s.cell_a(1));
  const Outcome singular = run(s, SolverKind::direct, 1);
  EXPECT_EQ(singular.result.factor.status, FactorStatus::zero_pivot) << singular.result.factor.message();
  s.set_compliance(1e-8);
  const Outcome regular = run(s, SolverKind::direct, 1);
  ASSERT_TRUE(regular.result.ok()) << regular.result.factor.message();
  // consistent right-hand side: the same targets on both copies; the impulse splits evenly
  std::copy(s.rhs.begin(), s.rhs.begin() + 3, s.rhs.begin() + 3);
  const Outcome split = run(s, SolverKind::direct, 1);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(split.lambda[r], split.lambda[3 + r], 1e-6 * std::abs(split.lambda[r]) + 1e-12);
  EXPECT_LT(velocity_residual(s, split.lambda, split.dv), 1e-6);
}

TEST(Solver, ComplianceIsPerRow) {
  // Rigid rows beside soft ones: every solver works on H + diag(eps_i H_ii), whatever eps_i.
  System s = random_system(13, kSizes, kAllEquality, 13);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> exponent(-8, -1);
  for (double& eps : s.compliance) eps = rng() % 3 == 0 ? 0.0 : std::pow(10.0, exponent(rng));
  const Eigen::VectorXd expected = regularized_h(s).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(s.rhs.data(), s.num_rows));
  EXPECT_LT(max_diff(run(s, SolverKind::direct, 1).lambda, expected), 1e-10);
  EXPECT_LT(max_diff(run(s, SolverKind::ldl_pgs, 1).lambda, expected), 1e-10);
  EXPECT_LT(max_diff(run(s, SolverKind::block_gs, 4000).lambda, expected), 1e-6);
  std::vector<int> sizes;
  const SymmetricCsc h = equality_matrix(s, &sizes);
  const Eigen::MatrixXd dense_h = regularized_h(s);
  double diff = 0;
  for (int j = 0; j < h.n; ++j)
    for (int p = h.col_ptr[j]; p < h.col_ptr[j + 1]; ++p) diff = std::max(diff, std::abs(h.values[p] - dense_h(h.row_idx[p], j)));
  EXPECT_LT(diff, 1e-12 * dense_h.cwiseAbs().maxCoeff());
  // and nothing of the lower triangle is missing from the pattern
  double stored = 0;
  for (double v : h.values) stored += std::abs(v);
  EXPECT_NEAR(stored, dense_h.triangularView<Eigen::Lower>().toDenseMatrix().cwiseAbs().sum(), 1e-12 * stored);
  EXPECT_EQ(sizes, kSizes);
}

// A block's shape is checked in every build: rows, columns in range, two different columns.
TEST(SystemBadInput, BlockWithoutRows) {
  System s;
  s.num_columns = 2;
  EXPECT_THROW(s.add_block(0, 0, 1), ArgumentError);
}
TEST(SystemBadInput, ColumnOutOfRange) {
  System s;
  s.num_columns = 2;
  EXPECT_THROW(s.add_block(3, 0, 2), ArgumentError);
  EXPECT_THROW(s.add_block(3, -2, 1), ArgumentError);
  EXPECT_EQ(s.add_block(3, 1, -1), 0);  // -1: the other side is static
}
TEST(SystemBadInput, BothSidesOnOneColumn) {
  System s;
  s.num_columns = 2;
  EXPECT_THROW(s.add_block(3, 1, 1), ArgumentError);
  EXPECT_EQ(s.num_rows, 0);
}

TEST(Solver, NamesRoundTrip) {
  for (const char* name : solver_names()) {
    SolverKind kind;
    ASSERT_TRUE(solver_kind_from_string(name, &kind));
    EXPECT_STREQ(to_string(kind), name);
  }
  SolverKind kind;
  EXPECT_FALSE(solver_kind_from_string("gauss-seidel", &kind));
}

}  // namespace
}  // namespace ldlpgs
