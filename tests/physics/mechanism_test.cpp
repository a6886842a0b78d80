// Mechanism: the constraint graph against a brute-force construction over all pairs of
// constraints (row counts from the table in constraint.h, adjacency = a shared dynamic body),
// on a hand-made mechanism and on random ones; static bodies couple nothing; equality_only
// keeps the equality constraints renumbered in order; the body graph and the bookkeeping.
#include "ldlpgs/physics/mechanism.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace ldlpgs {
namespace {

// Rows per type as constraint.h tabulates them (independent of num_rows()).
int rows_of(ConstraintType t) {
  switch (t) {
    case ConstraintType::ball: return 3;
    case ConstraintType::hinge: return 5;
    case ConstraintType::prismatic: return 5;
    case ConstraintType::cylindrical: return 4;
    case ConstraintType::weld: return 6;
    default: return 1;
  }
}
bool equality(ConstraintType t) {
  return t != ConstraintType::rope && t != ConstraintType::angular_limit && t != ConstraintType::positional_limit;
}

constexpr ConstraintType kTypes[] = {ConstraintType::ball,          ConstraintType::hinge, ConstraintType::prismatic,
                                     ConstraintType::cylindrical,   ConstraintType::weld,  ConstraintType::rod,
                                     ConstraintType::rope,          ConstraintType::angular_limit,
                                     ConstraintType::positional_limit};

RigidBody body(const std::string& name, bool is_static) {
  RigidBody b;
  b.name = name;
  b.is_static = is_static;
  return b;
}

// Only the type and the bodies matter to the graphs.
Constraint joint(ConstraintType type, int a, int b) {
  Constraint c;
  c.type = type;
  c.body_a = a;
  c.body_b = b;
  return c;
}

// The adjacency as a set of (smaller, larger) pairs.
std::set<std::pair<int, int>> edges_of(const Graph& g) {
  std::set<std::pair<int, int>> e;
  for (int v = 0; v < g.n; ++v) {
    const auto nb = g.neighbors(v);
    EXPECT_TRUE(std::is_sorted(nb.begin(), nb.end()));
    for (int u : nb) {
      EXPECT_NE(u, v);
      if (u > v) e.emplace(v, u);
    }
  }
  EXPECT_EQ(static_cast<int64_t>(e.size()), g.num_edges());
  return e;
}

// Brute force over all pairs of kept constraints: sizes and edges.
void expect_brute_force(const Mechanism& m, bool equality_only) {
  std::vector<int> kept;
  for (int c = 0; c < static_cast<int>(m.constraints.size()); ++c)
    if (!equality_only || equality(m.constraints[c].type)) kept.push_back(c);
  std::vector<int> sizes;
  std::set<std::pair<int, int>> expected;
  for (size_t i = 0; i < kept.size(); ++i) {
    const Constraint& ci = m.constraints[kept[i]];
    sizes.push_back(rows_of(ci.type));
    for (size_t j = i + 1; j < kept.size(); ++j) {
      const Constraint& cj = m.constraints[kept[j]];
      bool shared = false;
      for (int x : {ci.body_a, ci.body_b})
        for (int y : {cj.body_a, cj.body_b}) shared |= x == y && !m.bodies[x].is_static;
      if (shared) expected.emplace(static_cast<int>(i), static_cast<int>(j));
    }
  }
  const BlockPattern p = m.constraint_graph(equality_only);
  ASSERT_EQ(p.num_blocks(), static_cast<int>(kept.size()));
  EXPECT_EQ(p.block_sizes(), sizes);
  int rows = 0;
  for (int s : sizes) rows += s;
  EXPECT_EQ(p.num_rows(), rows);
  EXPECT_EQ(edges_of(p.graph()), expected);
}

// ground(static) - b1 - b2 - b3, b3 - wall(static), b2 = b4 by two constraints, limits on b1-b2.
Mechanism hand_made() {
  Mechanism m;
  m.name = "hand-made";
  m.add_body(body("ground", true));  // 0
  m.add_body(body("b1", false));     // 1
  m.add_body(body("b2", false));     // 2
  m.add_body(body("b3", false));     // 3
  m.add_body(body("wall", true));    // 4
  m.add_body(body("b4", false));     // 5
  m.add_constraint(joint(ConstraintType::ball, 0, 1));            // 0
  m.add_constraint(joint(ConstraintType::hinge, 1, 2));           // 1
  m.add_constraint(joint(ConstraintType::angular_limit, 1, 2));   // 2
  m.add_constraint(joint(ConstraintType::cylindrical, 2, 3));     // 3
  m.add_constraint(joint(ConstraintType::rope, 3, 4));            // 4
  m.add_constraint(joint(ConstraintType::weld, 4, 5));            // 5
  m.add_constraint(joint(ConstraintType::rod, 0, 5));             // 6
  m.add_constraint(joint(ConstraintType::prismatic, 2, 5));       // 7
  m.add_constraint(joint(ConstraintType::positional_limit, 5, 2));  // 8
  return m;
}

TEST(Mechanism, Bookkeeping) {
  const Mechanism m = hand_made();
  EXPECT_EQ(m.find_body("ground"), 0);
  EXPECT_EQ(m.find_body("b4"), 5);
  EXPECT_EQ(m.find_body("b5"), -1);
  EXPECT_EQ(m.find_body(""), -1);
  EXPECT_EQ(m.num_dynamic_bodies(), 4);
  EXPECT_EQ(m.num_rows(), 3 + 5 + 1 + 4 + 1 + 6 + 1 + 5 + 1);
  Mechanism n;
  EXPECT_EQ(n.add_body(body("x", false)), 0);
  EXPECT_EQ(n.add_body(body("y", true)), 1);
  EXPECT_EQ(n.add_constraint(joint(ConstraintType::ball, 0, 1)), 0);
  EXPECT_EQ(n.add_constraint(joint(ConstraintType::rope, 1, 0)), 1);
  EXPECT_EQ(n.num_rows(), 4);
  EXPECT_EQ(n.num_dynamic_bodies(), 1);
  EXPECT_EQ(Mechanism().num_rows(), 0);
  EXPECT_EQ(Mechanism().constraint_graph().num_blocks(), 0);
}

TEST(Mechanism, BodyGraphHasOneEdgePerConstraint) {
  const Mechanism m = hand_made();
  const auto edges = m.body_graph();
  ASSERT_EQ(edges.size(), m.constraints.size());
  for (size_t c = 0; c < edges.size(); ++c) {
    EXPECT_EQ(edges[c].first, m.constraints[c].body_a);
    EXPECT_EQ(edges[c].second, m.constraints[c].body_b);
  }
}

TEST(Mechanism, ConstraintGraphOfAHandMadeMechanism) {
  const Mechanism m = hand_made();
  expect_brute_force(m, false);
  // written out: through b1 {0,1,2}, b2 {1,2,3,7,8}, b3 {3,4}, b4 {5,6,7,8}; nothing through
  // ground (0, 6) or wall (4, 5)
  const std::set<std::pair<int, int>> expected = {{0, 1}, {0, 2}, {1, 2}, {1, 3}, {1, 7}, {1, 8}, {2, 3},
                                                  {2, 7}, {2, 8}, {3, 7}, {3, 8}, {7, 8}, {3, 4}, {5, 6},
                                                  {5, 7}, {5, 8}, {6, 7}, {6, 8}};
  const BlockPattern p = m.constraint_graph();
  EXPECT_EQ(edges_of(p.graph()), expected);
  EXPECT_EQ(p.block_sizes(), (std::vector<int>{3, 5, 1, 4, 1, 6, 1, 5, 1}));
  EXPECT_EQ(p.block(3).position, 3 + 5 + 1);
}

TEST(Mechanism, StaticBodiesCoupleNothing) {
  // a star: every constraint joins the static hub to its own dynamic body
  Mechanism m;
  m.add_body(body("hub", true));
  for (int i = 0; i < 6; ++i) {
    m.add_body(body(std::string("b") + std::to_string(i), false));
    m.add_constraint(joint(kTypes[i], 0, i + 1));
  }
  EXPECT_EQ(m.constraint_graph().num_edges(), 0);
  // the same with the hub dynamic: complete
  m.bodies[0].is_static = false;
  EXPECT_EQ(m.constraint_graph().num_edges(), 6 * 5 / 2);
  expect_brute_force(m, false);
  // two static bodies holding one dynamic body: the constraints meet at the dynamic one only
  Mechanism h;
  h.add_body(body("left", true));
  h.add_body(body("right", true));
  h.add_body(body("beam", false));
  h.add_constraint(joint(ConstraintType::hinge, 0, 2));
  h.add_constraint(joint(ConstraintType::hinge, 2, 1));
  h.add_constraint(joint(ConstraintType::rope, 0, 2));
  expect_brute_force(h, false);
  EXPECT_EQ(h.constraint_graph().num_edges(), 3);
}

TEST(Mechanism, EqualityOnlyRenumbersInOrder) {
  const Mechanism m = hand_made();
  expect_brute_force(m, true);
  // equality constraints 0, 1, 3, 5, 6, 7 become blocks 0..5
  const BlockPattern p = m.constraint_graph(true);
  EXPECT_EQ(p.block_sizes(), (std::vector<int>{3, 5, 4, 6, 1, 5}));
  const std::set<std::pair<int, int>> expected = {{0, 1}, {1, 2}, {1, 5}, {2, 5}, {3, 4}, {3, 5}, {4, 5}};
  EXPECT_EQ(edges_of(p.graph()), expected);
  // no equality constraint at all
  Mechanism r;
  r.add_body(body("a", false));
  r.add_body(body("b", false));
  r.add_constraint(joint(ConstraintType::rope, 0, 1));
  r.add_constraint(joint(ConstraintType::angular_limit, 0, 1));
  EXPECT_EQ(r.constraint_graph(true).num_blocks(), 0);
  EXPECT_EQ(r.constraint_graph(false).num_edges(), 1);
}

TEST(Mechanism, ConstraintGraphOfRandomMechanismsMatchesBruteForce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int nb = 2 + static_cast<int>(rng() % 12), nc = static_cast<int>(rng() % 40);
    Mechanism m;
    for (int b = 0; b < nb; ++b) m.add_body(body(std::string("b") + std::to_string(b), rng() % 4 == 0));
    m.bodies[0].is_static = false;  // at least one dynamic body
    for (int c = 0; c < nc; ++c) {
      int a = static_cast<int>(rng() % nb), b = static_cast<int>(rng() % nb);
      if (a == b) continue;
      if (m.bodies[a].is_static && m.bodies[b].is_static) b = 0;
      if (a == b) continue;
      m.add_constraint(joint(kTypes[rng() % std::size(kTypes)], a, b));
    }
    SCOPED_TRACE(std::string("trial ") + std::to_string(trial));
    expect_brute_force(m, false);
    expect_brute_force(m, true);
  }
}

TEST(Mechanism, LongChainGraphIsAPath) {
  // 100000 ball joints in a row from a static ground: a path graph of 99999 edges
  const int n = 100000;
  Mechanism m;
  m.add_body(body("ground", true));
  for (int i = 0; i < n; ++i) {
    m.add_body(body(std::string("link") + std::to_string(i), false));
    m.add_constraint(joint(ConstraintType::ball, i, i + 1));
  }
  const BlockPattern p = m.constraint_graph();
  EXPECT_EQ(p.num_blocks(), n);
  EXPECT_EQ(p.num_rows(), 3 * n);
  ASSERT_EQ(p.num_edges(), n - 1);
  for (int c = 0; c + 1 < n; ++c) {
    ASSERT_EQ(p.graph().degree(c), c == 0 ? 1 : 2);
    ASSERT_EQ(p.neighbors(c).back(), c + 1);
  }
}

}  // namespace
}  // namespace ldlpgs
