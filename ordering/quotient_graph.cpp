// The quotient-graph elimination behind mda, mda-w, meca and meca-w (see quotient_graph.h for
// the structure and the degree bound). Written from the descriptions in Amestoy, Davis and Duff,
// "An approximate minimum degree ordering algorithm" (SIMAX 1996) and, for the fill score,
// Rothberg and Eisenstat, "Node selection strategies for bottom-up sparse matrix ordering"
// (SIMAX 1998), whose approximate minimum local fill subtracts from the pairs of the degree
// bound the pairs already joined by the newest element. We subtract the largest element among
// E_i instead (each element is a clique, so any one of them may be subtracted; the largest
// makes the bound tightest): a variable whose neighbours all lie in one element scores exactly
// 0. That alone does not see original edges among the neighbours (no block of the input graph
// looks simplicial), and left fill on trees; where the neighbourhood is small the fill is
// therefore counted exactly (exact_fill below), which restores meca's zero fill on chordal
// block graphs (tests/quotient_graph_test.cpp fails without it).
//
// Lists are std::vectors per variable and element rather than AMD's single workspace: simpler,
// and at 1e5 blocks not the bottleneck (bench/orderings_bench). The queue is a binary heap of the
// variables, indexed (VariableHeap below).
#include "ldlpgs/ordering/quotient_graph.h"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

namespace ldlpgs {

namespace {
enum Status : uint8_t { kVariable, kElement, kMerged, kAbsorbed };

// The variables, smallest key first: a binary heap of their ids with each one's place in it, so
// that a new key moves its variable up or down (a merged one stays until popped), and the heap
// never holds more than n ids, where a heap of (key, id) entries with stale ones skipped grew
// many times n. papers/orderings.md, "MDA and MECA on a quotient graph".
template <class Key>
class VariableHeap {
 public:
  explicit VariableHeap(const std::vector<Key>& key) : key_(key), place_(key.size(), -1) {
    heap_.reserve(key.size());
  }
  bool empty() const { return heap_.empty(); }
  // After key[i] changed, or to add i.
  void update(int i) {
    if (place_[i] < 0) {
      place_[i] = static_cast<int>(heap_.size());
      heap_.push_back(i);
    }
    down(up(place_[i]));
  }
  int pop() {
    const int top = heap_.front();
    place_[top] = -1;
    heap_.front() = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) {
      place_[heap_.front()] = 0;
      down(0);
    }
    return top;
  }

 private:
  bool less(int a, int b) const { return key_[heap_[a]] < key_[heap_[b]]; }
  void swap(int a, int b) {
    std::swap(heap_[a], heap_[b]);
    place_[heap_[a]] = a;
    place_[heap_[b]] = b;
  }
  int up(int k) {
    while (k > 0 && less(k, (k - 1) / 2)) {
      swap(k, (k - 1) / 2);
      k = (k - 1) / 2;
    }
    return k;
  }
  void down(int k) {
    const int size = static_cast<int>(heap_.size());
    for (int c = 2 * k + 1; c < size; k = c, c = 2 * k + 1) {
      if (c + 1 < size && less(c + 1, c)) ++c;
      if (!less(c, k)) return;
      swap(c, k);
    }
  }

  const std::vector<Key>& key_;
  std::vector<int> heap_;   // ids not yet popped, merged ones included (size at most n)
  std::vector<int> place_;  // place_[i]: i's index in heap_, or -1 (size n)
};
}  // namespace

std::vector<int> quotient_order(const BlockPattern& pattern, const QuotientOptions& opt,
                                std::vector<QuotientStep>* trace) {
  const int n = pattern.num_blocks();
  const Graph& graph = pattern.graph();
  std::vector<uint8_t> status(n, kVariable);  // what id i is now (size n)
  std::vector<std::vector<int>> adj(n);       // A_i: variables, original edges (size n)
  std::vector<std::vector<int>> elems(n);     // E_i: elements of variable i (size n)
  std::vector<std::vector<int>> members(n);   // L_e: variables of element e (size n)
  std::vector<Mass> mass(n);                  // variable: its blocks; element: live L_e
  std::vector<Mass> degree(n);                // d_i, the external degree bound (size n)
  std::vector<int64_t> heaviest(n);           // largest block weight in supervariable i
  std::vector<int> tie_index(n);              // the block index the tie rule reads (size n)
  std::vector<std::vector<int>> blocks(n);    // blocks merged into supervariable i (size n)
  Mass live;                                  // mass of all variables not yet eliminated
  for (int i = 0; i < n; ++i) {
    const int64_t w = opt.weighted ? pattern.block(i).size : 1;
    mass[i] = {1, w, w * w};
    heaviest[i] = w;
    tie_index[i] = i;
    blocks[i] = {i};
    live += mass[i];
    auto nb = graph.neighbors(i);
    adj[i].assign(nb.begin(), nb.end());
  }
  for (int i = 0; i < n; ++i) {
    for (int j : adj[i]) degree[i] += mass[j];
  }

  // Key: (score, secondary, tie, id), smallest first. The secondary is the block degree for
  // meca-w's least_degree rule; the tie index is negated for highest_index.
  using Key = std::tuple<int64_t, int64_t, int, int>;
  std::vector<Key> key(n);
  std::vector<int64_t> exact(n, -1);  // exact fill of i when known, else -1 (size n)
  std::vector<Mass> cover(n);  // the largest element mass among E_i, minus i's own (size n)
  auto make_key = [&](int i) {
    int64_t s;
    if (opt.score == QuotientScore::degree) {
      s = degree[i].w + mass[i].w - heaviest[i];
    } else if (exact[i] >= 0) {
      s = exact[i];
    } else {
      s = std::max<int64_t>(0, degree[i].pairs() - cover[i].pairs());
    }
    const int64_t secondary = opt.tie == TieBreak::least_degree ? degree[i].c + mass[i].c - 1 : 0;
    const int t = opt.tie == TieBreak::highest_index ? -tie_index[i] : tie_index[i];
    return Key{s, secondary, t, i};
  };
  // The exact fill of i, when its neighbourhood is small: for each neighbour u (a supervariable:
  // its blocks are pairwise adjacent, and adjacent to v in full or not at all), the weight of
  // the other neighbours it is not adjacent to. Gives up (returns -1) past `budget` list
  // entries read, so that a hub of a star or a clique keeps the approximation.
  std::vector<int> in_reach(n, 0), near(n, 0);  // stamps (size n)
  int reach_stamp = 0, near_stamp = 0;
  std::vector<int> reach;
  auto exact_fill = [&](int i, int64_t budget) -> int64_t {
    ++reach_stamp;
    in_reach[i] = reach_stamp;
    reach.clear();
    int64_t total = 0;
    auto add = [&](int v) {
      if (status[v] == kVariable && in_reach[v] != reach_stamp) {
        in_reach[v] = reach_stamp;
        reach.push_back(v);
        total += mass[v].w;
      }
    };
    for (int v : adj[i]) add(v);
    for (int e : elems[i]) {
      if (status[e] != kElement) continue;
      budget -= static_cast<int64_t>(members[e].size());
      for (int v : members[e]) add(v);
    }
    // What the count below reads, from the list lengths alone: a count that cannot afford it
    // gives up before reading its neighbours' lists, so that a failure costs the lengths, not the
    // budget (the same counts succeed; papers/orderings.md, "Short lists: the second exact tier").
    for (int u : reach) {
      budget -= static_cast<int64_t>(adj[u].size());
      for (int e : elems[u]) {
        if (status[e] == kElement) budget -= static_cast<int64_t>(members[e].size());
      }
      if (budget < 0) return -1;
    }
    int64_t twice_fill = 0;
    for (int u : reach) {
      ++near_stamp;
      near[u] = near[i] = near_stamp;  // neither u nor i is a neighbour u may miss
      int64_t adjacent = 0;
      auto see = [&](int v) {
        if (in_reach[v] == reach_stamp && near[v] != near_stamp && status[v] == kVariable) {
          near[v] = near_stamp;
          adjacent += mass[v].w;
        }
      };
      for (int v : adj[u]) see(v);
      for (int e : elems[u]) {
        if (status[e] == kElement) {
          for (int v : members[e]) see(v);
        }
      }
      twice_fill += mass[u].w * (total - mass[u].w - adjacent);
    }
    return twice_fill / 2;
  };
  // Scores by exact_fill below this many blocks of degree bound, and this many list entries
  // read: without it no block is simplicial until an element covers it, and meca leaves fill
  // on trees. The pair trades meca's distance to meca-exact against ordering time
  // (papers/orderings.md, "MDA and MECA on a quotient graph").
  constexpr int64_t kExactDegree = 16, kExactBudget = 1024;
  // Past that degree a block is still counted exactly when its lists are short: at most
  // kShortLists entries in A_i and the L_e of E_i (their lengths; merged and eliminated ids in
  // an L_e count too), and at most kShortBudget entries of the L_e and the neighbours' lists
  // read. A grid's late blocks are such (dozens of blocks in a few supervariables), which the
  // first tier left well above meca-exact. A count that runs out of budget is not tried again
  // until the block's degree bound falls below the degree it failed at (failed_at), so that a
  // block read in vain costs once; nor is one whose lists were too long. (A heuristic: the bound
  // may grow again, and lists shrink as elements are absorbed, so a block may stay approximate
  // after it became cheap to count.) papers/orderings.md, "Short lists: the second exact tier".
  constexpr int64_t kShortLists = 32, kShortBudget = 256;
  std::vector<int64_t> failed_at(n, INT64_MAX);  // degree bound at the last failed count (size n)
  auto try_exact = [&](int i) -> int64_t {
    if (degree[i].c <= kExactDegree) return exact_fill(i, kExactBudget);
    if (degree[i].c >= failed_at[i]) return -1;
    int64_t lists = static_cast<int64_t>(adj[i].size());
    for (size_t k = 0; k < elems[i].size() && lists <= kShortLists; ++k) {
      if (status[elems[i][k]] == kElement) lists += static_cast<int64_t>(members[elems[i][k]].size());
    }
    const int64_t f = lists <= kShortLists ? exact_fill(i, kShortBudget) : -1;
    if (f < 0) failed_at[i] = degree[i].c;
    return f;
  };
  auto rescore = [&](int i) { exact[i] = opt.score == QuotientScore::fill ? try_exact(i) : -1; };

  std::vector<int> touched;      // blocks outside L_p next to it, this step
  std::vector<int> last_i(n, 0);  // stamp: counted for the current block of L_p (size n)
  std::vector<Mass> in_lp(n);     // of a touched block: its neighbours in L_p (size n)
  int i_stamp = 0;
  VariableHeap<Key> heap(key);
  auto rekey = [&](int i) {
    key[i] = make_key(i);
    heap.update(i);
  };
  for (int i = 0; i < n; ++i) {
    rescore(i);
    rekey(i);
  }

  std::vector<int> pivots;
  pivots.reserve(n);
  std::vector<int> lp;                 // L_p of the current pivot
  std::vector<int> mark(n, 0);         // stamp: in L_p, or entry of a list being compared
  std::vector<int> seen(n, 0);         // stamp: element whose |L_e \ L_p| is being counted
  std::vector<Mass> outside(n);        // |L_e \ L_p| for e seen this step (size n)
  std::vector<uint64_t> hash(n);       // of A_i and E_i, for supervariable detection
  std::vector<std::pair<uint64_t, int>> by_hash;
  int stamp = 0;
  while (!heap.empty()) {
    const int p = heap.pop();
    if (status[p] != kVariable) continue;  // merged into a supervariable

    // Output p's blocks in the order the exact game would take them: all of them have the same
    // neighbours, so the tie rule (and for mda-w the heaviest block, of least degree) decides.
    std::vector<int>& bp = blocks[p];
    std::sort(bp.begin(), bp.end(), [&](int a, int b) {
      if (opt.score == QuotientScore::degree && opt.weighted && pattern.block(a).size != pattern.block(b).size)
        return pattern.block(a).size > pattern.block(b).size;
      return opt.tie == TieBreak::highest_index ? a > b : a < b;
    });
    pivots.insert(pivots.end(), bp.begin(), bp.end());
    live -= mass[p];

    // L_p = (A_p u union of L_e over e in E_p) minus p; the elements of E_p are absorbed.
    ++stamp;
    mark[p] = stamp;
    lp.clear();
    Mass lp_mass;
    auto take = [&](int j) {
      if (status[j] == kVariable && mark[j] != stamp) {
        mark[j] = stamp;
        lp.push_back(j);
        lp_mass += mass[j];
      }
    };
    for (int e : elems[p]) {
      for (int j : members[e]) take(j);
      status[e] = kAbsorbed;
      std::vector<int>().swap(members[e]);
    }
    for (int j : adj[p]) take(j);
    status[p] = kElement;
    std::vector<int>().swap(adj[p]);
    std::vector<int>().swap(elems[p]);
    mass[p] = lp_mass;

    // |L_e \ L_p| for every element e adjacent to L_p: |L_e| minus the variables of L_p in it.
    const int lp_stamp = stamp;
    for (int i : lp) {
      for (int e : elems[i]) {
        if (status[e] != kElement) continue;
        if (seen[e] != lp_stamp) {
          seen[e] = lp_stamp;
          outside[e] = mass[e];
        }
        outside[e] -= mass[i];
      }
    }

    // Update each i in L_p: drop absorbed elements (and, aggressively, those inside L_p), add p;
    // drop from A_i what element p now covers; bound the degree; hash the lists.
    for (int i : lp) {
      Mass external;
      uint64_t h = static_cast<uint64_t>(p);
      size_t k = 0;
      for (int e : elems[i]) {
        if (status[e] != kElement) continue;
        if (outside[e].c == 0) {  // L_e is inside L_p: p absorbs it
          status[e] = kAbsorbed;
          std::vector<int>().swap(members[e]);
          continue;
        }
        external += outside[e];
        h += static_cast<uint64_t>(e);
        elems[i][k++] = e;
      }
      elems[i].resize(k);
      elems[i].push_back(p);
      k = 0;
      for (int j : adj[i]) {
        if (status[j] != kVariable || mark[j] == lp_stamp) continue;
        external += mass[j];
        h += static_cast<uint64_t>(j);
        adj[i][k++] = j;
      }
      adj[i].resize(k);
      const Mass rest = lp_mass - mass[i];
      const Mass bound = external + rest, grown = degree[i] + rest, all = live - mass[i];
      degree[i] = {std::min({bound.c, grown.c, all.c}), std::min({bound.w, grown.w, all.w}),
                   std::min({bound.q, grown.q, all.q})};
      hash[i] = h;
    }

    // Supervariables: variables of L_p with equal hash, then equal lists, are indistinguishable.
    by_hash.clear();
    for (int i : lp) by_hash.emplace_back(hash[i], i);
    std::sort(by_hash.begin(), by_hash.end());
    for (size_t a = 0; a < by_hash.size(); ++a) {
      const int i = by_hash[a].second;
      if (status[i] != kVariable) continue;
      bool marked = false;
      for (size_t b = a + 1; b < by_hash.size() && by_hash[b].first == by_hash[a].first; ++b) {
        const int j = by_hash[b].second;
        if (status[j] != kVariable || adj[j].size() != adj[i].size() || elems[j].size() != elems[i].size()) continue;
        if (!marked) {
          ++stamp;
          for (int x : adj[i]) mark[x] = stamp;
          for (int x : elems[i]) mark[x] = stamp;
          marked = true;
        }
        bool same = true;
        for (int x : adj[j]) same = same && mark[x] == stamp;
        for (int x : elems[j]) same = same && mark[x] == stamp;
        if (!same) continue;
        // j joins i: i's external degree no longer counts j.
        degree[i] -= mass[j];
        mass[i] += mass[j];
        // The tie rule reads the block the exact game would take first: any of i's for a degree
        // that all its blocks share, but for mda-w's weighted degree (the rest of the
        // supervariable counts, the block itself does not) one of its heaviest blocks.
        const bool by_weight = opt.score == QuotientScore::degree && opt.weighted && heaviest[i] != heaviest[j];
        if (by_weight) {
          if (heaviest[j] > heaviest[i]) tie_index[i] = tie_index[j];
        } else {
          tie_index[i] = opt.tie == TieBreak::highest_index ? std::max(tie_index[i], tie_index[j])
                                                           : std::min(tie_index[i], tie_index[j]);
        }
        heaviest[i] = std::max(heaviest[i], heaviest[j]);
        blocks[i].insert(blocks[i].end(), blocks[j].begin(), blocks[j].end());
        std::vector<int>().swap(blocks[j]);
        std::vector<int>().swap(adj[j]);
        std::vector<int>().swap(elems[j]);
        status[j] = kMerged;  // (left in the heap: popped and skipped, cheaper than taken out)
      }
    }

    // Element p keeps its live variables; new keys for them.
    size_t k = 0;
    for (int i : lp) {
      if (status[i] == kVariable) lp[k++] = i;
    }
    lp.resize(k);
    members[p] = lp;
    QuotientStep* step = nullptr;
    if (trace) {
      trace->push_back({bp, {}});
      step = &trace->back();
    }
    for (int i : lp) {
      if (opt.score == QuotientScore::fill) {
        Mass best;
        for (int e : elems[i]) {
          const Mass m = mass[e] - mass[i];
          if (m.pairs() > best.pairs()) best = m;
        }
        cover[i] = best;
        rescore(i);
      }
      rekey(i);
      if (step) {
        for (int b : blocks[i]) step->degrees.emplace_back(b, degree[i].c + mass[i].c - 1);
      }
    }
    // Blocks outside L_p next to two or more of it may have lost fill (the new edges of L_p's
    // clique join some of their neighbours): rescore those that the exact count can afford,
    // reached by original edges and small elements, as the exact game lowers them.
    // A pivot known to be simplicial (exact fill 0) created no edge, and a block next to only
    // one block of L_p gained no edge among its neighbours: both are skipped.
    // For meca, a block too large to count keeps its approximate score, but its neighbours in
    // L_p are now a clique: where they outweigh its cover (the largest element), they become it
    // (not for meca-w, where it measured worse: papers/orderings.md, "MDA and MECA on a quotient
    // graph").
    if (opt.score == QuotientScore::fill && exact[p] != 0) {
      ++stamp;
      for (int i : lp) mark[i] = stamp;
      mark[p] = stamp;
      touched.clear();
      for (int i : lp) {
        ++i_stamp;
        auto visit = [&](int x) {
          if (status[x] != kVariable || mark[x] == stamp || last_i[x] == i_stamp) return;
          last_i[x] = i_stamp;
          if (seen[x] != stamp) {  // (seen[] is free for variables)
            seen[x] = stamp;
            in_lp[x] = Mass{};
            touched.push_back(x);
          }
          in_lp[x] += mass[i];
        };
        for (int x : adj[i]) visit(x);
        for (int e : elems[i]) {
          if (e != p && static_cast<int64_t>(members[e].size()) <= kExactDegree) {
            for (int x : members[e]) visit(x);
          }
        }
      }
      for (int x : touched) {
        if (in_lp[x].c < 2) continue;
        const int64_t f = try_exact(x);
        if (f >= 0 && f != exact[x]) {
          exact[x] = f;
          rekey(x);
        }
        if (f < 0 && !opt.weighted && exact[x] < 0 && in_lp[x].pairs() > cover[x].pairs()) {
          cover[x] = in_lp[x];
          rekey(x);
        }
      }
    }
    std::vector<int>().swap(bp);
  }
  assert(static_cast<int>(pivots.size()) == n);
  return pivots;
}

}  // namespace ldlpgs
