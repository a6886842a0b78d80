// mechanism_matrix: for every family at 1, 12 and 150 constraints, the stored pattern is the
// constraint graph with dense blocks (against BlockPattern::expand and from_scalar); H = J W J^T
// is what a rigid-body Jacobian makes it, checked through invariants the test can see without J
// (positive semidefinite, rank at most 6 per dynamic body, positive definite on trees, every
// coupling block nonzero); the compliance scales the diagonal only and makes H positive definite
// (dense Eigen); and seeds.
#include "ldlpgs/sparse/mechanism_matrix.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "tests/support/test_matrices.h"

namespace ldlpgs {
namespace {

using testing::dense;
using testing::stored;

const int kSizes[] = {1, 12, 150};

struct Case {
  std::string name;
  BodyGraph g;
};

// Every family at every size, and a hand-built mechanism with the corner cases: two joints on
// the same two bodies (1-2 twice), a joint between the ground and a body, a joint from a body to
// itself (3-3, whose rows on body 3 are J_a + J_b).
std::vector<Case> cases() {
  std::vector<Case> all;
  for (std::string_view family : family_names()) {
    for (int m : kSizes) {
      all.push_back({std::string(family) + " " + std::to_string(m), make_family(family, m)});
    }
  }
  BodyGraph g;
  g.is_static = {1, 0, 0, 0};
  g.joints = {{0, 1, 3}, {1, 2, 1}, {0, 2, 5}, {2, 3, 6}, {2, 1, 4}, {3, 3, 3}};
  all.push_back({"hand-built", g});
  return all;
}

std::vector<int> row_counts(const BodyGraph& g) {
  std::vector<int> rows;
  for (const auto& j : g.joints) rows.push_back(j.rows);
  return rows;
}

// 6 times the number of dynamic bodies some joint touches: the columns of J, a bound on its rank.
int freedoms(const BodyGraph& g) {
  std::set<int> bodies;
  for (const auto& j : g.joints) {
    for (int b : {j.body_a, j.body_b}) {
      if (!g.is_static[b]) bodies.insert(b);
    }
  }
  return 6 * static_cast<int>(bodies.size());
}

Eigen::VectorXd eigenvalues(const SymmetricCsc& h) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(dense(h), Eigen::EigenvaluesOnly);
  EXPECT_EQ(eig.info(), Eigen::Success);
  return eig.eigenvalues();  // ascending
}

TEST(MechanismMatrix, PatternIsTheConstraintGraphWithDenseBlocks) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const SymmetricCsc h = mechanism_matrix(c.g);
    testing::expect_valid(h);
    const BlockPattern expected = constraint_graph(c.g);
    // expand() stores every diagonal block and every adjacent block dense, and nothing else.
    EXPECT_EQ(stored(h), stored(expected.expand()));
    const BlockPattern got = BlockPattern::from_scalar(h, row_counts(c.g));
    EXPECT_EQ(got.graph().ptr, expected.graph().ptr);
    EXPECT_EQ(got.graph().adj, expected.graph().adj);
    // The dense blocks are real couplings: a shared body gives J_xb W_b J_yb^T != 0.
    const Eigen::MatrixXd d = dense(h);
    for (int x = 0; x < expected.num_blocks(); ++x) {
      for (int y : expected.neighbors(x)) {
        const Block &bx = expected.block(x), &by = expected.block(y);
        EXPECT_GT(d.block(bx.position, by.position, bx.size, by.size).norm(), 0) << x << "-" << y;
      }
    }
  }
}

TEST(MechanismMatrix, PositiveSemidefiniteWithoutRegularization) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Eigen::VectorXd lambda = eigenvalues(mechanism_matrix(c.g, 1, 0.0));
    EXPECT_GE(lambda(0), -1e-12 * lambda(lambda.size() - 1));
  }
}

TEST(MechanismMatrix, RankAtMostSixPerDynamicBody) {
  // H = J W J^T has rank at most the number of columns of J: rows beyond 6 per dynamic body are
  // redundant and give zero eigenvalues. At least one case (the grid) must have such rows.
  int redundant_cases = 0;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const SymmetricCsc h = mechanism_matrix(c.g, 1, 0.0);
    const int redundant = h.n - freedoms(c.g);
    if (redundant <= 0) continue;
    ++redundant_cases;
    const Eigen::VectorXd lambda = eigenvalues(h);
    const double largest = lambda(lambda.size() - 1);
    EXPECT_LE(lambda(redundant - 1), 1e-12 * largest);
    // and the regularization lifts all of them
    EXPECT_GT(eigenvalues(mechanism_matrix(c.g, 1, 1e-6))(0), 1e-12 * largest);
  }
  EXPECT_GE(redundant_cases, 1);
}

TEST(MechanismMatrix, TreesArePositiveDefiniteWithoutRegularization) {
  // In a mechanism hung from the ground without loops each joint has a child body of its own,
  // on which its rows are independent (orthonormal directions): J has full row rank.
  for (const char* family : {"chain", "tree", "star"}) {
    for (int m : kSizes) {
      SCOPED_TRACE(std::string(family) + " " + std::to_string(m));
      const BodyGraph g = make_family(family, m);
      const SymmetricCsc h = mechanism_matrix(g, 1, 0.0);
      ASSERT_LE(h.n, freedoms(g));
      EXPECT_GT(eigenvalues(h)(0), 0);
      EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(dense(h)).info(), Eigen::Success);
    }
  }
}

TEST(MechanismMatrix, JointFromABodyToItselfHasRowsJaPlusJb) {
  // The hand-built 3-3 joint has rows J_a + J_b = [0, ((r_a - r_b) x u)^T] on body 3: all three
  // are orthogonal to r_a - r_b in the angular coordinates, so its diagonal block has rank 2.
  // The ball joint 0-1 (rows on body 1 only) has rank 3.
  const BodyGraph g = cases().back().g;
  const Eigen::MatrixXd d = dense(mechanism_matrix(g, 1, 0.0));
  const BlockPattern p = constraint_graph(g);
  auto block_eigenvalues = [&](int j) {
    const Block& b = p.block(j);
    const Eigen::MatrixXd n = d.block(b.position, b.position, b.size, b.size);
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(n).eigenvalues();
  };
  const Eigen::VectorXd self = block_eigenvalues(5), ball = block_eigenvalues(0);
  EXPECT_LE(std::abs(self(0)), 1e-12 * self(2));
  EXPECT_GT(self(1), 1e-6 * self(2));
  EXPECT_GT(ball(0), 1e-6 * ball(2));
}

TEST(MechanismMatrix, RegularizedIsPositiveDefinite) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(dense(mechanism_matrix(c.g))).info(), Eigen::Success);
  }
}

TEST(MechanismMatrix, RegularizationScalesTheDiagonalOnly) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const SymmetricCsc h0 = mechanism_matrix(c.g, 1, 0.0);
    for (double reg : {1e-6, 0.25}) {
      const SymmetricCsc h = mechanism_matrix(c.g, 1, reg);
      ASSERT_EQ(h.col_ptr, h0.col_ptr);
      ASSERT_EQ(h.row_idx, h0.row_idx);
      for (int col = 0; col < h.n; ++col) {
        for (int p = h.col_ptr[col]; p < h.col_ptr[col + 1]; ++p) {
          if (h.row_idx[p] == col) {
            ASSERT_GT(h0.values[p], 0) << "column " << col;  // J_i W J_i^T, J_i a nonzero row
            EXPECT_DOUBLE_EQ(h.values[p], (1 + reg) * h0.values[p]) << "column " << col;
          } else {
            EXPECT_EQ(h.values[p], h0.values[p]) << "(" << h.row_idx[p] << ", " << col << ")";
          }
        }
      }
    }
  }
}

TEST(MechanismMatrix, SameSeedSameValuesOtherSeedOtherValues) {
  for (std::string_view family : family_names()) {
    SCOPED_TRACE(family);
    const BodyGraph g = make_family(family, 150);
    const SymmetricCsc a = mechanism_matrix(g, 7);
    testing::expect_equal(a, mechanism_matrix(g, 7));
    testing::expect_equal(mechanism_matrix(g), mechanism_matrix(g, 1, 1e-6));  // defaults
    const SymmetricCsc b = mechanism_matrix(g, 8);
    EXPECT_EQ(a.row_idx, b.row_idx);  // the pattern is the mechanism's
    EXPECT_NE(a.values, b.values);
  }
}

}  // namespace
}  // namespace ldlpgs
