#pragma once
// The module's conversions between Python objects (scipy.sparse matrices, NumPy arrays, the
// blocks argument) and the library's types, with every check the library leaves to its callers
// (asserts there) done here, so that bad input is a Python exception and never a crash.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <span>
#include <string>
#include <vector>

#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs::python {

namespace py = pybind11;

// A square symmetric real scipy.sparse matrix (any format) as its lower triangle. With
// lower = false, A holds the full matrix (what scipy.io.mmread gives for a Matrix Market
// symmetric file) and must be symmetric in pattern and values, exactly, as our Matrix Market
// reader requires of a general file; with lower = true, A holds only the lower triangle (the
// file's storage, SymmetricCsc's) and an entry above the diagonal is refused. Duplicates are
// summed (CHOLMOD's and csc_from_triplets' convention); entries must be finite. InputError
// naming the entry (0-based, A[i, j]) otherwise.
SymmetricCsc symmetric_from_scipy(py::handle a, bool lower);

// The blocks argument: "auto" (identical consecutive rows, at most max_block), an integer
// (uniform), a path to a partition file (parse_partition), or a sequence of positive block sizes
// summing to n.
BlockPattern block_pattern_from(py::handle blocks, const SymmetricCsc& a, int max_block);

// An ordering list: "all", "mda,meca", or a sequence of names (parse_ordering_list checks them).
std::vector<std::string> ordering_names(py::handle orderings);

// A scipy.sparse.csc_matrix n x n from compressed columns (copied).
py::object scipy_csc(int n, std::span<const int> col_ptr, std::span<const int> row_idx,
                     std::span<const double> values);

template <class T>
py::array_t<T> numpy_copy(std::span<const T> x) {
  return py::array_t<T>(static_cast<py::ssize_t>(x.size()), x.data());
}

// A float64 NumPy array holding a copy of x (any array-like; complex and sparse refused), in
// Fortran order: columns of a 2-D array are contiguous, as the solve takes them.
py::array_t<double, py::array::f_style> dense_copy(py::handle x, const char* name);

}  // namespace ldlpgs::python
