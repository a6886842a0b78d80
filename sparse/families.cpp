#include "ldlpgs/sparse/families.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/limits.h"

namespace ldlpgs {

// Two joints are adjacent iff they share a dynamic body: H_ij = J_i W J_j^T sums over the bodies
// both touch, and W = 0 on a static body. Grouping the joints by body gives the edges in
// O(sum over bodies of degree^2), the size of the output, instead of testing all pairs.
BlockPattern constraint_graph(const BodyGraph& mechanism) {
  const int nb = mechanism.num_bodies(), nj = static_cast<int>(mechanism.joints.size());
  // The joints on each dynamic body, as compressed rows (ptr size bodies+1, on_body size <= 2 joints).
  std::vector<int> ptr(nb + 1, 0), on_body;
  auto each_dynamic_end = [&](auto&& visit) {
    for (int j = 0; j < nj; ++j)
      for (int body : {mechanism.joints[j].body_a, mechanism.joints[j].body_b})
        if (!mechanism.is_static[body]) visit(body, j);
  };
  each_dynamic_end([&](int body, int) { ++ptr[body + 1]; });
  for (int b = 0; b < nb; ++b) ptr[b + 1] += ptr[b];
  on_body.resize(ptr[nb]);
  std::vector<int> next(ptr.begin(), ptr.end() - 1);
  each_dynamic_end([&](int body, int j) { on_body[next[body]++] = j; });

  std::vector<std::pair<int, int>> edges;
  for (int b = 0; b < nb; ++b)
    for (int i = ptr[b]; i < ptr[b + 1]; ++i)
      for (int k = ptr[b]; k < i; ++k)
        if (on_body[k] != on_body[i]) edges.emplace_back(on_body[k], on_body[i]);
  // graph_from_edges merges the duplicates (two joints sharing both their bodies).
  std::vector<int> sizes;
  for (const BodyGraph::Joint& joint : mechanism.joints) sizes.push_back(joint.rows);
  return BlockPattern(sizes, graph_from_edges(nj, edges));
}

namespace {

constexpr std::array<std::string_view, 7> kFamilies = {"chain", "tree", "ladder", "loop",
                                                       "heavy", "grid", "star"};

// Builds a body graph joint by joint, with row counts drawn as joints have them.
class Builder {
 public:
  explicit Builder(uint32_t seed) : rng_(seed) {}
  int body(bool is_static = false) {
    g_.is_static.push_back(is_static);
    return g_.num_bodies() - 1;
  }
  void joint(int a, int b) {
    // rod 1, ball 3, cylindrical 4, hinge 5, weld 6: the talk's joint sizes.
    static constexpr std::array<int, 5> kRows = {1, 3, 4, 5, 6};
    g_.joints.push_back({a, b, kRows[rng_() % kRows.size()]});
  }
  uint32_t next() { return rng_(); }
  BodyGraph done() { return std::move(g_); }

 private:
  std::mt19937 rng_;
  BodyGraph g_;
};

}  // namespace

std::span<const std::string_view> family_names() { return kFamilies; }

// Long (one branch of a few lines per family): the families side by side read as their catalogue.
BodyGraph make_family(std::string_view family, int m, uint32_t seed) {
  if (m < 1) throw InputError("mechanism family '" + std::string(family) + "': needs at least 1 constraint");
  check_limit("mechanism family '" + std::string(family) + "'", m, size_limits().constraints, "constraints");
  Builder b(seed);
  const int ground = b.body(true);
  if (family == "chain") {
    int prev = ground;
    for (int k = 0; k < m; ++k) {
      int next = b.body();
      b.joint(prev, next);
      prev = next;
    }
  } else if (family == "tree") {
    // Bodies attach to a random earlier body that has fewer than 3 children.
    std::vector<int> open = {ground}, children(m + 1, 0);
    for (int k = 0; k < m; ++k) {
      size_t pick = b.next() % open.size();
      int parent = open[pick];
      int child = b.body();
      b.joint(parent, child);
      if (++children[parent] == 3) {
        open[pick] = open.back();
        open.pop_back();
      }
      open.push_back(child);
    }
  } else if (family == "ladder") {
    // Rungs r: rail bodies L_r and R_r, joints L_{r-1}-L_r, R_{r-1}-R_r and the rung L_r-R_r;
    // three joints per rung, the first pair hung from the ground.
    int left = ground, right = ground;
    int count = 0;
    while (count < m) {
      int l = b.body();
      b.joint(left, l);
      if (++count == m) break;
      int r = b.body();
      b.joint(right, r);
      if (++count == m) break;
      b.joint(l, r);
      ++count;
      left = l;
      right = r;
    }
  } else if (family == "loop") {
    // A closed track: m bodies in a ring, m joints; one body pinned to the ground would make it
    // a structure, so the track floats, as a tank track does around its wheels. A ring needs two
    // links: a single constraint is one body hung from the ground.
    if (m == 1) {
      b.joint(ground, b.body());
      return b.done();
    }
    int first = b.body(), prev = first;
    for (int k = 1; k < m; ++k) {
      int next = b.body();
      b.joint(prev, next);
      prev = next;
    }
    b.joint(prev, first);
  } else if (family == "heavy") {
    // One heavy body and m light bodies, each joined to it: every pair of constraints shares
    // the heavy body, so H is dense (the talk's multi-wheeled vehicle before shattering).
    int hub = b.body();
    for (int k = 0; k < m; ++k) b.joint(hub, b.body());
  } else if (family == "grid") {
    // A w x w cloth of bodies, joints on grid edges, the top row pinned to the ground.
    int w = std::max(1, static_cast<int>(std::lround(std::sqrt(m / 2.0))));
    // Bodies are made when a joint first reaches them, so that a grid cut short by m leaves no
    // loose body behind.
    std::vector<int> made(w * w, -1);
    auto id_of = [&](int cell) { return made[cell] == -1 ? (made[cell] = b.body()) : made[cell]; };
    int count = 0;
    for (int r = 0; r < w && count < m; ++r) {
      for (int c = 0; c < w && count < m; ++c) {
        if (r == 0) { b.joint(ground, id_of(c)); ++count; }
        if (c > 0 && count < m) { b.joint(id_of(r * w + c - 1), id_of(r * w + c)); ++count; }
        if (r > 0 && count < m) { b.joint(id_of((r - 1) * w + c), id_of(r * w + c)); ++count; }
      }
    }
    // A small grid holds fewer edges than asked for: hang a tail chain off the last body.
    for (int prev = count < m ? id_of(w * w - 1) : -1; count < m; ++count) {
      int next = b.body();
      b.joint(prev, next);
      prev = next;
    }
  } else if (family == "star") {
    // A hub hung from the ground carrying about sqrt(m/2) arms (chains): the hub's constraints
    // form a clique, the arms are chains.
    int hub = b.body();
    b.joint(ground, hub);
    int arms = std::max(1, static_cast<int>(std::lround(std::sqrt(m / 2.0))));
    std::vector<int> tips(arms, hub);
    for (int count = 1, a = 0; count < m; ++count, a = (a + 1) % arms) {
      int next = b.body();
      b.joint(tips[a], next);
      tips[a] = next;
    }
  } else {
    throw InputError("unknown mechanism family '" + std::string(family) +
                     "' (chain, tree, ladder, loop, heavy, grid, star)");
  }
  return b.done();
}

}  // namespace ldlpgs
