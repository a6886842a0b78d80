#include "sparse/cholmod_adapter.h"

#include <cassert>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "sparse/error.h"

namespace ldlpgs {

Cholmod::Cholmod() { cholmod_start(&common_); }
Cholmod::~Cholmod() { cholmod_finish(&common_); }

cholmod_sparse cholmod_view(const SymmetricCsc& a) {
  cholmod_sparse s{};
  s.nrow = s.ncol = static_cast<size_t>(a.n);
  s.nzmax = static_cast<size_t>(a.nnz());
  // CHOLMOD's struct has no const members; it only reads through these when given as input.
  s.p = const_cast<int*>(a.col_ptr.data());
  s.i = const_cast<int*>(a.row_idx.data());
  s.x = const_cast<double*>(a.values.data());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
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
  FILE* f = std::fopen(path.c_str(), "r");
  if (!f) throw InputError(path + ": cannot open file");
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

CholmodCounts cholmod_counts(const SymmetricCsc& a, std::span<const int> perm, Cholmod& cm) {
  assert(static_cast<int>(perm.size()) == a.n);
  cholmod_common* c = cm.common();
  // Without these three settings CHOLMOD silently tries its own orderings, postorders the one
  // given, or builds a supernodal LL^T: the counts would not be those of this permutation.
  const int nmethods = c->nmethods, ordering = c->method[0].ordering, postorder = c->postorder,
            supernodal = c->supernodal;
  c->nmethods = 1;
  c->method[0].ordering = CHOLMOD_GIVEN;
  c->postorder = false;
  c->supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse view = cholmod_view(a);
  std::vector<int> p(perm.begin(), perm.end());
  cholmod_factor* factor = cholmod_analyze_p(&view, p.data(), nullptr, 0, c);
  CholmodCounts counts{c->lnz, c->fl};
  const bool ok = factor != nullptr && c->status == CHOLMOD_OK;
  cholmod_free_factor(&factor, c);
  c->nmethods = nmethods;
  c->method[0].ordering = ordering;
  c->postorder = postorder;
  c->supernodal = supernodal;
  if (!ok) throw std::runtime_error("cholmod_analyze_p failed with status " + std::to_string(c->status));
  return counts;
}

}  // namespace ldlpgs
