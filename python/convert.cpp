// SciPy and NumPy objects to the library's types and back (python/convert.h).
#include "convert.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>

#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs::python {

namespace {

std::string type_name(py::handle x) { return py::str(py::type::of(x).attr("__name__")).cast<std::string>(); }

std::string entry(int row, int col, double value) {
  std::ostringstream s;
  s.precision(17);
  s << "A[" << row << ", " << col << "] = " << value;
  return s.str();
}

// Lower-triangle position order: by column, then row (the order of a SymmetricCsc's entries).
bool before(const Triplet& x, const Triplet& y) { return x.col != y.col ? x.col < y.col : x.row < y.row; }

// Every entry below the diagonal must meet its mirror image above it with the same value. Both
// lists are in lower-triangle positions (the upper entries transposed) and sorted; the first
// entry without a partner, or with a different one, is named.
void check_symmetric(const std::vector<Triplet>& lower, const std::vector<Triplet>& upper) {
  const std::string hint = " (A must be symmetric in pattern and values; lower=True takes its lower triangle alone)";
  auto unpaired = [&](int row, int col, double value) {
    return InputError("A is not symmetric: " + entry(row, col, value) + " is stored but A[" + std::to_string(col) +
                      ", " + std::to_string(row) + "] is not" + hint);
  };
  size_t u = 0;
  for (const Triplet& l : lower) {
    if (l.row == l.col) continue;
    if (u < upper.size() && before(upper[u], l)) throw unpaired(upper[u].col, upper[u].row, upper[u].value);
    if (u == upper.size() || before(l, upper[u])) throw unpaired(l.row, l.col, l.value);
    if (upper[u].value != l.value)
      throw InputError("A is not symmetric: " + entry(l.row, l.col, l.value) + " but " +
                       entry(l.col, l.row, upper[u].value) + hint);
    ++u;
  }
  if (u < upper.size()) throw unpaired(upper[u].col, upper[u].row, upper[u].value);
}

}  // namespace

SymmetricCsc symmetric_from_scipy(py::handle a, bool lower) {
  const py::module_ np = py::module_::import("numpy"), sp = py::module_::import("scipy.sparse");
  if (!sp.attr("issparse")(a).cast<bool>())
    throw InputError("A must be a scipy.sparse matrix, got " + type_name(a) + " (scipy.sparse.csc_matrix(A) converts)");
  const auto shape = a.attr("shape").cast<std::pair<int64_t, int64_t>>();
  if (shape.first != shape.second)
    throw InputError("A is " + std::to_string(shape.first) + " x " + std::to_string(shape.second) + ": not square");
  if (shape.first == 0) throw InputError("A is 0 x 0: empty");
  if (shape.first > std::numeric_limits<int>::max() / 2) throw InputError("A is too large for 32-bit indices");
  if (np.attr("iscomplexobj")(a).cast<bool>()) throw InputError("A is complex: only real matrices are supported");
  // A copy in CSC, float64, duplicates summed and rows sorted within columns.
  py::object c = a.attr("tocsc")().attr("astype")(np.attr("float64"), py::arg("copy") = true);
  c.attr("sum_duplicates")();
  const auto indptr = c.attr("indptr").cast<py::array_t<int64_t, py::array::c_style | py::array::forcecast>>();
  const auto indices = c.attr("indices").cast<py::array_t<int64_t, py::array::c_style | py::array::forcecast>>();
  const auto data = c.attr("data").cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
  const int n = static_cast<int>(shape.first);
  if (indices.size() > std::numeric_limits<int>::max()) throw InputError("A has too many entries for 32-bit indices");
  const int64_t* ptr = indptr.data();
  const int64_t* row = indices.data();
  const double* value = data.data();
  std::vector<Triplet> low, up;  // up: the entries above the diagonal, transposed
  for (int j = 0; j < n; ++j) {
    for (int64_t p = ptr[j]; p < ptr[j + 1]; ++p) {
      const int i = static_cast<int>(row[p]);
      if (!std::isfinite(value[p])) throw InputError("A is not finite: " + entry(i, j, value[p]));
      if (i >= j) {
        low.push_back({i, j, value[p]});
      } else if (lower) {
        throw InputError(entry(i, j, value[p]) + " is above the diagonal: lower=True takes the lower triangle alone");
      } else {
        up.push_back({j, i, value[p]});
      }
    }
  }
  if (!lower) {
    std::sort(up.begin(), up.end(), before);
    check_symmetric(low, up);
  }
  return csc_from_triplets(n, low);
}

BlockPattern block_pattern_from(py::handle blocks, const SymmetricCsc& a, int max_block) {
  std::vector<int> sizes;
  if (py::isinstance<py::str>(blocks) || py::hasattr(blocks, "__fspath__")) {
    sizes = parse_partition(py::str(blocks).cast<std::string>(), a, max_block);
  } else if (py::isinstance<py::bool_>(blocks)) {
    throw InputError("blocks must be \"auto\", a block size, a partition file or a sequence of block sizes, got a bool");
  } else if (py::isinstance<py::int_>(blocks)) {
    sizes = parse_partition(std::to_string(blocks.cast<int64_t>()), a, max_block);
  } else {
    try {
      sizes = blocks.cast<std::vector<int>>();
    } catch (const py::cast_error&) {
      throw InputError("blocks must be \"auto\", a block size, a partition file or a sequence of block sizes, got " +
                       type_name(blocks));
    }
    for (size_t b = 0; b < sizes.size(); ++b)
      if (sizes[b] < 1)
        throw InputError("blocks[" + std::to_string(b) + "] = " + std::to_string(sizes[b]) + ": block sizes must be positive");
    const int64_t sum = std::accumulate(sizes.begin(), sizes.end(), int64_t{0});
    if (sum != a.n)
      throw InputError("blocks sum to " + std::to_string(sum) + " rows, A has " + std::to_string(a.n));
  }
  return BlockPattern::from_scalar(a, sizes);
}

std::vector<std::string> ordering_names(py::handle orderings) {
  if (py::isinstance<py::str>(orderings)) return parse_ordering_list(orderings.cast<std::string>());
  std::string list;
  for (py::handle name : orderings) {
    if (!list.empty()) list += ',';
    list += py::str(name).cast<std::string>();
  }
  return parse_ordering_list(list);
}

py::object scipy_csc(int n, std::span<const int> col_ptr, std::span<const int> row_idx,
                     std::span<const double> values) {
  const py::module_ sp = py::module_::import("scipy.sparse");
  return sp.attr("csc_matrix")(py::make_tuple(numpy_copy(values), numpy_copy(row_idx), numpy_copy(col_ptr)),
                               py::arg("shape") = py::make_tuple(n, n));
}

py::array_t<double, py::array::f_style> dense_copy(py::handle x, const char* name) {
  const py::module_ np = py::module_::import("numpy"), sp = py::module_::import("scipy.sparse");
  if (sp.attr("issparse")(x).cast<bool>())
    throw InputError(std::string(name) + " must be dense (a NumPy array), got a scipy.sparse matrix (.toarray() converts)");
  if (np.attr("iscomplexobj")(x).cast<bool>()) throw InputError(std::string(name) + " is complex: only real arrays are supported");
  try {
    return np.attr("array")(x, py::arg("dtype") = np.attr("float64"), py::arg("order") = "F", py::arg("copy") = true)
        .cast<py::array_t<double, py::array::f_style>>();
  } catch (const py::error_already_set& e) {
    throw InputError(std::string(name) + " is not an array of numbers (" + e.what() + ")");
  }
}

}  // namespace ldlpgs::python
