#include "ldlpgs/sparse/cholmod_adapter.h"

#include <cassert>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/text.h"

namespace ldlpgs {

Cholmod::Cholmod() { cholmod_start(&common_); }
Cholmod::~Cholmod() { cholmod_finish(&common_); }

cholmod_sparse cholmod_view(const SymmetricCsc& a) {
  cholmod_sparse s{};
  s.nrow = s.ncol = static_cast<size_t>(a.n);
  s.nzmax = static_cast<size_t>(a.nnz());
  // CHOLMOD's struct has no const members; it only reads through these when given as input.
  // A matrix without stored entries has empty vectors, whose data() may be null, and CHOLMOD
  // refuses a null i or x as an invalid xtype (status -4, on a 0 x 0 or all-empty matrix):
  // point them at a never-read dummy.
  static int no_index = 0;
  static double no_value = 0;
  s.p = const_cast<int*>(a.col_ptr.empty() ? &no_index : a.col_ptr.data());
  s.i = a.row_idx.empty() ? &no_index : const_cast<int*>(a.row_idx.data());
  s.x = a.values.empty() ? &no_value : const_cast<double*>(a.values.data());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

cholmod_dense cholmod_view(std::span<double> x) {
  cholmod_dense d{};
  d.nrow = d.d = d.nzmax = x.size();
  d.ncol = 1;
  d.x = x.data();
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

SymmetricCsc from_cholmod(const cholmod_sparse& a, Cholmod& cm) {
  assert(a.nrow == a.ncol && a.xtype == CHOLMOD_REAL && a.itype == CHOLMOD_INT);
  (void)cm;
  const int n = static_cast<int>(a.ncol);
  const int* ap = static_cast<const int*>(a.p);
  const int* anz = static_cast<const int*>(a.nz);
  const int* ai = static_cast<const int*>(a.i);
  const double* ax = static_cast<const double*>(a.x);
  std::vector<Triplet> entries;
  for (int j = 0; j < n; ++j) {
    const int end = a.packed ? ap[j + 1] : ap[j] + anz[j];
    for (int p = ap[j]; p < end; ++p) {
      const int i = ai[p];
      // stype = 1 keeps the upper triangle, -1 the lower, 0 both: keep the stored triangle.
      if ((a.stype > 0 && i > j) || (a.stype < 0 && i < j) || (a.stype == 0 && i < j)) continue;
      entries.push_back({i, j, ax[p]});
    }
  }
  return csc_from_triplets(n, entries);
}

SymmetricCsc cholmod_read(const std::string& path, Cholmod& cm) {
  FILE* f = open_input(path);
  cholmod_sparse* s = cholmod_read_sparse(f, cm.common());
  std::fclose(f);
  if (!s) throw InputError(path + ": CHOLMOD's reader refused the file");
  if (s->xtype != CHOLMOD_REAL || s->nrow != s->ncol) {
    cholmod_free_sparse(&s, cm.common());
    throw InputError(path + ": not a real square matrix");
  }
  SymmetricCsc a = from_cholmod(*s, cm);
  cholmod_free_sparse(&s, cm.common());
  return a;
}

namespace {

// For its lifetime, makes CHOLMOD analyze and factor in exactly the order given to
// cholmod_analyze_p as a simplicial LDL^T, left as LDL^T, packed and monotonic; restores the
// caller's settings at the end. Without it CHOLMOD silently tries its own orderings, postorders
// the one given, builds a supernodal LL^T, or converts the factor when done (final_*): neither
// the counts nor the factor would be those of this permutation in this convention.
class GivenOrderLdl {
 public:
  explicit GivenOrderLdl(cholmod_common* c) : c_(c), saved_(read(*c)) {
    write(*c, {.nmethods = 1,
               .ordering = CHOLMOD_GIVEN,
               .postorder = false,
               .supernodal = CHOLMOD_SIMPLICIAL,
               .final_asis = false,
               .final_super = false,
               .final_ll = false,
               .final_pack = true,
               .final_monotonic = true,
               .final_resymbol = false,
               .print = 0});
  }
  ~GivenOrderLdl() { write(*c_, saved_); }
  GivenOrderLdl(const GivenOrderLdl&) = delete;
  GivenOrderLdl& operator=(const GivenOrderLdl&) = delete;

 private:
  struct Settings {
    int nmethods, ordering, postorder, supernodal;
    int final_asis, final_super, final_ll, final_pack, final_monotonic, final_resymbol;
    int print;  // 0: a zero pivot is the returned status, not also CHOLMOD's warning on stderr
  };
  static Settings read(const cholmod_common& c) {
    return {c.nmethods,  c.method[0].ordering, c.postorder, c.supernodal,     c.final_asis,
            c.final_super, c.final_ll,         c.final_pack, c.final_monotonic, c.final_resymbol, c.print};
  }
  static void write(cholmod_common& c, const Settings& s) {
    c.nmethods = s.nmethods;
    c.method[0].ordering = s.ordering;
    c.postorder = s.postorder;
    c.supernodal = s.supernodal;
    c.final_asis = s.final_asis;
    c.final_super = s.final_super;
    c.final_ll = s.final_ll;
    c.final_pack = s.final_pack;
    c.final_monotonic = s.final_monotonic;
    c.final_resymbol = s.final_resymbol;
    c.print = s.print;
  }

  cholmod_common* c_;
  Settings saved_;
};

// cholmod_analyze_p of a under perm with the current settings; throws if CHOLMOD fails (out of
// memory, or an invalid matrix), which is neither bad user input nor a numerical failure.
cholmod_factor* analyze_given(cholmod_sparse& view, std::span<const int> perm, cholmod_common* c) {
  std::vector<int> p(perm.begin(), perm.end());  // CHOLMOD takes a non-const pointer
  cholmod_factor* factor = cholmod_analyze_p(&view, p.data(), nullptr, 0, c);
  if (factor == nullptr || c->status != CHOLMOD_OK) {
    cholmod_free_factor(&factor, c);
    throw std::runtime_error("cholmod_analyze_p failed with status " + std::to_string(c->status));
  }
  return factor;
}

}  // namespace

CholmodCounts cholmod_counts(const SymmetricCsc& a, std::span<const int> perm, Cholmod& cm) {
  check_symmetric_csc(a, "cholmod_counts");
  check_permutation(perm, a.n, "cholmod_counts");
  if (a.n == 0) return {0, 0};  // CHOLMOD's analysis refuses n = 0 (status -4)
  cholmod_common* c = cm.common();
  const GivenOrderLdl settings(c);
  cholmod_sparse view = cholmod_view(a);
  cholmod_factor* factor = analyze_given(view, perm, c);
  const CholmodCounts counts{c->lnz, c->fl};
  cholmod_free_factor(&factor, c);
  return counts;
}

CholmodLdl cholmod_ldl(const SymmetricCsc& a, std::span<const int> perm, std::span<const double> b,
                       Cholmod& cm) {
  check_symmetric_csc(a, "cholmod_ldl");
  check_permutation(perm, a.n, "cholmod_ldl");
  if (!b.empty() && std::ssize(b) != a.n)
    throw ArgumentError("cholmod_ldl: right-hand side of " + std::to_string(b.size()) + " entries for " +
                        std::to_string(a.n) + " rows");
  if (a.n == 0) return {SymmetricCsc{0, {0}, {}, {}}, {}, CHOLMOD_OK, 0};  // CHOLMOD refuses n = 0
  cholmod_common* c = cm.common();
  const GivenOrderLdl settings(c);
  cholmod_sparse view = cholmod_view(a);
  cholmod_factor* factor = analyze_given(view, perm, c);
  // A zero pivot is a warning (status > 0) and leaves L numeric; only status < 0 (out of
  // memory) leaves no factor to report.
  cholmod_factorize(&view, factor, c);
  CholmodLdl out{{}, {}, c->status, static_cast<int>(factor->minor)};
  if (out.status < CHOLMOD_OK) {
    cholmod_free_factor(&factor, c);
    throw std::runtime_error("cholmod_factorize failed with status " + std::to_string(out.status));
  }
  if (!b.empty() && out.minor == a.n) {
    // CHOLMOD_A applies P^T L^-T D^-1 L^-1 P, so x comes back in the original row order.
    std::vector<double> rhs(b.begin(), b.end());
    cholmod_dense bview = cholmod_view(std::span<double>(rhs));
    cholmod_dense* x = cholmod_solve(CHOLMOD_A, factor, &bview, c);
    if (x == nullptr) {
      cholmod_free_factor(&factor, c);
      throw std::runtime_error("cholmod_solve failed with status " + std::to_string(c->status));
    }
    const double* xs = static_cast<const double*>(x->x);
    out.x.assign(xs, xs + a.n);
    cholmod_free_dense(&x, c);
  }
  // cholmod_factor_to_sparse packs L and makes it monotonic but keeps its kind (it calls
  // cholmod_change_factor with L->is_ll): an LDL^T stays LDL^T, with D on the diagonal, not
  // sqrt(D). Its columns are sorted already (the row-by-row factorization appends row k to each
  // column in increasing k). It hands L's arrays over and leaves the factor symbolic.
  assert(!factor->is_ll && !factor->is_super);
  cholmod_sparse* l = cholmod_factor_to_sparse(factor, c);
  cholmod_free_factor(&factor, c);
  if (l == nullptr) throw std::runtime_error("cholmod_factor_to_sparse failed with status " + std::to_string(c->status));
  out.l = from_cholmod(*l, cm);
  cholmod_free_sparse(&l, c);
  return out;
}

}  // namespace ldlpgs
