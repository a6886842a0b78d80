#include "ldlpgs/sparse/eigen_adapter.h"

#include <vector>

namespace ldlpgs {

Eigen::SparseMatrix<double> to_eigen(const SymmetricCsc& a, Triangle t) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(t == Triangle::full ? 2 * a.nnz() : a.nnz());
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      entries.emplace_back(a.row_idx[p], j, a.values[p]);
      if (t == Triangle::full && a.row_idx[p] != j) entries.emplace_back(j, a.row_idx[p], a.values[p]);
    }
  }
  Eigen::SparseMatrix<double> m(a.n, a.n);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

SymmetricCsc from_eigen(const Eigen::SparseMatrix<double>& m) {
  std::vector<Triplet> entries;
  for (int j = 0; j < m.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, j); it; ++it) {
      if (it.row() >= j) entries.push_back({static_cast<int>(it.row()), j, it.value()});
    }
  }
  return csc_from_triplets(static_cast<int>(m.rows()), entries);
}

}  // namespace ldlpgs
