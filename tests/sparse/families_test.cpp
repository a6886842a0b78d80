// Mechanism families: every family at 1, 7 and 100 constraints has exactly that many joints,
// row counts from {1,3,4,5,6} and a connected body graph; constraint_graph against a brute force
// (two joints adjacent iff they share a dynamic body) on generated and hand-built mechanisms; the
// shapes (heavy complete, chain a path, loop a cycle, star a hub clique, tree, ladder, grid);
// errors; and seeds (same seed same mechanism, another seed other row counts).
#include "ldlpgs/sparse/families.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {
namespace {

using Edge = std::pair<int, int>;  // (smaller, larger)
const int kSizes[] = {1, 7, 100};

std::vector<std::string> names() {
  return {family_names().begin(), family_names().end()};
}

// Union-find over bodies, joined along the joints.
struct Components {
  std::vector<int> parent;
  explicit Components(const BodyGraph& g) : parent(g.num_bodies()) {
    std::iota(parent.begin(), parent.end(), 0);
    for (const auto& j : g.joints) parent[find(j.body_a)] = find(j.body_b);
  }
  int find(int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); }
  int count() {
    int k = 0;
    for (int x = 0; x < static_cast<int>(parent.size()); ++x) k += find(x) == x;
    return k;
  }
};

// The first body cut off from the mechanism, empty if none. Every dynamic body and every body a
// joint touches must be in one piece; a static body no joint touches (the ground of the floating
// shapes, loop and heavy) is not part of the mechanism and is left out.
std::string disconnected_body(const BodyGraph& g) {
  std::vector<int> joints_on(g.num_bodies(), 0);
  for (const auto& j : g.joints) ++joints_on[j.body_a], ++joints_on[j.body_b];
  Components c(g);
  int root = -1, first = -1;
  for (int b = 0; b < g.num_bodies(); ++b) {
    if (g.is_static[b] && joints_on[b] == 0) continue;
    if (root < 0) {
      root = c.find(b);
      first = b;
    } else if (c.find(b) != root) {
      return "body " + std::to_string(b) + (g.is_static[b] ? " (static, " : " (dynamic, ") +
             std::to_string(joints_on[b]) + " joints) is not connected to body " +
             std::to_string(first);
    }
  }
  return {};
}

// Brute force: joints j < k are adjacent iff one of j's bodies is one of k's and is dynamic.
std::set<Edge> brute_force_edges(const BodyGraph& g) {
  std::set<Edge> edges;
  const int m = static_cast<int>(g.joints.size());
  for (int j = 0; j < m; ++j) {
    for (int k = j + 1; k < m; ++k) {
      for (int x : {g.joints[j].body_a, g.joints[j].body_b}) {
        for (int y : {g.joints[k].body_a, g.joints[k].body_b}) {
          if (x == y && !g.is_static[x]) edges.insert({j, k});
        }
      }
    }
  }
  return edges;
}

std::set<Edge> edges_of(const BlockPattern& p) {
  std::set<Edge> edges;
  for (int b = 0; b < p.num_blocks(); ++b) {
    for (int c : p.neighbors(b)) edges.insert({std::min(b, c), std::max(b, c)});
  }
  return edges;
}

// constraint_graph(g) against the brute force: block j is joint j with its rows, in order.
void expect_constraint_graph(const BodyGraph& g) {
  const BlockPattern p = constraint_graph(g);
  ASSERT_EQ(p.num_blocks(), static_cast<int>(g.joints.size()));
  int position = 0;
  for (int j = 0; j < p.num_blocks(); ++j) {
    EXPECT_EQ(p.block(j).size, g.joints[j].rows) << "block " << j;
    EXPECT_EQ(p.block(j).position, position) << "block " << j;
    position += g.joints[j].rows;
  }
  EXPECT_EQ(edges_of(p), brute_force_edges(g));
  EXPECT_EQ(p.num_edges(), static_cast<int64_t>(brute_force_edges(g).size()));
}

std::vector<int> row_counts(const BodyGraph& g) {
  std::vector<int> rows;
  for (const auto& j : g.joints) rows.push_back(j.rows);
  return rows;
}

// --- every family -----------------------------------------------------------------------------

TEST(Families, NamesAreTheDocumentedSeven) {
  std::vector<std::string> got = names(), expected = {"chain", "grid",  "heavy", "ladder",
                                                      "loop",  "star", "tree"};
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, expected);
}

TEST(Families, ExactJointCountsAndRowCounts) {
  // Every shape gives exactly the count asked for: where the shape rounds (grid's width, the
  // star's number of arms, a ladder's last rung) the rounding changes the shape, not the count
  // (the grid hangs a tail chain, a ladder stops mid-rung, the arms differ in length).
  const std::set<int> allowed = {1, 3, 4, 5, 6};
  for (const std::string& family : names()) {
    for (int m : kSizes) {
      SCOPED_TRACE(family + " " + std::to_string(m));
      const BodyGraph g = make_family(family, m);
      EXPECT_EQ(static_cast<int>(g.joints.size()), m);
      for (const auto& j : g.joints) {
        EXPECT_TRUE(allowed.count(j.rows)) << j.rows << " rows";
        EXPECT_TRUE(j.body_a >= 0 && j.body_a < g.num_bodies());
        EXPECT_TRUE(j.body_b >= 0 && j.body_b < g.num_bodies());
      }
    }
  }
  // Over 100 draws every joint kind turns up.
  const std::vector<int> rows = row_counts(make_family("chain", 100));
  EXPECT_EQ(std::set<int>(rows.begin(), rows.end()), allowed);
}

TEST(Families, JointsJoinTwoDifferentBodies) {
  // A joint from a body to itself would remove no freedom (its Jacobian rows cancel); a loop
  // of one joint is a body hung from the ground instead.
  for (const std::string& family : names()) {
    for (int m : {1, 2, 7, 100}) {
      const BodyGraph g = make_family(family, m);
      for (const auto& j : g.joints) {
        EXPECT_NE(j.body_a, j.body_b) << family << " " << m;
      }
    }
  }
}

TEST(Families, BodyGraphIsConnected) {
  // At the asked sizes and every size up to 60 (to reach each way a shape can round). A failure
  // lists the sizes and the first loose body of the first of them.
  std::vector<int> sizes(60);
  std::iota(sizes.begin(), sizes.end(), 1);
  sizes.push_back(100);
  for (const std::string& family : names()) {
    std::vector<int> bad;
    std::string first;
    for (int m : sizes) {
      const std::string problem = disconnected_body(make_family(family, m));
      if (problem.empty()) continue;
      if (bad.empty()) first = problem;
      bad.push_back(m);
    }
    std::string list;
    for (int m : bad) {
      list += ' ';  // (not " " + string: GCC 12 -O3 warns falsely there, bug 105329)
      list += std::to_string(m);
    }
    EXPECT_TRUE(bad.empty()) << family << " is disconnected at sizes" << list << "; at "
                             << bad.front() << ": " << first;
  }
}

TEST(Families, ConnectivityCheckCanFail) {
  BodyGraph g;
  g.is_static = {1, 0, 0, 0};
  g.joints = {{0, 1, 3}, {1, 2, 3}};
  EXPECT_EQ(disconnected_body(g), "body 3 (dynamic, 0 joints) is not connected to body 0");
  g.is_static[3] = 1;  // an unused static body is not part of the mechanism
  EXPECT_EQ(disconnected_body(g), "");
}

TEST(Families, ConstraintGraphMatchesBruteForce) {
  for (const std::string& family : names()) {
    for (int m : kSizes) {
      for (uint32_t seed : {1u, 2u}) {
        SCOPED_TRACE(family + " " + std::to_string(m) + ", seed " + std::to_string(seed));
        expect_constraint_graph(make_family(family, m, seed));
      }
    }
  }
}

// --- constraint_graph on hand-built mechanisms --------------------------------------------------

TEST(ConstraintGraph, HandBuilt) {
  // Ground 0 (static), bodies 1, 2, 3. Joints: j0 0-1, j1 1-2, j2 0-2, j3 2-3, j4 2-1 (a second
  // joint on the pair 1-2). By hand: j0-j1 and j0-j4 share body 1; j1, j2, j3, j4 all touch
  // body 2; j0-j2 share only the ground, which couples nothing.
  BodyGraph g;
  g.is_static = {1, 0, 0, 0};
  g.joints = {{0, 1, 3}, {1, 2, 1}, {0, 2, 5}, {2, 3, 6}, {2, 1, 4}};
  const std::set<Edge> expected = {{0, 1}, {0, 4}, {1, 2}, {1, 3}, {1, 4},
                                   {2, 3}, {2, 4}, {3, 4}};
  EXPECT_EQ(brute_force_edges(g), expected);
  EXPECT_EQ(edges_of(constraint_graph(g)), expected);
  expect_constraint_graph(g);
  // Body 2 made static as well: only body 1 couples anything.
  g.is_static[2] = 1;
  EXPECT_EQ(edges_of(constraint_graph(g)), (std::set<Edge>{{0, 1}, {0, 4}, {1, 4}}));
}

TEST(ConstraintGraph, SelfJointIsOneBlockWithoutEdges) {
  // A hand-built joint from a body to itself: still one block, no self loop.
  BodyGraph g;
  g.is_static = {1, 0};
  g.joints = {{1, 1, 5}};
  const BlockPattern p = constraint_graph(g);
  EXPECT_EQ(p.num_blocks(), 1);
  EXPECT_EQ(p.num_edges(), 0);
  EXPECT_EQ(constraint_graph(make_family("loop", 1)).num_edges(), 0);
}

TEST(ConstraintGraph, NoJoints) {
  BodyGraph g;
  g.is_static = {1, 0};
  const BlockPattern p = constraint_graph(g);
  EXPECT_EQ(p.num_blocks(), 0);
  EXPECT_EQ(p.num_rows(), 0);
}

// --- shapes -----------------------------------------------------------------------------------

TEST(Shapes, HeavyIsComplete) {
  for (int m : kSizes) {
    const BlockPattern p = constraint_graph(make_family("heavy", m));
    EXPECT_EQ(p.num_edges(), static_cast<int64_t>(m) * (m - 1) / 2) << m;
    for (int b = 0; b < m; ++b) ASSERT_EQ(p.graph().degree(b), m - 1) << m;
  }
}

TEST(Shapes, ChainIsAPath) {
  for (int m : kSizes) {
    std::set<Edge> path;
    for (int j = 0; j + 1 < m; ++j) path.insert({j, j + 1});
    EXPECT_EQ(edges_of(constraint_graph(make_family("chain", m))), path) << m;
  }
}

TEST(Shapes, LoopIsACycle) {
  // A ring of m >= 3 joints is the cycle 0-1-...-(m-1)-0. Two joints on the same two bodies
  // are one edge; a single joint has none.
  for (int m : {3, 7, 100}) {
    std::set<Edge> cycle = {{0, m - 1}};
    for (int j = 0; j + 1 < m; ++j) cycle.insert({j, j + 1});
    EXPECT_EQ(edges_of(constraint_graph(make_family("loop", m))), cycle) << m;
  }
  EXPECT_EQ(edges_of(constraint_graph(make_family("loop", 2))), (std::set<Edge>{{0, 1}}));
  EXPECT_EQ(constraint_graph(make_family("loop", 1)).num_edges(), 0);
}

TEST(Shapes, StarHubCarriesAboutSqrtHalfMArms) {
  // The hub is the dynamic body with the most joints: its hanging joint plus one per arm,
  // about sqrt(m/2) + 1 in all; they form a clique. Every other body is on an arm (a chain):
  // at most two joints.
  for (int m : kSizes) {
    SCOPED_TRACE(m);
    const BodyGraph g = make_family("star", m);
    std::vector<std::vector<int>> on(g.num_bodies());
    for (int j = 0; j < m; ++j) {
      on[g.joints[j].body_a].push_back(j);
      on[g.joints[j].body_b].push_back(j);
    }
    int hub = -1;
    for (int b = 0; b < g.num_bodies(); ++b) {
      if (!g.is_static[b] && (hub < 0 || on[b].size() > on[hub].size())) hub = b;
    }
    ASSERT_GE(hub, 0);
    const double clique = static_cast<double>(on[hub].size());
    EXPECT_NEAR(clique, std::sqrt(m / 2.0) + 1, 1.0);
    const std::set<Edge> edges = edges_of(constraint_graph(g));
    for (int x : on[hub]) {
      for (int y : on[hub]) {
        if (x < y) {
          EXPECT_TRUE(edges.count({x, y})) << x << "-" << y << " not adjacent";
        }
      }
    }
    for (int b = 0; b < g.num_bodies(); ++b) {
      if (b != hub && !g.is_static[b]) {
        EXPECT_LE(on[b].size(), 2u) << "body " << b;
      }
    }
  }
  // At 100: 7 arms (sqrt(50) = 7.07), so the hub has 8 joints.
  const BodyGraph g = make_family("star", 100);
  std::map<int, int> joints_on;
  for (const auto& j : g.joints) ++joints_on[j.body_a], ++joints_on[j.body_b];
  int most = 0;
  for (auto [b, k] : joints_on) {
    if (!g.is_static[b]) most = std::max(most, k);
  }
  EXPECT_EQ(most, 8);
}

TEST(Shapes, TreeIsATreeWithAtMostThreeChildren) {
  // m joints on m + 1 bodies, connected: a tree. Joints go parent -> child, so each body is
  // the first body of at most three joints, and the second body of exactly one (the ground of
  // none).
  for (int m : kSizes) {
    SCOPED_TRACE(m);
    const BodyGraph g = make_family("tree", m);
    ASSERT_EQ(g.num_bodies(), m + 1);
    EXPECT_EQ(Components(g).count(), 1);
    std::vector<int> children(g.num_bodies(), 0), parents(g.num_bodies(), 0);
    for (const auto& j : g.joints) ++children[j.body_a], ++parents[j.body_b];
    for (int b = 0; b < g.num_bodies(); ++b) {
      EXPECT_LE(children[b], 3) << "body " << b;
      EXPECT_EQ(parents[b], g.is_static[b] ? 0 : 1) << "body " << b;
    }
  }
  // Branching happens: a 100-body tree is not a chain.
  const BodyGraph g = make_family("tree", 100);
  std::vector<int> children(g.num_bodies(), 0);
  for (const auto& j : g.joints) ++children[j.body_a];
  EXPECT_GT(*std::max_element(children.begin(), children.end()), 1);
}

TEST(Shapes, LadderHasOneLoopPerRung) {
  // With whole rungs (m = 3k) the body graph has 2k + 1 bodies, 3k joints, one piece: its
  // cycle rank (independent loops) is k, one per rung. No body has more than three joints.
  for (int k : {1, 2, 33}) {
    const BodyGraph g = make_family("ladder", 3 * k);
    Components c(g);
    EXPECT_EQ(g.num_bodies(), 2 * k + 1) << k;
    EXPECT_EQ(static_cast<int>(g.joints.size()) - g.num_bodies() + c.count(), k) << k;
    std::vector<int> degree(g.num_bodies(), 0);
    for (const auto& j : g.joints) ++degree[j.body_a], ++degree[j.body_b];
    for (int b = 0; b < g.num_bodies(); ++b) {
      if (!g.is_static[b]) {
        EXPECT_LE(degree[b], 3);
      }
    }
  }
}

TEST(Shapes, GridIsPinnedAndHasManyLoops) {
  // A cloth: no dynamic body has more than four neighbours (left, right, up, down); the top
  // row hangs from static bodies; and there are many independent loops (a w x w grid pinned
  // along its top has w (w - 1)).
  const BodyGraph g = make_family("grid", 100);
  std::vector<int> degree(g.num_bodies(), 0);
  int pins = 0;
  for (const auto& j : g.joints) {
    ++degree[j.body_a], ++degree[j.body_b];
    pins += g.is_static[j.body_a] || g.is_static[j.body_b];
  }
  for (int b = 0; b < g.num_bodies(); ++b) {
    if (!g.is_static[b]) {
      EXPECT_LE(degree[b], 4) << "body " << b;
    }
  }
  EXPECT_GE(pins, 2);
  Components c(g);
  EXPECT_GE(static_cast<int>(g.joints.size()) - g.num_bodies() + c.count(), 100 / 3);
}

// --- errors and seeds ---------------------------------------------------------------------------

TEST(Families, UnknownNameThrows) {
  for (const char* bad : {"chains", "Chain", "", "mesh"}) {
    try {
      make_family(bad, 10);
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + std::string(bad) + "'"), std::string::npos)
          << e.what();
    }
  }
}

TEST(Families, FewerThanOneConstraintThrows) {
  EXPECT_THROW(make_family("chain", 0), InputError);
  EXPECT_THROW(make_family("heavy", -5), InputError);
}

bool same(const BodyGraph& x, const BodyGraph& y) {
  if (x.is_static != y.is_static || x.joints.size() != y.joints.size()) return false;
  for (size_t k = 0; k < x.joints.size(); ++k) {
    const auto &a = x.joints[k], &b = y.joints[k];
    if (a.body_a != b.body_a || a.body_b != b.body_b || a.rows != b.rows) return false;
  }
  return true;
}

TEST(Families, SameSeedSameMechanismOtherSeedOtherRows) {
  for (const std::string& family : names()) {
    SCOPED_TRACE(family);
    const BodyGraph a = make_family(family, 100, 7), b = make_family(family, 100, 7);
    EXPECT_TRUE(same(a, b));
    EXPECT_TRUE(same(make_family(family, 100), make_family(family, 100, 1)));  // default seed
    const BlockPattern pa = constraint_graph(a), pb = constraint_graph(b);
    EXPECT_EQ(pa.graph().adj, pb.graph().adj);
    EXPECT_EQ(pa.block_sizes(), pb.block_sizes());
    // 100 draws from 5 kinds: equal by chance with probability 5^-100.
    EXPECT_NE(row_counts(a), row_counts(make_family(family, 100, 8)));
  }
  // The tree's shape is random too: which body each joint hangs from.
  auto parents = [](const BodyGraph& g) {
    std::vector<int> p;
    for (const auto& j : g.joints) p.push_back(j.body_a);
    return p;
  };
  EXPECT_NE(parents(make_family("tree", 100, 1)), parents(make_family("tree", 100, 2)));
}

}  // namespace
}  // namespace ldlpgs
