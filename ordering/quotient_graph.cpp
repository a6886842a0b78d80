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
// block graphs (tests/ordering/quotient_graph_test.cpp fails without it).
//
// All lists live in one integer workspace, as in AMD: a variable's E_i then A_i, an element's L_e,
// each a start and a length into it. A variable's lists are rewritten in place (each update drops
// at least the entry through which the variable was reached from the pivot, which makes room for
// the pivot's); a new element goes at the end, and when the end is reached the live lists are
// compacted to the front (collect_garbage). The queue is a binary heap of the
// variables, indexed (VariableHeap below).
#include "ldlpgs/ordering/quotient_graph.h"

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <cstring>
#include <span>
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

// Key: (score, secondary, tie, id), smallest first. The secondary is the block degree for
// meca-w's least_degree rule; the tie index is negated for highest_index.
using Key = std::tuple<int64_t, int64_t, int, int>;

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

// The elimination on the quotient graph, one pivot supervariable per step (run): take the
// cheapest, output its blocks, make it an element (form_element), count |L_e \ L_p|
// (count_outside), update the variables of L_p (update_variables), merge the indistinguishable
// ones (merge_supervariables), score them again (rekey_element) and the blocks outside L_p
// whose fill the new element may have lowered (rescore_outside).
class QuotientGame {
 public:
  QuotientGame(const BlockPattern& pattern, const QuotientOptions& opt)
      : pattern_(pattern), opt_(opt), n_(pattern.num_blocks()), status_(n_, kVariable), pe_(n_, 0), len_(n_, 0),
        elen_(n_, 0), first_(n_), mass_(n_), degree_(n_), heaviest_(n_), tie_index_(n_), next_block_(n_, -1),
        last_block_(n_), key_(n_), exact_(n_, -1), cover_(n_), in_reach_(n_, 0), near_(n_, 0),
        failed_at_(n_, INT64_MAX), last_i_(n_, 0), in_lp_(n_), heap_(key_), mark_(n_, 0), seen_(n_, 0),
        outside_(n_), hash_(n_) {
    const Graph& graph = pattern.graph();
    int64_t entries = 0;
    for (int i = 0; i < n_; ++i) entries += static_cast<int64_t>(graph.neighbors(i).size());
    // Room for the variables' lists and, by default, about as much again for the elements' (a
    // live element's members mostly mirror entries of its variables' E_i): compactions are rare.
    const auto room = static_cast<int64_t>(std::max(0.0, opt.element_room) * static_cast<double>(entries + n_));
    iw_.resize(static_cast<size_t>(entries + n_ + room + 16));
    for (int i = 0; i < n_; ++i) {
      const int64_t w = opt.weighted ? pattern.block(i).size : 1;
      mass_[i] = {1, w, w * w};
      heaviest_[i] = w;
      tie_index_[i] = i;
      last_block_[i] = i;
      live_ += mass_[i];
      auto nb = graph.neighbors(i);
      pe_[i] = tail_;
      len_[i] = static_cast<int>(nb.size());
      std::copy(nb.begin(), nb.end(), iw_.begin() + tail_);
      tail_ += len_[i];
    }
    for (int i = 0; i < n_; ++i) {
      for (int j : adj(i)) degree_[i] += mass_[j];
    }
    lp_.reserve(n_);
    reach_.reserve(n_);
    touched_.reserve(n_);
    by_hash_.reserve(n_);
    for (int i = 0; i < n_; ++i) {
      rescore(i);
      rekey(i);
    }
  }

  std::vector<int> run(std::vector<QuotientStep>* trace) {
    std::vector<int> pivots;
    pivots.reserve(n_);
    while (!heap_.empty()) {
      const int p = heap_.pop();
      if (status_[p] != kVariable) continue;  // merged into a supervariable
      const size_t first = pivots.size();
      output_blocks(p, pivots);
      const Mass lp_mass = form_element(p);
      count_outside();
      update_variables(p, lp_mass);
      merge_supervariables();
      rekey_element(p, std::span<const int>(pivots).subspan(first), trace);
      if (opt_.score == QuotientScore::fill && exact_[p] != 0) rescore_outside(p);
    }
    assert(static_cast<int>(pivots.size()) == n_);
    return pivots;
  }

 private:
  // The lists of id i in the workspace: E_i and A_i of a variable, L_e of an element.
  std::span<const int> elems(int i) const { return {iw_.data() + pe_[i], static_cast<size_t>(elen_[i])}; }
  std::span<const int> adj(int i) const {
    return {iw_.data() + pe_[i] + elen_[i], static_cast<size_t>(len_[i] - elen_[i])};
  }
  std::span<const int> members(int e) const { return {iw_.data() + pe_[e], static_cast<size_t>(len_[e])}; }
  void drop_lists(int i) { len_[i] = elen_[i] = 0; }

  // `size` free entries at the end of the workspace, compacting it first when they do not fit.
  // Moves lists: no span into the workspace survives a call.
  int64_t allocate(int64_t size) {
    if (tail_ + size > static_cast<int64_t>(iw_.size())) collect_garbage();
    if (tail_ + size > static_cast<int64_t>(iw_.size())) iw_.resize(static_cast<size_t>(2 * (tail_ + size)));
    const int64_t at = tail_;
    tail_ += size;
    return at;
  }
  // Moves the live lists to the front in workspace order, as AMD does: the first entry of each is
  // replaced by -(id + 1) (the entry kept in first_), so that one sweep finds where lists start.
  void collect_garbage() {
    for (int i = 0; i < n_; ++i) {
      if (len_[i] == 0) continue;
      first_[i] = iw_[pe_[i]];
      iw_[pe_[i]] = -(i + 1);
    }
    int64_t to = 0;
    for (int64_t from = 0; from < tail_;) {
      if (iw_[from] >= 0) {  // not in a live list
        ++from;
        continue;
      }
      const int i = -iw_[from] - 1;
      pe_[i] = to;
      iw_[to] = first_[i];
      std::memmove(iw_.data() + to + 1, iw_.data() + from + 1, sizeof(int) * static_cast<size_t>(len_[i] - 1));
      to += len_[i];
      from += len_[i];
    }
    tail_ = to;
  }

  Key make_key(int i) const {
    int64_t s;
    if (opt_.score == QuotientScore::degree) {
      s = degree_[i].w + mass_[i].w - heaviest_[i];
    } else if (exact_[i] >= 0) {
      s = exact_[i];
    } else {
      s = std::max<int64_t>(0, degree_[i].pairs() - cover_[i].pairs());
    }
    const int64_t secondary = opt_.tie == TieBreak::least_degree ? degree_[i].c + mass_[i].c - 1 : 0;
    const int t = opt_.tie == TieBreak::highest_index ? -tie_index_[i] : tie_index_[i];
    return Key{s, secondary, t, i};
  }
  void rekey(int i) {
    key_[i] = make_key(i);
    heap_.update(i);
  }
  void rescore(int i) { exact_[i] = opt_.score == QuotientScore::fill ? try_exact(i) : -1; }

  // The exact fill of i, when its neighbourhood is small: for each neighbour u (a supervariable:
  // its blocks are pairwise adjacent, and adjacent to v in full or not at all), the weight of
  // the other neighbours it is not adjacent to. Gives up (returns -1) past `budget` list
  // entries read, so that a hub of a star or a clique keeps the approximation.
  int64_t exact_fill(int i, int64_t budget) {
    ++reach_stamp_;
    in_reach_[i] = reach_stamp_;
    reach_.clear();
    int64_t total = 0;
    auto add = [&](int v) {
      if (status_[v] == kVariable && in_reach_[v] != reach_stamp_) {
        in_reach_[v] = reach_stamp_;
        reach_.push_back(v);
        total += mass_[v].w;
      }
    };
    for (int v : adj(i)) add(v);
    for (int e : elems(i)) {
      if (status_[e] != kElement) continue;
      budget -= len_[e];
      for (int v : members(e)) add(v);
    }
    // What the count below reads, from the list lengths alone: a count that cannot afford it
    // gives up before reading its neighbours' lists, so that a failure costs the lengths, not the
    // budget (the same counts succeed; papers/orderings.md, "Short lists: the second exact tier").
    for (int u : reach_) {
      budget -= len_[u] - elen_[u];
      for (int e : elems(u)) {
        if (status_[e] == kElement) budget -= len_[e];
      }
      if (budget < 0) return -1;
    }
    int64_t twice_fill = 0;
    for (int u : reach_) {
      ++near_stamp_;
      near_[u] = near_[i] = near_stamp_;  // neither u nor i is a neighbour u may miss
      int64_t adjacent = 0;
      auto see = [&](int v) {
        if (in_reach_[v] == reach_stamp_ && near_[v] != near_stamp_ && status_[v] == kVariable) {
          near_[v] = near_stamp_;
          adjacent += mass_[v].w;
        }
      };
      for (int v : adj(u)) see(v);
      for (int e : elems(u)) {
        if (status_[e] == kElement) {
          for (int v : members(e)) see(v);
        }
      }
      twice_fill += mass_[u].w * (total - mass_[u].w - adjacent);
    }
    return twice_fill / 2;
  }
  // exact_fill within the two tiers' limits (kExactDegree, kShortLists), or -1.
  int64_t try_exact(int i) {
    if (degree_[i].c <= kExactDegree) return exact_fill(i, kExactBudget);
    if (degree_[i].c >= failed_at_[i]) return -1;
    int64_t lists = len_[i] - elen_[i];
    const std::span<const int> ei = elems(i);
    for (size_t k = 0; k < ei.size() && lists <= kShortLists; ++k) {
      if (status_[ei[k]] == kElement) lists += len_[ei[k]];
    }
    const int64_t f = lists <= kShortLists ? exact_fill(i, kShortBudget) : -1;
    if (f < 0) failed_at_[i] = degree_[i].c;
    return f;
  }

  // Output p's blocks in the order the exact game would take them: all of them have the same
  // neighbours, so the tie rule (and for mda-w the heaviest block, of least degree) decides.
  void output_blocks(int p, std::vector<int>& pivots) {
    const auto first = pivots.end() - pivots.begin();
    for (int b = p; b >= 0; b = next_block_[b]) pivots.push_back(b);
    std::sort(pivots.begin() + first, pivots.end(), [&](int a, int b) {
      if (opt_.score == QuotientScore::degree && opt_.weighted && pattern_.block(a).size != pattern_.block(b).size)
        return pattern_.block(a).size > pattern_.block(b).size;
      return opt_.tie == TieBreak::highest_index ? a > b : a < b;
    });
    live_ -= mass_[p];
  }

  // L_p = (A_p u union of L_e over e in E_p) minus p; the elements of E_p are absorbed. Marks
  // L_p with a new stamp (lp_stamp_) and returns its mass.
  Mass form_element(int p) {
    ++stamp_;
    mark_[p] = stamp_;
    lp_.clear();
    Mass lp_mass;
    auto take = [&](int j) {
      if (status_[j] == kVariable && mark_[j] != stamp_) {
        mark_[j] = stamp_;
        lp_.push_back(j);
        lp_mass += mass_[j];
      }
    };
    for (int e : elems(p)) {
      for (int j : members(e)) take(j);
      status_[e] = kAbsorbed;
      drop_lists(e);
    }
    for (int j : adj(p)) take(j);
    status_[p] = kElement;
    drop_lists(p);  // (L_p is written by rekey_element)
    mass_[p] = lp_mass;
    lp_stamp_ = stamp_;
    return lp_mass;
  }

  // |L_e \ L_p| for every element e adjacent to L_p: |L_e| minus the variables of L_p in it.
  void count_outside() {
    for (int i : lp_) {
      for (int e : elems(i)) {
        if (status_[e] != kElement) continue;
        if (seen_[e] != lp_stamp_) {
          seen_[e] = lp_stamp_;
          outside_[e] = mass_[e];
        }
        outside_[e] -= mass_[i];
      }
    }
  }

  // Update each i in L_p: prune its lists and add p (prune_lists); bound the degree.
  void update_variables(int p, const Mass& lp_mass) {
    for (int i : lp_) {
      Mass external;
      hash_[i] = prune_lists(i, p, external);
      const Mass rest = lp_mass - mass_[i];
      const Mass bound = external + rest, grown = degree_[i] + rest, all = live_ - mass_[i];
      degree_[i] = {std::min({bound.c, grown.c, all.c}), std::min({bound.w, grown.w, all.w}),
                    std::min({bound.q, grown.q, all.q})};
    }
  }
  // E_i loses its absorbed elements (and, aggressively, those inside L_p, which p absorbs) and
  // gains p after the rest; A_i loses what element p now covers. Adds the mass of what remains
  // to `external`, returns the hash of the lists. In place: p, or an element of E_p, was in the
  // lists and is dropped, so the new lists fit; were nothing dropped they move to the end.
  uint64_t prune_lists(int i, int p, Mass& external) {
    int* list = iw_.data() + pe_[i];
    const int e_len = elen_[i], a_len = len_[i] - elen_[i];
    uint64_t h = static_cast<uint64_t>(p);
    int ke = 0, ka = 0;
    for (int k = 0; k < e_len; ++k) {
      const int e = list[k];
      if (status_[e] != kElement) continue;
      if (outside_[e].c == 0) {  // L_e is inside L_p: p absorbs it
        status_[e] = kAbsorbed;
        drop_lists(e);
        continue;
      }
      external += outside_[e];
      h += static_cast<uint64_t>(e);
      list[ke++] = e;
    }
    int* a = list + e_len;
    for (int k = 0; k < a_len; ++k) {
      const int j = a[k];
      if (status_[j] != kVariable || mark_[j] == lp_stamp_) continue;
      external += mass_[j];
      h += static_cast<uint64_t>(j);
      a[ka++] = j;
    }
    if (ke + 1 + ka > len_[i]) {  // nothing dropped: the lists are whole, [E_i, A_i]
      const int64_t at = allocate(len_[i] + 1);
      list = iw_.data() + pe_[i];
      std::memmove(iw_.data() + at, list, sizeof(int) * static_cast<size_t>(ke));
      std::memmove(iw_.data() + at + ke + 1, list + ke, sizeof(int) * static_cast<size_t>(ka));
      pe_[i] = at;
      list = iw_.data() + at;
    } else {
      std::memmove(list + ke + 1, a, sizeof(int) * static_cast<size_t>(ka));
    }
    list[ke] = p;
    elen_[i] = ke + 1;
    len_[i] = ke + 1 + ka;
    return h;
  }

  // Supervariables: variables of L_p with equal hash, then equal lists, are indistinguishable.
  void merge_supervariables() {
    by_hash_.clear();
    for (int i : lp_) by_hash_.emplace_back(hash_[i], i);
    std::sort(by_hash_.begin(), by_hash_.end());
    for (size_t a = 0; a < by_hash_.size(); ++a) {
      const int i = by_hash_[a].second;
      if (status_[i] != kVariable) continue;
      bool marked = false;
      for (size_t b = a + 1; b < by_hash_.size() && by_hash_[b].first == by_hash_[a].first; ++b) {
        const int j = by_hash_[b].second;
        if (status_[j] != kVariable || len_[j] != len_[i] || elen_[j] != elen_[i]) continue;
        if (!marked) {
          ++stamp_;
          for (int x : adj(i)) mark_[x] = stamp_;
          for (int x : elems(i)) mark_[x] = stamp_;
          marked = true;
        }
        bool same = true;
        for (int x : adj(j)) same = same && mark_[x] == stamp_;
        for (int x : elems(j)) same = same && mark_[x] == stamp_;
        if (same) merge(i, j);
      }
    }
  }
  // j joins i: i's external degree no longer counts j.
  void merge(int i, int j) {
    degree_[i] -= mass_[j];
    mass_[i] += mass_[j];
    // The tie rule reads the block the exact game would take first: any of i's for a degree
    // that all its blocks share, but for mda-w's weighted degree (the rest of the
    // supervariable counts, the block itself does not) one of its heaviest blocks.
    const bool by_weight = opt_.score == QuotientScore::degree && opt_.weighted && heaviest_[i] != heaviest_[j];
    if (by_weight) {
      if (heaviest_[j] > heaviest_[i]) tie_index_[i] = tie_index_[j];
    } else {
      tie_index_[i] = opt_.tie == TieBreak::highest_index ? std::max(tie_index_[i], tie_index_[j])
                                                          : std::min(tie_index_[i], tie_index_[j]);
    }
    heaviest_[i] = std::max(heaviest_[i], heaviest_[j]);
    next_block_[last_block_[i]] = j;
    last_block_[i] = last_block_[j];
    drop_lists(j);
    status_[j] = kMerged;  // (left in the heap: popped and skipped, cheaper than taken out)
  }

  // Element p keeps its live variables; new keys for them (for meca, a new cover: the largest
  // element among E_i), and the step in the trace (p's blocks are `eliminated`).
  void rekey_element(int p, std::span<const int> eliminated, std::vector<QuotientStep>* trace) {
    size_t k = 0;
    for (int i : lp_) {
      if (status_[i] == kVariable) lp_[k++] = i;
    }
    lp_.resize(k);
    pe_[p] = allocate(static_cast<int64_t>(k));
    std::copy(lp_.begin(), lp_.end(), iw_.begin() + pe_[p]);
    len_[p] = static_cast<int>(k);
    QuotientStep* step = nullptr;
    if (trace) {
      trace->push_back({std::vector<int>(eliminated.begin(), eliminated.end()), {}});
      step = &trace->back();
    }
    for (int i : lp_) {
      if (opt_.score == QuotientScore::fill) {
        Mass best;
        for (int e : elems(i)) {
          const Mass m = mass_[e] - mass_[i];
          if (m.pairs() > best.pairs()) best = m;
        }
        cover_[i] = best;
        rescore(i);
      }
      rekey(i);
      if (step) {
        for (int b = i; b >= 0; b = next_block_[b]) step->degrees.emplace_back(b, degree_[i].c + mass_[i].c - 1);
      }
    }
  }

  // Blocks outside L_p next to two or more of it may have lost fill (the new edges of L_p's
  // clique join some of their neighbours): rescore those that the exact count can afford,
  // reached by original edges and small elements, as the exact game lowers them. Called only
  // for meca and meca-w, and only when p was not known to be simplicial (exact fill 0: it
  // created no edge); a block next to only one block of L_p gained no edge among its
  // neighbours and is skipped.
  // For meca, a block too large to count keeps its approximate score, but its neighbours in
  // L_p are now a clique: where they outweigh its cover (the largest element), they become it
  // (not for meca-w, where it measured worse: papers/orderings.md, "MDA and MECA on a quotient
  // graph").
  void rescore_outside(int p) {
    ++stamp_;
    for (int i : lp_) mark_[i] = stamp_;
    mark_[p] = stamp_;
    touched_.clear();
    for (int i : lp_) {
      ++i_stamp_;
      auto visit = [&](int x) {
        if (status_[x] != kVariable || mark_[x] == stamp_ || last_i_[x] == i_stamp_) return;
        last_i_[x] = i_stamp_;
        if (seen_[x] != stamp_) {  // (seen_[] is free for variables)
          seen_[x] = stamp_;
          in_lp_[x] = Mass{};
          touched_.push_back(x);
        }
        in_lp_[x] += mass_[i];
      };
      for (int x : adj(i)) visit(x);
      for (int e : elems(i)) {
        if (e != p && len_[e] <= kExactDegree) {
          for (int x : members(e)) visit(x);
        }
      }
    }
    for (int x : touched_) {
      if (in_lp_[x].c < 2) continue;
      const int64_t f = try_exact(x);
      if (f >= 0 && f != exact_[x]) {
        exact_[x] = f;
        rekey(x);
      }
      if (f < 0 && !opt_.weighted && exact_[x] < 0 && in_lp_[x].pairs() > cover_[x].pairs()) {
        cover_[x] = in_lp_[x];
        rekey(x);
      }
    }
  }

  const BlockPattern& pattern_;
  const QuotientOptions opt_;
  const int n_;
  std::vector<uint8_t> status_;             // what id i is now (size n)
  // The workspace: a variable's E_i (elements) then A_i (variables, original edges) at
  // iw_[pe_[i]], len_[i] entries of which the first elen_[i] are E_i; an element's L_e (its
  // variables) at iw_[pe_[e]], len_[e] entries. Entries from tail_ on are free.
  std::vector<int> iw_;
  int64_t tail_ = 0;
  std::vector<int64_t> pe_;                 // (size n)
  std::vector<int> len_, elen_;             // (size n)
  std::vector<int> first_;                  // collect_garbage: each list's first entry (size n)
  std::vector<Mass> mass_;                  // variable: its blocks; element: live L_e (size n)
  std::vector<Mass> degree_;                // d_i, the external degree bound (size n)
  std::vector<int64_t> heaviest_;           // largest block weight in supervariable i (size n)
  std::vector<int> tie_index_;              // the block index the tie rule reads (size n)
  // The blocks of supervariable i: i, next_block_[i], ... to -1, ending at last_block_[i].
  std::vector<int> next_block_, last_block_;  // (size n)
  Mass live_;                               // mass of all variables not yet eliminated
  std::vector<Key> key_;                    // (size n)
  std::vector<int64_t> exact_;              // exact fill of i when known, else -1 (size n)
  std::vector<Mass> cover_;                 // the largest element mass among E_i, minus i's own (size n)
  std::vector<int> in_reach_, near_;        // exact_fill's stamps (size n)
  int reach_stamp_ = 0, near_stamp_ = 0;
  std::vector<int> reach_;                  // exact_fill: the neighbours of i
  std::vector<int64_t> failed_at_;          // degree bound at the last failed count (size n)
  std::vector<int> touched_;                // blocks outside L_p next to it, this step
  std::vector<int> last_i_;                 // stamp: counted for the current block of L_p (size n)
  std::vector<Mass> in_lp_;                 // of a touched block: its neighbours in L_p (size n)
  int i_stamp_ = 0;
  VariableHeap<Key> heap_;                  // after key_, which it reads
  std::vector<int> lp_;                     // L_p of the current pivot
  std::vector<int> mark_;                   // stamp: in L_p, or entry of a list being compared (size n)
  std::vector<int> seen_;                   // stamp: element whose |L_e \ L_p| is being counted (size n)
  std::vector<Mass> outside_;               // |L_e \ L_p| for e seen this step (size n)
  std::vector<uint64_t> hash_;              // of A_i and E_i, for supervariable detection (size n)
  std::vector<std::pair<uint64_t, int>> by_hash_;
  int stamp_ = 0, lp_stamp_ = 0;
};

}  // namespace

std::vector<int> quotient_order(const BlockPattern& pattern, const QuotientOptions& opt,
                                std::vector<QuotientStep>* trace) {
  return QuotientGame(pattern, opt).run(trace);
}

}  // namespace ldlpgs
