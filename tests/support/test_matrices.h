#pragma once
// Shared helpers for the tests on SymmetricCsc: the collection's test matrices read once, the
// dense reference of a matrix, and the structural invariants csc.h promises.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/csc.h"
#include "ldlpgs/sparse/matrix_market.h"

namespace ldlpgs::testing {

struct Named {
  std::string name;
  SymmetricCsc a;
};

// Every test matrix except the unsymmetric Pd.mtx, read once, in name order.
inline const std::vector<Named>& test_matrices() {
  static const std::vector<Named> all = [] {
    std::vector<Named> out;
    for (const auto& file : std::filesystem::directory_iterator(LDLPGS_MATRICES)) {
      if (file.path().extension() != ".mtx" || file.path().filename() == "Pd.mtx") continue;
      out.push_back({file.path().filename().string(), read_matrix_market(file.path().string())});
    }
    std::sort(out.begin(), out.end(), [](const Named& x, const Named& y) { return x.name < y.name; });
    return out;
  }();
  return all;
}

// The full symmetric matrix as dense, read from the arrays.
inline Eigen::MatrixXd dense(const SymmetricCsc& a) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(a.n, a.n);
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      d(a.row_idx[p], j) = d(j, a.row_idx[p]) = a.values[p];
    }
  }
  return d;
}

// The stored positions (row, col) of a, row >= col, read from the arrays.
inline std::set<std::pair<int, int>> stored(const SymmetricCsc& a) {
  std::set<std::pair<int, int>> s;
  for (int j = 0; j < a.n; ++j) {
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) s.insert({a.row_idx[p], j});
  }
  return s;
}

// The invariants csc.h promises for a SymmetricCsc: sizes agree, lower triangle only, rows
// strictly ascending within each column (so no duplicates).
inline void expect_valid(const SymmetricCsc& a) {
  ASSERT_EQ(static_cast<int>(a.col_ptr.size()), a.n + 1);
  ASSERT_EQ(a.col_ptr[0], 0);
  ASSERT_EQ(a.row_idx.size(), static_cast<std::size_t>(a.nnz()));
  ASSERT_EQ(a.values.size(), static_cast<std::size_t>(a.nnz()));
  for (int j = 0; j < a.n; ++j) {
    ASSERT_LE(a.col_ptr[j], a.col_ptr[j + 1]) << "column " << j;
    for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
      ASSERT_GE(a.row_idx[p], j) << "column " << j << " holds an upper entry";
      ASSERT_LT(a.row_idx[p], a.n);
      if (p > a.col_ptr[j]) {
        ASSERT_LT(a.row_idx[p - 1], a.row_idx[p]) << "column " << j;
      }
    }
  }
}

// x and y hold the same arrays, entry for entry.
inline void expect_equal(const SymmetricCsc& x, const SymmetricCsc& y) {
  EXPECT_EQ(x.n, y.n);
  EXPECT_EQ(x.col_ptr, y.col_ptr);
  EXPECT_EQ(x.row_idx, y.row_idx);
  EXPECT_EQ(x.values, y.values);
}

}  // namespace ldlpgs::testing
