#pragma once
// Scalar sparse storage: a symmetric matrix in compressed columns (lower triangle, as CHOLMOD's
// stype = -1) and an undirected graph in compressed rows (the pattern the orderings work on).
#include <cstdint>
#include <span>
#include <vector>

namespace ldlpgs {

// Symmetric n x n matrix, lower triangle: column j holds rows i >= j, sorted, no duplicates.
// A structurally missing diagonal entry is allowed (it is a zero).
struct SymmetricCsc {
  int n = 0;
  std::vector<int> col_ptr;    // column pointers (size n+1)
  std::vector<int> row_idx;    // row indices, ascending within a column (size col_ptr[n])
  std::vector<double> values;  // values (size col_ptr[n])

  int64_t nnz() const { return col_ptr.empty() ? 0 : col_ptr[n]; }
};

// The public API's check of a matrix a caller passes (every build, Release included): n >= 0,
// col_ptr of size n+1 from 0 and non-decreasing, row_idx and values of size nnz, rows of column
// j within j..n-1 and strictly ascending. Throws ArgumentError naming `what`, the column and the
// fault; O(n + nnz).
void check_symmetric_csc(const SymmetricCsc& a, const char* what);

// The same for a permutation of 0..n-1 (size n, each value once).
void check_permutation(std::span<const int> perm, int n, const char* what);

struct Triplet {
  int row, col;
  double value;
};

// Builds the lower triangle from entries of either triangle (an upper entry (i,j) is stored as
// (j,i)). Duplicates are summed, as CHOLMOD's triplet conversion does. Asserts indices in range.
SymmetricCsc csc_from_triplets(int n, std::span<const Triplet> entries);

// Undirected graph, compressed rows: neighbours of v are adj[ptr[v] .. ptr[v+1]), ascending,
// no self loops, each edge stored in both directions.
struct Graph {
  int n = 0;
  std::vector<int> ptr;  // row pointers (size n+1)
  std::vector<int> adj;  // neighbour lists (size ptr[n] = 2 * edges)

  std::span<const int> neighbors(int v) const {
    return {adj.data() + ptr[v], static_cast<size_t>(ptr[v + 1] - ptr[v])};
  }
  int degree(int v) const { return ptr[v + 1] - ptr[v]; }
  int64_t num_edges() const { return ptr.empty() ? 0 : ptr[n] / 2; }
};

// Builds a graph from a list of edges (u, v), u != v; duplicates are merged.
Graph graph_from_edges(int n, std::span<const std::pair<int, int>> edges);

// The graph of a symmetric matrix: an edge for every off-diagonal entry (explicit zeros count).
Graph graph_of(const SymmetricCsc& a);

// a without its stored off-diagonal entries whose value is exactly 0 (the diagonal is kept, zero
// or not): the pattern of the values, not of what was stored. Exports of H store every coupling
// block dense, and anchors at body centres or aligned axes leave half of those entries 0.
SymmetricCsc without_zeros(const SymmetricCsc& a);

// Stored entries of the full symmetric A whose lower triangle a stores: 2 off-diagonal + diagonal
// (not 2 nnz - n, which assumes every diagonal entry is stored: -5 for an empty 5 x 5).
int64_t full_nnz(const SymmetricCsc& a);

// y = A x for the full symmetric A whose lower triangle a stores (sizes a.n).
void symmetric_multiply(const SymmetricCsc& a, std::span<const double> x, std::span<double> y);
// ||A||_inf of the full symmetric A: the largest absolute row sum.
double norm_inf(const SymmetricCsc& a);
// The normwise backward error of x for A x = b: ||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf)
// (Higham, Accuracy and Stability of Numerical Algorithms, 7.1); 0 for an empty system.
double backward_error(const SymmetricCsc& a, std::span<const double> x, std::span<const double> b);

}  // namespace ldlpgs
