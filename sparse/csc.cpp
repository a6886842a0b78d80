#include "ldlpgs/sparse/csc.h"

#include <algorithm>
#include <cassert>
#include <cmath>

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

void symmetric_multiply(const SymmetricCsc& a, std::span<const double> x, std::span<double> y) {
  assert(static_cast<int>(x.size()) == a.n && static_cast<int>(y.size()) == a.n);
  std::fill(y.begin(), y.end(), 0.0);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int i = a.row_idx[p];
      y[i] += a.values[p] * x[j];
      if (i != j) y[j] += a.values[p] * x[i];
    }
  }
}

double norm_inf(const SymmetricCsc& a) {
  std::vector<double> row_sum(a.n, 0.0);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int i = a.row_idx[p];
      row_sum[i] += std::abs(a.values[p]);
      if (i != j) row_sum[j] += std::abs(a.values[p]);
    }
  }
  return row_sum.empty() ? 0.0 : *std::max_element(row_sum.begin(), row_sum.end());
}

double backward_error(const SymmetricCsc& a, std::span<const double> x, std::span<const double> b) {
  std::vector<double> r(a.n);
  symmetric_multiply(a, x, r);
  double rn = 0, xn = 0, bn = 0;
  for (int i = 0; i < a.n; ++i) {
    rn = std::max(rn, std::abs(r[i] - b[i]));
    xn = std::max(xn, std::abs(x[i]));
    bn = std::max(bn, std::abs(b[i]));
  }
  const double scale = norm_inf(a) * xn + bn;
  return scale > 0 ? rn / scale : rn;
}

}  // namespace ldlpgs
