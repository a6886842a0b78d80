#include "ldlpgs/sparse/csc.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

void check_symmetric_csc(const SymmetricCsc& a, const char* what) {
  const auto fail = [&](const std::string& why) { throw ArgumentError(std::string(what) + ": " + why); };
  if (a.n < 0) fail("negative dimension " + std::to_string(a.n));
  if (a.col_ptr.size() != static_cast<size_t>(a.n) + 1)
    fail("col_ptr has " + std::to_string(a.col_ptr.size()) + " entries, not n+1 = " + std::to_string(int64_t{a.n} + 1));
  if (a.col_ptr[0] != 0) fail("col_ptr[0] is " + std::to_string(a.col_ptr[0]) + ", not 0");
  for (int j = 0; j < a.n; ++j)
    if (a.col_ptr[j + 1] < a.col_ptr[j]) fail("col_ptr decreases at column " + std::to_string(j));
  const size_t nnz = static_cast<size_t>(a.col_ptr[a.n]);
  if (a.row_idx.size() != nnz || a.values.size() != nnz)
    fail("row_idx and values have " + std::to_string(a.row_idx.size()) + " and " + std::to_string(a.values.size()) +
         " entries, col_ptr says " + std::to_string(nnz));
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int i = a.row_idx[p];
      if (i < j || i >= a.n)
        fail("row " + std::to_string(i) + " in column " + std::to_string(j) + " is outside the lower triangle " +
             std::to_string(j) + ".." + std::to_string(a.n - 1));
      if (p > a.col_ptr[j] && i <= a.row_idx[p - 1])
        fail("rows of column " + std::to_string(j) + " are not strictly ascending at row " + std::to_string(i));
    }
  }
}

void check_permutation(std::span<const int> perm, int n, const char* what) {
  if (std::ssize(perm) != n)
    throw ArgumentError(std::string(what) + ": permutation of " + std::to_string(perm.size()) + " entries for " +
                        std::to_string(n) + " rows");
  std::vector<char> seen(n, 0);
  for (size_t k = 0; k < perm.size(); ++k) {
    if (perm[k] < 0 || perm[k] >= n || seen[perm[k]])
      throw ArgumentError(std::string(what) + ": entry " + std::to_string(k) + " of the permutation, " +
                          std::to_string(perm[k]) + ", is " + (perm[k] < 0 || perm[k] >= n ? "outside 0.." + std::to_string(n - 1) : std::string("repeated")));
    seen[perm[k]] = 1;
  }
}

SymmetricCsc csc_from_triplets(int n, std::span<const Triplet> entries) {
  if (n < 0) throw ArgumentError("csc_from_triplets: negative dimension " + std::to_string(n));
  SymmetricCsc a;
  a.n = n;
  // Two stable counting sorts, by row and then by column (the transpose-twice of CSparse's
  // cs_compress/cs_transpose): each column's entries come out in row order and duplicates in
  // input order, in O(n + entries) with no comparison sort (papers/factor.md, "Supernodes: before
  // and after", the 1000-arm star). by_row[] is the permutation of the entries by row (size
  // entries); row_ptr and count are the row and column starts (size n + 1; size_t: n may be INT_MAX).
  std::vector<int> row_ptr(static_cast<size_t>(n) + 1, 0), count(static_cast<size_t>(n) + 1, 0);
  for (const Triplet& t : entries) {
    if (t.row < 0 || t.row >= n || t.col < 0 || t.col >= n)
      throw ArgumentError("triplet (" + std::to_string(t.row) + ", " + std::to_string(t.col) + ") outside 0.." +
                          std::to_string(n - 1));
    ++row_ptr[std::max(t.row, t.col) + 1];
    ++count[std::min(t.row, t.col) + 1];
  }
  for (int j = 0; j < n; ++j) {
    row_ptr[j + 1] += row_ptr[j];
    count[j + 1] += count[j];
  }
  std::vector<int> by_row(entries.size());
  for (size_t p = 0; p < entries.size(); ++p) by_row[row_ptr[std::max(entries[p].row, entries[p].col)]++] = static_cast<int>(p);
  std::vector<std::pair<int, double>> slots(entries.size());
  std::vector<int> next(count.begin(), count.end() - 1);
  for (const int p : by_row) {
    const Triplet& t = entries[p];
    slots[next[std::min(t.row, t.col)]++] = {std::max(t.row, t.col), t.value};
  }
  a.col_ptr.assign(static_cast<size_t>(n) + 1, 0);
  a.row_idx.reserve(entries.size());
  a.values.reserve(entries.size());
  for (int j = 0; j < n; ++j) {
    auto first = slots.begin() + count[j], last = slots.begin() + count[j + 1];
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
  g.ptr.assign(static_cast<size_t>(n) + 1, 0);
  for (auto [u, v] : edges) {
    if (u == v || u < 0 || v < 0 || u >= n || v >= n)
      throw ArgumentError("graph: edge (" + std::to_string(u) + ", " + std::to_string(v) + ") is a loop or outside 0.." +
                          std::to_string(n - 1));
    ++g.ptr[u + 1];
    ++g.ptr[v + 1];
  }
  for (int v = 0; v < n; ++v) g.ptr[v + 1] += g.ptr[v];
  // Each list in ascending order without a comparison sort (papers/factor.md, "Supernodes:
  // before and after", the 1000-arm star): the arcs s -> w are bucketed by w (bucket w holds the s), then
  // the buckets are walked in ascending w and w appended to each s's list. Duplicates end up
  // adjacent and are dropped while compacting.
  std::vector<int> by_target(g.ptr[n]), adj(g.ptr[n]);  // (size 2 edges)
  std::vector<int> next(g.ptr.begin(), g.ptr.end() - 1);
  for (auto [u, v] : edges) {
    by_target[next[v]++] = u;
    by_target[next[u]++] = v;
  }
  std::copy(g.ptr.begin(), g.ptr.end() - 1, next.begin());
  for (int w = 0; w < n; ++w)
    for (int p = g.ptr[w]; p < g.ptr[w + 1]; ++p) adj[next[by_target[p]]++] = w;
  g.adj.reserve(adj.size());
  std::vector<int> ptr(static_cast<size_t>(n) + 1, 0);
  for (int v = 0; v < n; ++v) {
    auto first = adj.begin() + g.ptr[v], last = adj.begin() + g.ptr[v + 1];
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

SymmetricCsc without_zeros(const SymmetricCsc& a) {
  SymmetricCsc b;
  b.n = a.n;
  b.col_ptr.assign(a.n + 1, 0);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      if (a.row_idx[p] != j && a.values[p] == 0.0) continue;
      b.row_idx.push_back(a.row_idx[p]);
      b.values.push_back(a.values[p]);
    }
    b.col_ptr[j + 1] = static_cast<int>(b.row_idx.size());
  }
  return b;
}

void symmetric_multiply(const SymmetricCsc& a, std::span<const double> x, std::span<double> y) {
  if (std::ssize(x) != a.n || std::ssize(y) != a.n)
    throw ArgumentError("symmetric_multiply: x and y have " + std::to_string(x.size()) + " and " +
                        std::to_string(y.size()) + " entries, the matrix " + std::to_string(a.n) + " rows");
  std::fill(y.begin(), y.end(), 0.0);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      const int i = a.row_idx[p];
      y[i] += a.values[p] * x[j];
      if (i != j) y[j] += a.values[p] * x[i];
    }
  }
}

int64_t full_nnz(const SymmetricCsc& a) {
  int64_t diagonal = 0;
  for (int j = 0; j < a.n; ++j)
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) diagonal += a.row_idx[p] == j;
  return 2 * a.nnz() - diagonal;
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
  if (std::ssize(b) != a.n)
    throw ArgumentError("backward_error: b has " + std::to_string(b.size()) + " entries for " + std::to_string(a.n) + " rows");
  // The measure is invariant under A, b -> 2^-e A, 2^-e b; at the edges of double the residual
  // is computed so (a matrix at 1e-320 has a residual rounded to the subnormal spacing 5e-324,
  // a relative 1e-4 of nothing but arithmetic). Exact: e is a power of two.
  const double na = norm_inf(a);
  if (na > 0 && (na > 0x1p500 || na < 0x1p-500)) {
    const int e = std::ilogb(na);
    SymmetricCsc as = a;
    for (double& v : as.values) v = std::ldexp(v, -e);
    std::vector<double> bs(b.begin(), b.end());
    for (double& v : bs) v = std::ldexp(v, -e);
    return backward_error(as, x, bs);
  }
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
