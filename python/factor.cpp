// The sparse side of the module: orderings and their costs (ordering/), CHOLMOD's counts for a
// permutation, the block LDL^T as a Factor shaped after scikit-sparse's cholmod.Factor
// (factor/), and the comparison with CHOLMOD that `ldlpgs verify --json` prints (factor/verify.h).
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "bindings.h"
#include "convert.h"
#include "ldlpgs/factor/factor.h"
#include "ldlpgs/factor/verify.h"
#include "ldlpgs/ordering/certify.h"
#include "ldlpgs/ordering/metrics.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/version.h"
#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/eigen_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/matrix_market.h"

namespace ldlpgs::python {

namespace {

// A permutation of 0 .. n-1: a 1-D integer array, checked by the library (check_permutation)
// once its entries are known to fit an int.
std::vector<int> permutation_from(py::handle perm, int n) {
  const py::object array = py::module_::import("numpy").attr("asarray")(perm);
  // (forcecast alone had truncated [0.5, 1, 2] to [0, 1, 2] without a word)
  const int ndim = array.attr("ndim").cast<int>();
  if (ndim != 1) throw ArgumentError("perm must be a 1-D array, got " + std::to_string(ndim) + " dimensions");
  const std::string kind = py::str(array.attr("dtype").attr("kind"));
  if (kind != "i" && kind != "u" && py::len(array) > 0)  // (an empty list is float64 in NumPy)
    throw ArgumentError("perm must be an array of integers, got dtype " + std::string(py::str(array.attr("dtype"))));
  const auto p = array.cast<py::array_t<int64_t, py::array::c_style | py::array::forcecast>>();
  std::vector<int> out(p.size());
  for (py::ssize_t k = 0; k < p.size(); ++k) {
    if (p.at(k) < 0 || p.at(k) >= n)  // named here: an int64 outside int's range cannot reach check_permutation
      throw ArgumentError("cholmod_counts: entry " + std::to_string(k) + " of the permutation, " + std::to_string(p.at(k)) +
                          ", is outside 0.." + std::to_string(n - 1));
    out[k] = static_cast<int>(p.at(k));
  }
  check_permutation(out, n, "cholmod_counts");
  return out;
}

// CHOLMOD's counts as a dict with the names of our own counts.
py::dict counts_dict(const CholmodCounts& c) {
  py::dict d;
  d["nnz_L"] = static_cast<int64_t>(c.lnz);
  d["flops"] = c.fl;
  return d;
}

// A non-finite double as None, as the program's JSON writes it.
py::object number(double x) { return std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none()); }

// One analyzed pattern and, after factorize, its numeric factor. The Symbolic is owned here (the
// Numeric keeps a pointer to it).
struct Factor {
  BlockPattern blocks;
  Ordering ordering;
  std::unique_ptr<Symbolic> symbolic;
  std::unique_ptr<Numeric> numeric;
  // (the analyzed pattern, checked by factorize, and whether a factorization ran are the
  // library's: Symbolic::check_pattern, Numeric::factored)
  bool factored() const { return numeric->factored(); }
  int n() const { return symbolic->num_rows(); }

  const FactorInfo& usable(const char* what) const {
    if (!factored()) throw ArgumentError(std::string(what) + ": factorize(A) first");
    const FactorInfo& info = numeric->info();
    if (!info.usable()) throw ArgumentError(std::string(what) + ": the factorization failed: " + info.message());
    return info;
  }

  py::array_t<double, py::array::f_style> solve(py::handle b) const {
    usable("solve");
    py::array_t<double, py::array::f_style> x = dense_copy(b, "b");
    const int n = this->n();
    if (x.ndim() < 1 || x.ndim() > 2 || x.shape(0) != n)
      throw ArgumentError("b must have " + std::to_string(n) + " rows (shape (n,) or (n, k)), got shape " +
                          py::str(py::object(x.attr("shape"))).cast<std::string>());
    const int nrhs = x.ndim() == 1 ? 1 : static_cast<int>(x.shape(1));
    if (nrhs > 0) numeric->solve(x.mutable_data(), nrhs, n);
    return x;
  }
};

Factor analyze(py::handle a_in, py::handle blocks, const std::string& ordering_name, int max_block, bool lower) {
  const OrderingInfo& info = find_ordering(ordering_name);
  Factor f;
  const SymmetricCsc pattern = symmetric_from_scipy(a_in, lower);
  f.blocks = block_pattern_from(blocks, pattern, max_block);
  f.ordering = compute_ordering(info, f.blocks, pattern);
  f.symbolic = std::make_unique<Symbolic>(Symbolic::analyze(pattern, f.blocks, f.ordering));
  f.numeric = std::make_unique<Numeric>(*f.symbolic);
  return f;
}

const char* const kMatrixDoc =
    "A: a square symmetric real scipy.sparse matrix (any format). By default A is the full matrix, as "
    "scipy.io.mmread returns a Matrix Market symmetric file, and must be symmetric in pattern and values "
    "exactly; lower=True takes A's lower triangle alone (what the file and the library store) and refuses "
    "entries above the diagonal. Explicit zeros are entries of the pattern; duplicates are summed.\n"
    "blocks: \"auto\" (consecutive rows with identical patterns, at most max_block rows), an integer "
    "(uniform blocks), a partition file (one block size per line) or a sequence of block sizes.\n";

}  // namespace

void bind_factor(py::module_& m) {
  m.def(
      "orderings",
      [] {
        py::dict d;
        for (const OrderingInfo& o : orderings()) d[py::str(std::string(o.name))] = std::string(o.summary);
        return d;
      },
      "The orderings' names, in the order reports list them, with a one-line summary of each.");

  m.def(
      "mmread",
      [](const std::string& path) {
        Eigen::SparseMatrix<double> full = to_eigen(read_matrix_market(path), Triangle::full);
        full.makeCompressed();
        const int nnz = static_cast<int>(full.nonZeros());
        return scipy_csc(static_cast<int>(full.rows()), {full.outerIndexPtr(), static_cast<size_t>(full.cols()) + 1},
                         {full.innerIndexPtr(), static_cast<size_t>(nnz)}, {full.valuePtr(), static_cast<size_t>(nnz)});
      },
      py::arg("path"),
      "A Matrix Market file as the program reads it (sparse/matrix_market.h), as the full symmetric "
      "scipy.sparse.csc_matrix. Unlike scipy.io.mmread, a pattern file gets CHOLMOD's values (off-diagonal -1, "
      "diagonal 1 + degree: positive definite), so that verify() and the factor see the program's matrix.");

  m.def(
      "order",
      [](py::handle a_in, py::handle blocks, py::handle orderings_arg, int max_block, bool cholmod, bool lower,
         bool certify, double certify_time_limit_s) {
        const std::vector<std::string> names = ordering_names(orderings_arg);
        const SymmetricCsc a = symmetric_from_scipy(a_in, lower);
        const BlockPattern bp = block_pattern_from(blocks, a, max_block);
        const Graph scalar_graph = graph_of(a);
        std::optional<Cholmod> cm;
        if (cholmod) cm.emplace();
        if (!(certify_time_limit_s >= 0) || !std::isfinite(certify_time_limit_s))
          throw py::value_error("certify_time_limit_s must be finite and >= 0");
        std::vector<std::pair<Ordering, OrderingSummary>> computed;
        const std::pair<Ordering, OrderingSummary>* known = nullptr;  // fewest block flops: prunes certify
        for (const std::string& name : names) {
          Ordering o = compute_ordering(find_ordering(name), bp, a);
          OrderingSummary s = summarize(o, bp, scalar_graph);
          computed.emplace_back(std::move(o), std::move(s));
        }
        for (const auto& c : computed)
          if (c.second.block && (!known || c.second.block->flops < known->second.block->flops)) known = &c;
        std::optional<BlockFlopsCertificate> cert;
        if (certify) {
          cert = certify_block_flops(bp, certify_time_limit_s,
                                     known ? std::span<const int>(known->first.pivots) : std::span<const int>());
          // as `ldlpgs order --certify`: an optimum below every ordering is an entry, "optimal"
          const double fewest = known ? known->second.block->flops : std::numeric_limits<double>::infinity();
          if (std::optional<Ordering> o = certificate_ordering(bp, *cert, fewest)) {
            OrderingSummary s = summarize(*o, bp, scalar_graph);
            computed.emplace_back(std::move(*o), std::move(s));
          }
        }
        py::dict out;
        for (const auto& [o, s] : computed) {
          const std::string& name = s.name;
          py::dict r;
          r["ordering"] = s.name;
          r["chosen"] = o.chosen;
          r["perm"] = numpy_copy<int>(o.perm);
          r["nnz_L"] = s.nnz_L;
          r["flops"] = s.flops;
          r["block_fill_edges"] = s.block ? py::object(py::int_(s.block->fill_edges)) : py::object(py::none());
          r["block_flops"] = s.block ? py::object(py::float_(s.block->flops)) : py::object(py::none());
          r["ordering_ms"] = s.time_ms;
          if (cert) {  // as `ldlpgs order --certify --json` (apps/compare.cpp)
            r["certified_optimal"] = s.block && certified_optimal(*cert, s.block->flops);
            r["lower_bound_block_flops"] = cert->lower_bound;
            r["optimum_proved"] = cert->optimal_proved;
          }
          if (cm) {
            const CholmodCounts c = cholmod_counts(a, o.perm, *cm);
            r["cholmod_nnz_L"] = static_cast<int64_t>(c.lnz);
            r["cholmod_flops"] = c.fl;
          }
          out[py::str(name)] = r;
        }
        return out;
      },
      py::arg("A"), py::arg("blocks") = "auto", py::arg("orderings") = "all", py::arg("max_block") = 6,
      py::arg("cholmod") = false, py::arg("lower") = false, py::arg("certify") = false,
      py::arg("certify_time_limit_s") = 10.0,
      (std::string("Every requested ordering on A's block graph (what `ldlpgs order --json` prints): a dict from "
                   "ordering name to a dict with perm (the scalar pivot order, perm[k] = row eliminated k-th), "
                   "nnz_L and flops (scalar, as CHOLMOD counts them), block_fill_edges and block_flops (None for "
                   "the -scalar orderings, which may split blocks) and ordering_ms; with cholmod=True also "
                   "cholmod_nnz_L and cholmod_flops, CHOLMOD's counts for the same permutation (the names of "
                   "docs/cli.md's vocabulary); chosen, the ordering that gave perm (best's winner); with "
                   "certify=True also certified_optimal (no block order has fewer block flops), "
                   "lower_bound_block_flops and optimum_proved (the bound is the optimum), as `ldlpgs order "
                   "--certify`, within certify_time_limit_s, and an entry \"optimal\" (chosen \"certify\") with the "
                   "certificate's order when it proves an optimum that no ordering reached.\n"
                   "orderings: \"all\", comma-separated names, or a sequence of names (see orderings()).\n") +
       kMatrixDoc)
          .c_str());

  m.def(
      "block_sizes",
      [](py::handle a_in, py::handle blocks, int max_block, bool lower) {
        const SymmetricCsc a = symmetric_from_scipy(a_in, lower);
        return numpy_copy<int>(block_pattern_from(blocks, a, max_block).block_sizes());
      },
      py::arg("A"), py::arg("blocks") = "auto", py::arg("max_block") = 6, py::arg("lower") = false,
      (std::string("The block partition order() and analyze() use for these arguments: the rows of each block, "
                   "in order (its length is the `blocks` of `ldlpgs order --json`).\n") +
       kMatrixDoc)
          .c_str());

  m.def(
      "cholmod_counts",
      [](py::handle a_in, py::handle perm, bool lower) {
        const SymmetricCsc a = symmetric_from_scipy(a_in, lower);
        Cholmod cm;
        return counts_dict(cholmod_counts(a, permutation_from(perm, a.n), cm));
      },
      py::arg("A"), py::arg("perm"), py::arg("lower") = false,
      "CHOLMOD's symbolic counts (cholmod_analyze_p, the given order, no postordering) for the simplicial LDL^T "
      "of A[perm][:, perm]: nnz_L (Common->lnz, diagonal included) and flops (Common->fl). The reference for "
      "order()'s nnz_L and flops.");

  py::class_<Factor>(m, "Factor",
                     "The block LDL^T of one sparsity pattern, shaped after scikit-sparse's cholmod.Factor: analyze() "
                     "runs the ordering and the symbolic phase once, factorize(A) the numeric phase for any matrix "
                     "of that pattern. With P = P(), L = L() and D = D():\n"
                     "    A[P][:, P] + regularization * diag(A[P][:, P]) = L @ diag(D) @ L.T")
      .def(
          "factorize",
          [](py::object self, py::handle a_in, double regularization, double zero_pivot, bool lower) {
            Factor& f = self.cast<Factor&>();
            if (!(regularization >= 0) || !std::isfinite(regularization))
              throw ArgumentError("regularization must be finite and >= 0");
            if (!(zero_pivot >= 0) || !std::isfinite(zero_pivot)) throw ArgumentError("zero_pivot must be finite and >= 0");
            const SymmetricCsc a = symmetric_from_scipy(a_in, lower);
            // Another pattern or size than analyzed: the library's ArgumentError (Symbolic::check_pattern).
            f.numeric->factorize(a, {.regularization = regularization, .zero_pivot = zero_pivot});
            return self;
          },
          py::arg("A"), py::arg("regularization") = FactorOptions{}.regularization,
          py::arg("zero_pivot") = FactorOptions{}.zero_pivot, py::arg("lower") = false,
          "Factors A + regularization * diag(A) (A of the analyzed pattern). A zero or non-finite pivot does not "
          "raise: status says so, and solve, L and D then raise.")
      .def("solve", &Factor::solve, py::arg("b"),
           "x with A x = b, for b of shape (n,) or (n, k) (k right-hand sides); b is not changed.")
      .def("solve_A", &Factor::solve, py::arg("b"), "solve(b), scikit-sparse's name.")
      .def("__call__", &Factor::solve, py::arg("b"), "solve(b), as scikit-sparse's Factor.")
      .def(
          "L",
          [](const Factor& f) {
            f.usable("L");
            SymmetricCsc l = f.numeric->scalar_ldl();
            for (int j = 0; j < l.n; ++j)  // CHOLMOD keeps D on the diagonal; L itself is unit there
              for (int p = l.col_ptr[j]; p < l.col_ptr[j + 1]; ++p)
                if (l.row_idx[p] == j) l.values[p] = 1;
            return scipy_csc(l.n, l.col_ptr, l.row_idx, l.values);
          },
          "The unit lower triangular factor of A[P][:, P] in CHOLMOD's scalar "
          "convention (Numeric::scalar_ldl), every block dense (explicit zeros included).")
      .def(
          "D",
          [](const Factor& f) {
            f.usable("D");
            const SymmetricCsc l = f.numeric->scalar_ldl();
            std::vector<double> d(l.n, 0.0);
            for (int j = 0; j < l.n; ++j)
              for (int p = l.col_ptr[j]; p < l.col_ptr[j + 1]; ++p)
                if (l.row_idx[p] == j) d[j] = l.values[p];
            return numpy_copy<double>(d);
          },
          "The diagonal of D (scikit-sparse's D() also returns the diagonal).")
      .def(
          "P", [](const Factor& f) { return numpy_copy<int>(f.symbolic->perm()); },
          "The fill-reducing permutation, P[k] = row eliminated k-th (scikit-sparse's).")
      .def_property_readonly(
          "status",
          [](const Factor& f) { return f.factored() ? py::object(py::str(to_string(f.numeric->info().status))) : py::object(py::none()); },
          "\"ok\" (positive definite), \"indefinite\", \"zero pivot\", \"not finite\" (to_string(FactorStatus), as `ldlpgs verify` prints it); None before factorize.")
      .def_property_readonly(
          "inertia",
          [](const Factor& f) -> py::object {
            if (!f.factored()) return py::none();
            const Inertia& i = f.numeric->info().inertia;
            return py::make_tuple(i.positive, i.negative, i.zero);
          },
          "(positive, negative, zero) pivots counted (all of them when the factorization completed); None "
          "before factorize.")
      .def_property_readonly(
          "message",
          [](const Factor& f) { return f.factored() ? py::object(py::str(f.numeric->info().message())) : py::object(py::none()); },
          "One line naming the status and, if any, the failing (or first negative) block, row and pivot.")
      .def_property_readonly(
          "min_pivot_ratio",
          [](const Factor& f) { return f.factored() ? py::object(py::float_(f.numeric->info().min_pivot_ratio)) : py::object(py::none()); },
          "min over pivots of |d_r| / |A_rr|: near 0 means nearly singular.")
      .def_property_readonly("n", [](const Factor& f) { return f.n(); })
      .def_property_readonly("ordering", [](const Factor& f) { return f.ordering.name; })
      .def_property_readonly("chosen", [](const Factor& f) { return f.ordering.chosen; },
                             "The ordering whose pivots the factor uses: `ordering`, or the one `best` chose.")
      .def_property_readonly("nnz_L", [](const Factor& f) { return f.symbolic->nnz_l(); },
                             "Entries of L with the diagonal, every block dense.")
      .def_property_readonly("flops", [](const Factor& f) { return f.symbolic->flops(); },
                             "Flops of the factorization as CHOLMOD counts them, every block dense.")
      .def_property_readonly("block_sizes", [](const Factor& f) { return numpy_copy<int>(f.blocks.block_sizes()); })
      .def("__repr__", [](const Factor& f) {
        return "<ldlpgs.Factor n=" + std::to_string(f.n()) + " blocks=" + std::to_string(f.blocks.num_blocks()) +
               " ordering=" + f.ordering.name + " status=" +
               (f.factored() ? to_string(f.numeric->info().status) : "unfactored") + ">";
      });

  m.def("analyze", &analyze, py::arg("A"), py::arg("blocks") = "auto", py::arg("ordering") = "best",
        py::arg("max_block") = 6, py::arg("lower") = false,
        (std::string("The ordering and symbolic phase of A's block LDL^T (values ignored); then "
                     "f.factorize(A). ordering: a name from orderings().\n") +
         kMatrixDoc)
            .c_str());

  m.def(
      "verify",
      [](py::handle a_in, py::handle blocks, const std::string& ordering_name, int max_block, double tolerance,
         double per_condition, double backward_tolerance, const std::string& name, bool lower) {
        const OrderingInfo& info = find_ordering(ordering_name);
        const SymmetricCsc a = symmetric_from_scipy(a_in, lower);
        const BlockPattern bp = block_pattern_from(blocks, a, max_block);
        const Ordering ordering = compute_ordering(info, bp, a);
        const Verification v = verify_against_cholmod(
            a, bp, ordering, {.factor = tolerance, .per_condition = per_condition, .backward = backward_tolerance});
        // The fields of `ldlpgs verify --json` (apps/verify_command.cpp, where the program builds its
        // JSON: not in the library); tests/test_factor.py compares the keys with the program's.
        py::dict d;
        d["ldlpgs_version"] = kVersion;
        d["command"] = "verify";
        d["matrix"] = name;
        d["n"] = a.n;
        d["blocks"] = bp.num_blocks();
        d["ordering"] = v.ordering;
        d["chosen"] = v.chosen;
        d["nnz_L"] = v.nnz_L;
        d["cholmod_nnz_L"] = v.nnz_L_cholmod;
        d["flops"] = v.flops;
        d["cholmod_flops"] = v.flops_cholmod;
        d["L_rel_diff"] = number(v.L_rel_diff);
        d["D_rel_diff"] = number(v.D_rel_diff);
        d["x_rel_diff"] = number(v.x_rel_diff);
        d["backward_error"] = number(v.backward_error);
        d["cholmod_backward_error"] = number(v.backward_error_cholmod);
        d["status"] = to_string(v.info.status);
        py::dict inertia;
        inertia["positive"] = v.info.inertia.positive;
        inertia["negative"] = v.info.inertia.negative;
        inertia["zero"] = v.info.inertia.zero;
        d["inertia"] = inertia;
        d["min_pivot_ratio"] = v.info.min_pivot_ratio;
        d["cholmod_status"] = v.cholmod_status;
        d["cholmod_row"] = v.cholmod_row >= 0 ? py::object(py::int_(v.cholmod_row)) : py::object(py::none());
        d["condition_estimate"] = number(v.condition_estimate);
        py::dict t;
        t["factor"] = number(v.factor_tolerance);
        t["backward"] = v.tolerance.backward;
        d["tolerance"] = t;
        d["verifiable"] = v.verifiable;
        d["ok"] = v.ok;
        return d;
      },
      py::arg("A"), py::arg("blocks") = "auto", py::arg("ordering") = "best", py::arg("max_block") = 6,
      py::arg("tolerance") = VerifyTolerance{}.factor, py::arg("per_condition") = VerifyTolerance{}.per_condition,
      py::arg("backward_tolerance") = VerifyTolerance{}.backward, py::arg("name") = "A", py::arg("lower") = false,
      (std::string("Our block LDL^T against CHOLMOD's simplicial LDL^T in the same pivot order, and both solutions "
                   "of A x = A (1, -1, 1, ...)^T (factor/verify.h): the fields of `ldlpgs verify --json` (matrix "
                   "is `name`), ok True when they agree within the tolerances.\n") +
       kMatrixDoc)
          .c_str());
}

}  // namespace ldlpgs::python
