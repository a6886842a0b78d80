#include "sparse/csc.h"

#include <algorithm>
#include <cassert>

namespace ldlpgs {

SymmetricCsc csc_from_triplets(int n, std::span<const Triplet> entries) {
  SymmetricCsc a;
  a.n = n;
  // Counting sort by column, then sort each column by row and sum duplicates.
  std::vector<int> count(n + 1, 0);
  for (const Triplet& t : entries) {
    assert(t.row >= 0 && t.row < n && t.col >= 0 && t.col < n);
    ++count[std::min(t.row, t.col) + 1];
  }
  for (int j = 0; j < n; ++j) count[j + 1] += count[j];
  std::vector<std::pair<int, double>> slots(entries.size());
  std::vector<int> next(count.begin(), count.end() - 1);
  for (const Triplet& t : entries) {
    slots[next[std::min(t.row, t.col)]++] = {std::max(t.row, t.col), t.value};
  }
  a.col_ptr.assign(n + 1, 0);
  a.row_idx.reserve(entries.size());
  a.values.reserve(entries.size());
  for (int j = 0; j < n; ++j) {
    auto first = slots.begin() + count[j], last = slots.begin() + count[j + 1];
    std::sort(first, last, [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto it = first; it != last; ++it) {
      if (static_cast<int>(a.row_idx.size()) > a.col_ptr[j] && a.row_idx.back() == it->first) {
        a.values.back() += it->second;
      } else {
        a.row_idx.push_back(it->first);
        a.values.push_back(it->second);
      }
    }
    a.col_ptr[j + 1] = static_cast<int>(a.row_idx.size());
  }
  return a;
}

Graph graph_from_edges(int n, std::span<const std::pair<int, int>> edges) {
  Graph g;
  g.n = n;
  g.ptr.assign(n + 1, 0);
  for (auto [u, v] : edges) {
    assert(u != v && u >= 0 && v >= 0 && u < n && v < n);
    ++g.ptr[u + 1];
    ++g.ptr[v + 1];
  }
  for (int v = 0; v < n; ++v) g.ptr[v + 1] += g.ptr[v];
  std::vector<int> adj(g.ptr[n]);
  std::vector<int> next(g.ptr.begin(), g.ptr.end() - 1);
  for (auto [u, v] : edges) {
    adj[next[u]++] = v;
    adj[next[v]++] = u;
  }
  // Sort each list and drop duplicates, compacting in place.
  g.adj.reserve(adj.size());
  std::vector<int> ptr(n + 1, 0);
  for (int v = 0; v < n; ++v) {
    auto first = adj.begin() + g.ptr[v], last = adj.begin() + g.ptr[v + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    g.adj.insert(g.adj.end(), first, last);
    ptr[v + 1] = static_cast<int>(g.adj.size());
  }
  g.ptr = std::move(ptr);
  return g;
}

Graph graph_of(const SymmetricCsc& a) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(a.nnz());
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      if (a.row_idx[p] != j) edges.emplace_back(a.row_idx[p], j);
    }
  }
  return graph_from_edges(a.n, edges);
}

}  // namespace ldlpgs
