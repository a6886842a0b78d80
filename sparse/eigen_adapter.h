#pragma once
// Conversions between SymmetricCsc and Eigen::SparseMatrix (column-major, int indices).
#include <Eigen/SparseCore>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

enum class Triangle { lower, full };

// The lower triangle (as stored) or the full symmetric matrix.
Eigen::SparseMatrix<double> to_eigen(const SymmetricCsc& a, Triangle t = Triangle::full);
// The lower triangle of a square Eigen matrix; entries above the diagonal are ignored.
SymmetricCsc from_eigen(const Eigen::SparseMatrix<double>& a);

}  // namespace ldlpgs
