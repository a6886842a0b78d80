// The least block flops of any elimination order (certify.h). Cost of eliminating block v of d
// rows whose neighbours at that moment hold h rows: f(d, h) = d(d+1)(2d+1)/6 + h d(d+1) + d h^2
// (metrics.h), increasing in h.
//
// 0. Flops are a function of the filled graph. The block flops equal CHOLMOD's fl of the scalar
//    matrix with dense blocks, sum over scalar columns of (h_j + 1)^2 (metrics.h), and since
//    sum_j h_j = E and sum_j h_j^2 = 2T + E, they are n + 3E + 2T, with E the edges and T the
//    triangles of the scalar filled graph H (chordal; the order is a perfect elimination order
//    of it: each triangle is counted once, at its first vertex). So OPT(G) = min over chordal
//    H containing G of n + 3E(H) + 2T(H): a triangulation's cost grows with its edges, and any
//    perfect elimination order of H eliminates G with a filled graph inside H.
// 1. Peeling. If v is simplicial (its neighbours pairwise adjacent), some optimal order
//    eliminates v first: OPT(G) = f(d_v, w(N(v))) + OPT(G - v). Usually stated for fill;
//    for block flops it follows from 0 (a triangulation of G - v plus v is one of G, with no
//    more edges), or directly: take any order pi, and pi' = v first, then pi without v. A fill
//    path of G - v is one of G, so every u != v has in pi' a subset of its pi neighbourhood,
//    without v: h'(u) <= h(u), and h'(u) <= h(u) - d_v for u in A = the neighbours of v
//    eliminated before v in pi. With A = a_1 .. a_m in pi order and B = N(v) \ A, a_i sees v,
//    a_{>i} and B (N(v) is a clique): h(a_i) >= d_v + w(a_{>i}) + w(B), and pi' saves on A
//    sum_i d_v d_ai (d_ai + 1 + 2 h(a_i) - d_v) >= d_v (w(A) + d_v w(A) + w(A)^2 + 2 w(A) w(B)),
//    exactly what v pays more in pi', f(d_v, w(A) + w(B)) - f(d_v, w(B)).
//    Removing simplicial blocks until none is left empties the graph exactly when it is chordal
//    (Fulkerson and Gross 1965; the removal order is a perfect elimination order), so this is
//    also the chordality test: a chordal block graph is solved by peeling alone, at zero fill.
// 2. Clique separators. If a clique C separates G into G1 and G2 (G1 n G2 = C, no edge between
//    G1 - C and G2 - C), OPT(G) = OPT(G1) + OPT(G2) - cost(C), cost(C) = the flops of C alone
//    (dense). By 0: a triangulation H of G contains H[G1] and H[G2], triangulations of G1 and
//    G2 whose union, glued along the clique C, is chordal, no larger than H, and costs by
//    n + 3E + 2T the sum of theirs less C's (every clique of the union lies in G1 or G2, those
//    in C counted twice); and gluing optimal triangulations of G1 and G2 gives one of G. So the
//    rule known for fill holds for block flops, with the separator's own cost subtracted. The
//    separators come from Tarjan's decomposition (1985) over a minimal elimination ordering from
//    MCS-M (Berry, Blair, Heggernes, Peyton 2004); each is checked to be a separating clique
//    before it is used, so a separator the method misses costs time, not correctness.
// 3. Connected sets. The blocks reachable from v through eliminated blocks lie in v's component
//    of the eliminated set, so eliminating a set S first costs F(S) = sum over the components C
//    of G[S] of F(C), and, for C connected, with N(C) its neighbours outside C:
//      F(C) = min over v in C of f(d_v, w(N(C))) + F(C - v)
//    (the last of C sees all of N(C) through C). Memoised on C: a dynamic programme over the
//    connected sets of each atom, OPT(atom) = F(atom), searched as a branch and bound below the
//    cost of a known order (the best ordering's, restricted to the atom), with the bound of 4 on
//    each connected set, sharpened by its last block paying f(d_v, w(N(C))).
// 4. Lower bounds. An atom the search does not finish within the time limit (or the memo cap)
//    counts n + 3E + 2T of its own scalar graph, the cost of a zero-fill order if it had one
//    (0: every triangulation contains G). Inside the search, for a connected set C, block v sees
//    at least its neighbours outside C and its neighbours in C eliminated after it; each edge
//    (u, v) inside C adds d_u d_v (d_u + d_v + 1) whichever of the two goes first.
// tests/ordering/certify_test.cpp checks all of it against brute force over every order of small graphs.
#include "ldlpgs/ordering/certify.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

namespace {

// A search past the time limit or the memo cap stops by throwing this, caught per component.
struct OutOfBudget {};

using Clock = std::chrono::steady_clock;
using Set = uint64_t;  // bit v: block v of the component (components of at most 64 blocks)

// The filled graph of `pivots` on the graph `adj` (bit sets): adj and the game's fill edges.
std::vector<Set> filled_graph(std::vector<Set> adj, std::span<const int> pivots) {
  Set alive = ~Set{0};
  for (int v : pivots) {
    alive &= ~(Set{1} << v);
    const Set later = adj[v] & alive;  // v's neighbours when it goes: made a clique
    for (Set m = later; m; m &= m - 1) adj[std::countr_zero(m)] |= later & ~(Set{1} << std::countr_zero(m));
  }
  return adj;
}

// The exact search on one connected component of the peeled graph, its blocks numbered 0..k-1,
// k <= 64, as a branch and bound: solve(C, budget) returns F(C) when F(C) < budget, and
// otherwise some value >= budget that F(C) is not below. The memo keeps either kind.
class ConnectedSetSearch {
 public:
  ConnectedSetSearch(std::vector<Set> adj, std::vector<int> size, Clock::time_point deadline)
      : adj_(std::move(adj)), size_(std::move(size)), deadline_(deadline) {}

  double solve_all(double budget) {
    const Set all = adj_.size() == 64 ? ~Set{0} : (Set{1} << adj_.size()) - 1;
    return solve(all, budget);
  }
  int64_t states() const { return static_cast<int64_t>(memo_.size()); }

  // An order of C reaching F(C), read back from the memo: C's entry must be exact (else false).
  // A branch that set F(C) left exact entries for all its parts (solve returns a value below a
  // part's budget only from an exact entry, and exact entries are never replaced), so the
  // block whose branch sums to F(C) goes last, after its parts' orders. The sum is redone in
  // solve's order (f, then the parts lowest block first): integers below 2^53, equal exactly.
  bool order_of(Set c, std::vector<int>* out) const {
    const auto it = memo_.find(c);
    if (it == memo_.end() || !it->second.exact) return false;
    if (std::popcount(c) == 1) {
      out->push_back(std::countr_zero(c));
      return true;
    }
    const int64_t w = rows(neighbours(c));
    for (Set m = c; m; m &= m - 1) {
      const int last = std::countr_zero(m);
      double cost = block_pivot_flops(size_[last], w);
      std::vector<Set> parts;
      bool known = true;
      for (Set left = c & ~(Set{1} << last); left && known;) {
        const Set part = component(left);
        const auto p = memo_.find(part);
        known = p != memo_.end() && p->second.exact;
        if (known) cost += p->second.value;
        parts.push_back(part);
        left &= ~part;
      }
      if (!known || cost != it->second.value) continue;
      for (Set part : parts)
        if (!order_of(part, out)) return false;
      out->push_back(last);
      return true;
    }
    return false;
  }
  bool order_all(std::vector<int>* out) const {
    return order_of(adj_.size() == 64 ? ~Set{0} : (Set{1} << adj_.size()) - 1, out);
  }

  // Block flops of `pivots` (component numbering) played as the elimination game.
  double cost_of(const std::vector<int>& pivots) const {
    const std::vector<Set> filled = filled_graph(adj_, pivots);
    Set alive = ~Set{0};
    double total = 0;
    for (int v : pivots) {  // v sees its filled neighbours eliminated after it
      alive &= ~(Set{1} << v);
      total += block_pivot_flops(size_[v], rows(filled[v] & alive));
    }
    return total;
  }

 private:
  struct Entry {
    double value;
    bool exact;  // value = F(C); otherwise F(C) >= value
  };
  // Memo entries at most: about 50 bytes each in the hash table, so 200 MB.
  static constexpr size_t kMaxStates = 4'000'000;

  int64_t rows(Set s) const {
    int64_t r = 0;
    for (; s; s &= s - 1) r += size_[std::countr_zero(s)];
    return r;
  }
  Set neighbours(Set s) const {
    Set n = 0;
    for (Set m = s; m; m &= m - 1) n |= adj_[std::countr_zero(m)];
    return n & ~s;
  }
  // The component of `s` holding its lowest block.
  Set component(Set s) const {
    Set c = s & (~s + 1), grown = c;
    while (grown) {
      const Set add = neighbours(grown) & s & ~c;
      c |= add;
      grown = add;
    }
    return c;
  }

  // Two lower bounds on F(C), the larger. (a) (4. above, with the boundary) block v sees at
  // least its neighbours outside C and its neighbours in C eliminated after it; each edge
  // inside C adds d_u d_v (d_u + d_v + 1); and the last block of C sees all of N(C) (w rows).
  // (b) By 0., F(C) is the cost, less the clique N(C)'s own, of a chordal graph containing
  // G[C + N(C)] with N(C) made a clique: n + 3E + 2T over the scalar vertices, edges and
  // triangles of that graph that touch C (blocks: f(d_v, 0) each, d_u d_v (d_u + d_v + 1) per
  // edge, 2 d_u d_v d_x per triangle, those with two corners in N(C) included).
  double lower_bound(Set c, int64_t w) const {
    double lb = 0, last = std::numeric_limits<double>::infinity(), chordal = 0;
    const Set boundary = neighbours(c);
    for (Set m = c; m; m &= m - 1) {
      const int v = std::countr_zero(m);
      const int64_t dv = size_[v];
      const double own = block_pivot_flops(dv, rows(adj_[v] & ~c));
      lb += own;
      last = std::min(last, block_pivot_flops(dv, w) - own);
      chordal += block_pivot_flops(dv, 0);
      const Set later = ~((Set{2} << v) - 1);  // blocks after v
      // each edge touching C once: inside C at its first end, to N(C) at its end in C
      for (Set e = adj_[v] & ((c & later) | boundary); e; e &= e - 1) {
        const int u = std::countr_zero(e);
        const int64_t du = size_[u];
        const double edge = static_cast<double>(du * dv * (du + dv + 1));
        chordal += edge;
        // each triangle v u x once: x after u in C or anywhere in N(C) for u in C (one or two
        // corners in C); x after u in N(C) for u in N(C) (v its only corner in C)
        const Set after_u = ~((Set{2} << u) - 1);
        Set third = 0;
        if ((c >> u) & 1) {
          lb += edge;
          third = adj_[v] & adj_[u] & ((c & after_u) | boundary);
        } else {
          third = adj_[v] & boundary & after_u;
        }
        for (Set t = third; t; t &= t - 1) chordal += 2.0 * static_cast<double>(dv * du * size_[std::countr_zero(t)]);
      }
    }
    return std::max(lb + last, chordal);
  }

  double solve(Set c, double budget) {
    const auto it = memo_.find(c);
    if (it != memo_.end() && (it->second.exact || it->second.value >= budget)) return it->second.value;
    if (memo_.size() >= kMaxStates || ((++calls_ & 1023) == 0 && Clock::now() > deadline_)) throw OutOfBudget{};
    const int64_t w = rows(neighbours(c));
    double best = std::numeric_limits<double>::infinity();
    if (std::popcount(c) == 1) {
      best = block_pivot_flops(size_[std::countr_zero(c)], w);
    } else {
      const double lb = lower_bound(c, w);
      if (lb >= budget) {
        memo_[c] = {lb, false};
        return lb;
      }
      // Every block of C as the last of C; the others as the components they leave. The
      // branches go in the order of their bounds, so that a good one soon caps the others.
      struct Branch {
        double bound;              // f(d_last, w) + the parts' bounds
        int last;
        std::vector<Set> parts;    // components of C - last
        std::vector<double> bounds;  // a lower bound of each part (the memo's, or lower_bound)
      };
      std::vector<Branch> branches;
      for (Set m = c; m; m &= m - 1) {
        Branch b{block_pivot_flops(size_[std::countr_zero(m)], w), std::countr_zero(m), {}, {}};
        for (Set left = c & ~(Set{1} << b.last); left;) {
          const Set part = component(left);
          const auto known = memo_.find(part);
          double lb = known != memo_.end() ? known->second.value : 0;
          if (known == memo_.end() || !known->second.exact) lb = std::max(lb, lower_bound(part, rows(neighbours(part))));
          b.parts.push_back(part);
          b.bounds.push_back(lb);
          b.bound += lb;
          left &= ~part;
        }
        branches.push_back(std::move(b));
      }
      std::sort(branches.begin(), branches.end(), [](const Branch& x, const Branch& y) { return x.bound < y.bound; });
      double floor = std::numeric_limits<double>::infinity();  // least lower value of a cut branch
      for (const Branch& br : branches) {
        const std::vector<Set>& parts = br.parts;
        const std::vector<double>& bounds = br.bounds;
        const double cap = std::min(best, budget);
        double cost = block_pivot_flops(size_[br.last], w);
        double pending = br.bound - cost;
        bool cut = cost + pending >= cap;
        for (size_t i = 0; i < parts.size() && !cut; ++i) {
          pending -= bounds[i];
          const double sub_budget = cap - cost - pending;
          const double v = solve(parts[i], sub_budget);
          cost += v;
          cut = v >= sub_budget;
        }
        if (cut) {
          floor = std::min(floor, std::max(cost + pending, cap));
        } else {
          best = std::min(best, cost);
        }
      }
      if (best >= budget) {
        memo_[c] = {std::min(best, floor), false};
        return std::min(best, floor);
      }
    }
    memo_[c] = {best, true};
    return best;
  }

  std::vector<Set> adj_;  // neighbours within the component (size k)
  std::vector<int> size_; // rows of each block (size k)
  Clock::time_point deadline_;
  int64_t calls_ = 0;
  std::unordered_map<Set, Entry> memo_;
};

// Scalar n + 3E + 2T (0. above) of the block graph induced on the blocks flagged in `in`: the
// block flops of a zero-fill order, a lower bound for any order (4.).
double zero_fill_flops(const std::vector<std::vector<int>>& adj, std::span<const int> size,
                       std::span<const int> members, std::vector<uint8_t>& in) {
  double total = 0;
  for (int v : members) {
    const int64_t dv = size[v];
    total += block_pivot_flops(dv, 0);  // the block's own clique: sum of c^2, c = 1..d
    for (int u : adj[v]) {
      if (!in[u] || u < v) continue;
      const int64_t du = size[u];
      total += static_cast<double>(dv * du * (dv + du + 1));  // 3 d_v d_u edges, the triangles in v u
      for (int x : adj[u])  // triangles v u x of the block graph, x > u, adjacent to both
        if (in[x] && x > u && std::binary_search(adj[v].begin(), adj[v].end(), x))
          total += 2.0 * static_cast<double>(dv * du * size[x]);
    }
  }
  return total;
}

// The block flops of C as a dense clique alone (2.): the same in every order.
double clique_flops(Set c, std::span<const int> size) {
  int64_t rows = 0;
  for (Set m = c; m; m &= m - 1) rows += size[std::countr_zero(m)];
  double total = 0;
  for (Set m = c; m; m &= m - 1) {
    rows -= size[std::countr_zero(m)];
    total += block_pivot_flops(size[std::countr_zero(m)], rows);
  }
  return total;
}

// MCS-M (Berry, Blair, Heggernes, Peyton 2004) on a connected graph of at most 64 blocks: a
// minimal elimination ordering, in `order` (eliminated first to last), and for each block its
// higher neighbours in the filled graph (madj, size k). The block numbered next is the one of
// largest weight; it raises the weight of, and is joined in the filled graph to, each unnumbered
// u reachable through unnumbered blocks of weight below u's.
void mcs_m(const std::vector<Set>& adj, std::vector<int>* order, std::vector<Set>* madj) {
  const int k = static_cast<int>(adj.size());
  std::vector<int> weight(k, 0);
  order->assign(k, -1);
  madj->assign(k, 0);
  Set unnumbered = k == 64 ? ~Set{0} : (Set{1} << k) - 1;
  for (int i = k - 1; i >= 0; --i) {
    int v = -1;
    for (Set m = unnumbered; m; m &= m - 1)
      if (v == -1 || weight[std::countr_zero(m)] > weight[v]) v = std::countr_zero(m);
    (*order)[i] = v;
    unnumbered &= ~(Set{1} << v);
    Set reached = 0;
    for (Set m = unnumbered; m; m &= m - 1) {
      const int u = std::countr_zero(m);
      Set allowed = 0;  // interior blocks a path to u may use
      for (Set a = unnumbered; a; a &= a - 1)
        if (weight[std::countr_zero(a)] < weight[u]) allowed |= Set{1} << std::countr_zero(a);
      Set seen = adj[v] & allowed, frontier = seen;
      bool found = (adj[v] >> u) & 1;
      while (!found && frontier) {
        Set next = 0;
        for (Set f = frontier; f; f &= f - 1) next |= adj[std::countr_zero(f)];
        found = (next >> u) & 1;
        frontier = next & allowed & ~seen;
        seen |= frontier;
      }
      if (found) reached |= Set{1} << u;
    }
    for (Set m = reached; m; m &= m - 1) {
      ++weight[std::countr_zero(m)];
      (*madj)[std::countr_zero(m)] |= Set{1} << v;
    }
  }
}

// Tarjan's decomposition by clique separators (1985) of a connected graph of at most 64 blocks:
// in the minimal elimination order, the higher neighbours C of u, when a clique of G, split off
// the component of G - C holding u, with C, as an atom. Returns the atoms and the separators
// between them (one fewer).
void clique_atoms(const std::vector<Set>& adj, std::vector<Set>* atoms, std::vector<Set>* separators) {
  std::vector<int> order;
  std::vector<Set> madj;
  mcs_m(adj, &order, &madj);
  Set rest = adj.size() == 64 ? ~Set{0} : (Set{1} << adj.size()) - 1;
  for (int u : order) {
    const Set c = madj[u];
    if (!((rest >> u) & 1) || (c & ~rest) != 0) continue;
    bool clique = true;
    for (Set m = c; m && clique; m &= m - 1) {
      const int x = std::countr_zero(m);
      clique = (c & ~(Set{1} << x) & ~adj[x]) == 0;
    }
    if (!clique) continue;
    Set b = Set{1} << u, grown = b;  // the component of G[rest - C] holding u
    while (grown) {
      Set next = 0;
      for (Set g = grown; g; g &= g - 1) next |= adj[std::countr_zero(g)];
      grown = next & rest & ~c & ~b;
      b |= grown;
    }
    if ((b | c) == rest) continue;
    atoms->push_back(b | c);
    separators->push_back(c);
    rest &= ~b;
  }
  atoms->push_back(rest);
}

}  // namespace

std::optional<Ordering> certificate_ordering(const BlockPattern& pattern, const BlockFlopsCertificate& cert,
                                             double fewest_known) {
  if (cert.pivots.empty() || !(cert.lower_bound < fewest_known)) return std::nullopt;
  Ordering o;
  o.name = "optimal";
  o.chosen = "certify";
  o.level = Level::block;
  o.pivots = cert.pivots;
  o.perm = expand_pivots(pattern, o.pivots);
  o.elimination = eliminate(pattern, o.pivots);
  o.time_ms = cert.time_ms;
  return o;
}

double zero_fill_block_flops(const BlockPattern& pattern) {
  const int nb = pattern.num_blocks();
  std::vector<std::vector<int>> adj(nb);  // (size nb)
  for (int v = 0; v < nb; ++v) adj[v].assign(pattern.neighbors(v).begin(), pattern.neighbors(v).end());
  std::vector<int> all(nb);
  std::iota(all.begin(), all.end(), 0);
  std::vector<uint8_t> in(nb, 1);
  return zero_fill_flops(adj, pattern.block_sizes(), all, in);
}

// Long: the proof's steps in order (1. peeling, 2. atoms, 3. search, 4. bound, then the order), sharing graph and deadline.
BlockFlopsCertificate certify_block_flops(const BlockPattern& pattern, double time_limit_s, std::span<const int> pivots) {
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(time_limit_s));
  BlockFlopsCertificate cert;
  const int nb = pattern.num_blocks();
  // The known order caps the search (F >= its cost is read as F = its cost): it must be one.
  if (!pivots.empty()) check_permutation(pivots, nb, "certify_block_flops (pivots)");
  const std::vector<int> size = pattern.block_sizes();
  std::vector<std::vector<int>> adj(nb);  // live neighbours, ascending (size nb)
  for (int v = 0; v < nb; ++v) adj[v].assign(pattern.neighbors(v).begin(), pattern.neighbors(v).end());
  std::vector<uint8_t> removed(nb, 0);
  std::vector<int> mark(nb, -1);
  auto rows_of = [&](const std::vector<int>& list) {
    int64_t rows = 0;
    for (int u : list) rows += size[u];
    return rows;
  };
  auto simplicial = [&](int v) {
    for (int u : adj[v]) mark[u] = v;
    for (int u : adj[v]) {
      size_t common = 0;
      for (int x : adj[u]) common += mark[x] == v;
      if (common + 1 != adj[v].size()) return false;
    }
    return true;
  };
  // An order reaching the optimum, while one is known: the peeled blocks in peeling order (1.),
  // then each component in a perfect elimination order of the union of its atoms' optimal
  // filled graphs, chordal as cliques glue them (2.), which no order of G fills beyond, so that
  // its flops are at most the sum of the atoms' less the separators': the optimum.
  std::vector<int> optimal;  // (size nb when complete)
  bool order_read = true;    // every atom's optimal order was read back
  // 1. Peeling, until no block is simplicial: a removal can make only its neighbours simplicial.
  double exact = 0;
  std::vector<int> queue(nb);
  for (int v = 0; v < nb; ++v) queue[v] = nb - 1 - v;
  std::vector<uint8_t> queued(nb, 1);
  while (!queue.empty()) {
    const int v = queue.back();
    queue.pop_back();
    queued[v] = 0;
    if (removed[v] || !simplicial(v)) continue;
    exact += block_pivot_flops(size[v], rows_of(adj[v]));
    removed[v] = 1;
    optimal.push_back(v);
    ++cert.peeled;
    for (int u : adj[v]) {
      adj[u].erase(std::lower_bound(adj[u].begin(), adj[u].end(), v));
      if (!queued[u]) {
        queued[u] = 1;
        queue.push_back(u);
      }
    }
    adj[v].clear();
  }
  cert.chordal = cert.peeled == nb;
  // The components of what remains: atoms (2.), each searched exactly (3.) or bounded (4.).
  bool all_exact = true;
  std::vector<int> local(nb, -1);  // a block's index in its component (size nb)
  std::vector<uint8_t> in(nb, 0);  // flags the blocks of the atom being bounded (size nb)
  auto bound_of = [&](std::span<const int> members) {
    for (int v : members) in[v] = 1;
    const double b = zero_fill_flops(adj, size, members, in);
    for (int v : members) in[v] = 0;
    return b;
  };
  for (int root = 0; root < nb; ++root) {
    if (removed[root] || local[root] != -1) continue;
    std::vector<int> comp = {root};  // its blocks, local index -> block
    local[root] = 0;
    for (size_t i = 0; i < comp.size(); ++i) {
      for (int u : adj[comp[i]]) {
        if (local[u] == -1) {
          local[u] = static_cast<int>(comp.size());
          comp.push_back(u);
        }
      }
    }
    if (comp.size() > 64) {
      all_exact = false;
      exact += bound_of(comp);
      continue;
    }
    const int k = static_cast<int>(comp.size());
    std::vector<Set> cadj(k, 0);
    std::vector<int> csize(k);
    for (int i = 0; i < k; ++i) {
      csize[i] = size[comp[i]];
      for (int u : adj[comp[i]]) cadj[i] |= Set{1} << local[u];
    }
    std::vector<Set> atoms, separators;
    clique_atoms(cadj, &atoms, &separators);
    std::vector<Set> filled(k, 0);  // union of the atoms' optimal filled graphs (size k)
    cert.atoms += static_cast<int>(atoms.size());
    for (Set c : separators) exact -= clique_flops(c, csize);
    for (Set atom : atoms) {
      std::vector<int> at(k, -1), members;  // local index -> index in the atom; the atom's blocks
      for (Set m = atom; m; m &= m - 1) {
        at[std::countr_zero(m)] = static_cast<int>(members.size());
        members.push_back(std::countr_zero(m));
      }
      std::vector<Set> aadj(members.size(), 0);
      std::vector<int> asize(members.size());
      for (size_t i = 0; i < members.size(); ++i) {
        asize[i] = csize[members[i]];
        for (Set m = cadj[members[i]] & atom; m; m &= m - 1) aadj[i] |= Set{1} << at[std::countr_zero(m)];
      }
      ConnectedSetSearch search(aadj, std::move(asize), deadline);
      // The given order restricted to the atom is an order of it: its cost bounds F above, and
      // the search need only look below it (F >= that cost then means F = that cost).
      double budget = std::numeric_limits<double>::infinity();
      std::vector<int> restricted;
      if (!pivots.empty()) {
        for (int v : pivots) {
          // (local[v] is -1 for a block of a component not reached yet)
          const bool here = !removed[v] && local[v] >= 0 && local[v] < k && comp[local[v]] == v && at[local[v]] != -1;
          if (here) restricted.push_back(at[local[v]]);
        }
        budget = search.cost_of(restricted);
      }
      try {
        const double value = search.solve_all(budget);
        exact += std::min(value, budget);
        std::vector<int> best;  // the atom's optimal order, atom numbering
        if (value >= budget) best = restricted;
        else if (!search.order_all(&best)) best.clear();
        if (best.size() == members.size()) {
          const std::vector<Set> f = filled_graph(aadj, best);
          for (size_t i = 0; i < members.size(); ++i)
            for (Set m = f[i]; m; m &= m - 1) filled[members[i]] |= Set{1} << members[std::countr_zero(m)];
        } else {  // not expected: the memo holds the optimum's branch (order_of); the value stands
          order_read = false;
          assert(false && "certify: no order read back for an atom searched exactly");
        }
      } catch (const OutOfBudget&) {
        all_exact = false;
        std::vector<int> blocks;
        for (int i : members) blocks.push_back(comp[i]);
        exact += bound_of(blocks);
      }
      cert.states += search.states();
    }
    // MCS-M's minimal elimination order of a chordal graph fills nothing (the graph is its own
    // only minimal triangulation): a perfect elimination order of the union.
    std::vector<int> peo;
    std::vector<Set> unused;
    mcs_m(filled, &peo, &unused);
    for (int i : peo) optimal.push_back(comp[i]);
  }
  cert.optimal_proved = all_exact;
  if (all_exact && order_read) {  // played as the game before it is reported
    assert(std::ssize(optimal) == nb);
    const double flops = block_costs(pattern, optimal, eliminate(pattern, optimal)).flops;
    assert(flops == exact);
    if (flops == exact) cert.pivots = std::move(optimal);
  }
  cert.lower_bound = exact;
  cert.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return cert;
}

}  // namespace ldlpgs
