// The ldlpgs Python module's bindings (pybind11), the extension ldlpgs._ldlpgs that the package's
// __init__.py re-exports (python/ldlpgs/): orderings, the block LDL^T and its comparison with
// CHOLMOD on SciPy sparse matrices (factor.cpp), the rigid-body simulation (physics.cpp) and its
// viewer (view.cpp).
// Bad input raises ldlpgs.InputError and API misuse ldlpgs.ArgumentError, both ValueErrors
// carrying the library's message (sparse/error.h); any other C++ exception is a RuntimeError.
#include "bindings.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/version.h"

PYBIND11_MODULE(_ldlpgs, m) {
  namespace py = pybind11;
  m.doc() = "ldlpgs: block-sparse LDL^T with graph-elimination orderings, and LDL-PGS rigid-body physics.";
  m.attr("__version__") = ldlpgs::kVersion;
  // pybind11 tries the translators registered last first; its own turns every other
  // std::exception into a RuntimeError.
  py::register_exception<ldlpgs::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<ldlpgs::ArgumentError>(m, "ArgumentError", PyExc_ValueError);
  ldlpgs::python::bind_factor(m);
  ldlpgs::python::bind_physics(m);
  ldlpgs::python::bind_view(m);
}
