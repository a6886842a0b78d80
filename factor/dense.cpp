// The supernodal kernels (dense.h) on the reference BLAS interface, which Debian's OpenBLAS
// (build.sh installs libopenblas0-serial as libblas.so.3) implements with this machine's vector
// kernels. Declared here instead of through a cblas.h: the Fortran symbols are the one interface
// every libblas.so.3 alternative exports (CHOLMOD calls them the same way).
#include "ldlpgs/factor/dense.h"

#include <algorithm>
#include <cmath>

extern "C" {
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);
void dtrmm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
}

namespace ldlpgs::dense {

namespace {

// The inverse of the b x b lower triangle of the column-major block l (leading dimension ld) into
// inv (column-major, leading dimension b, zeros above); unit diagonal if unit. Column j is
// L^-1 e_j by forward substitution, its inner loop down a column of l.
void invert_lower(const double* l, int ld, int b, bool unit, double* inv) {
  for (int j = 0; j < b; ++j) {
    double* x = inv + static_cast<int64_t>(j) * b;
    std::fill_n(x, b, 0.0);
    x[j] = 1;
    for (int k = j; k < b; ++k) {
      const double* lk = l + static_cast<int64_t>(k) * ld;
      if (!unit) x[k] /= lk[k];
      const double xk = x[k];
      for (int i = k + 1; i < b; ++i) x[i] -= lk[i] * xk;
    }
  }
}

// A node block here is column-major lower (dense.h): entry (i, j), i >= j, at a[j * ld + i],
// LAPACK's "L". For a row-major m x n matrix X (stride ld_x), BLAS's X' = X^T (n x m), so
//   X L^-T  is  (L^-1 X')^T,
// forward substitution on X' by diagonal blocks of kSolveBlock: X'_k <- L_kk^-1 X'_k (dtrmm with
// the block's explicit inverse), then X'_below -= L_below,k X'_k (dgemm). OpenBLAS's left-side
// dtrsm kernel, which this replaces, ran 2-3x slower (papers/factor.md, "The rows' solve by
// blocks"); only a kSolveBlock triangle is ever inverted.
void solve_rows(bool unit, const double* node, int n, int ld_node, double* x, int m, int ld_x) {
  if (m == 0 || n == 0) return;
  const double one = 1, minus_one = -1;
  double inv[kSolveBlock * kSolveBlock];
  for (int k = 0; k < n; k += kSolveBlock) {
    const int b = std::min(kSolveBlock, n - k), below = n - k - b;
    const double* lkk = node + static_cast<int64_t>(k) * ld_node + k;
    invert_lower(lkk, ld_node, b, unit, inv);
    dtrmm_("L", "L", "N", unit ? "U" : "N", &b, &m, &one, inv, &b, x + k, &ld_x);
    if (below > 0)
      dgemm_("N", "N", &below, &m, &b, &minus_one, lkk + b, &ld_node, x + k, &ld_x, &one, x + k + b, &ld_x);
  }
}

// C[i0:i1, 0:i1] (+)= alpha A[i0:i1, :] B[0:i1, :]^T for the row panels [i0, i1) of the h x h
// row-major C (stride ldc); A, B h x k row-major with strides lda, ldb. BLAS sees
// C'[0:i1, i0:i1] = alpha B'[:, 0:i1]^T A'[:, i0:i1] + beta C'.
void lower_gemm(double alpha, const double* a, int lda, const double* b, int ldb, int h, int k, double beta,
                double* c, int ldc) {
  if (h == 0 || k == 0) return;
  for (int i0 = 0; i0 < h; i0 += kRowPanel) {
    const int i1 = std::min(h, i0 + kRowPanel), rows = i1 - i0;
    dgemm_("T", "N", &i1, &rows, &k, &alpha, b, &ldb, a + static_cast<int64_t>(i0) * lda, &lda, &beta,
           c + static_cast<int64_t>(i0) * ldc, &ldc);
  }
}

// Pivot d counts as zero at or below its floor, or when not finite (kernels::zero_pivot's test).
bool zero_pivot(double d, double floor) { return !(std::abs(d) > floor) || !std::isfinite(d); }

// The lower triangle of the b x b column-major block src (leading dimension ld_src) into dst.
void copy_lower(const double* src, int ld_src, double* dst, int ld_dst, int b) {
  for (int j = 0; j < b; ++j)
    std::copy_n(src + static_cast<int64_t>(j) * ld_src + j, b - j, dst + static_cast<int64_t>(j) * ld_dst + j);
}

// kernels::ldl_node's elimination on a column-major block: one panel's diagonal block. Column j
// is finished left-looking (its pivot, then each row below minus the earlier columns' products).
int ldl_unblocked(double* a, int n, int ld, const double* floor, double* inv_d) {
  for (int j = 0; j < n; ++j) {
    double* aj = a + static_cast<int64_t>(j) * ld;
    for (int k = 0; k < j; ++k) {
      const double* ak = a + static_cast<int64_t>(k) * ld;
      const double f = ak[j] * ak[k];  // L_jk D_k
      for (int i = j; i < n; ++i) aj[i] -= ak[i] * f;
    }
    const double d = aj[j];
    if (zero_pivot(d, floor[j])) return j;
    const double inv = 1.0 / d;
    inv_d[j] = inv;
    for (int i = j + 1; i < n; ++i) aj[i] *= inv;
  }
  return -1;
}

// The pivots of Cholesky's Lc (b columns, leading dimension ld): D_j = Lc_jj^2 onto the diagonal,
// inv_d = 1 / D, and w[j] = 1 / Lc_jj, the scale that turns column j of Lc into unit L's.
void cholesky_pivots(double* a, int b, int ld, double* inv_d, double* w) {
  for (int j = 0; j < b; ++j) {
    const double l = a[static_cast<int64_t>(j) * ld + j];
    w[j] = 1.0 / l;
    a[static_cast<int64_t>(j) * ld + j] = l * l;
    inv_d[j] = w[j] * w[j];
  }
}

// Cholesky's Lc (b columns of b + m rows from the diagonal, leading dimension ld) to unit L and
// D = diag(Lc)^2: column j of Lc divided by Lc_jj, a contiguous scaling. w: b doubles of scratch.
void to_unit_ldl(double* a11, int b, int m, int ld, double* inv_d, double* w) {
  cholesky_pivots(a11, b, ld, inv_d, w);
  for (int j = 0; j < b; ++j) {
    double* aj = a11 + static_cast<int64_t>(j) * ld;
    for (int i = j + 1; i < b + m; ++i) aj[i] *= w[j];
  }
}

// Every pivot D_j = Lc_jj^2 of a Cholesky factor above its floor (and finite).
bool pivots_above_floor(const double* a, int n, int ld, const double* floor) {
  for (int j = 0; j < n; ++j) {
    const double l = a[static_cast<int64_t>(j) * ld + j];
    if (zero_pivot(l * l, floor[j])) return false;
  }
  return true;
}

// A panel's diagonal block b x b (leading dimension ld) by LAPACK's Cholesky, A11 = Lc Lc^T, when
// it is positive definite with every pivot D_j = Lc_jj^2 above its floor; then the m rows below,
// R = A21, become X = R Lc^-T (dtrsm, non-unit) and the trailing matrix A22 -= X X^T (dsyrk,
// lower triangle only), which is A22 - L21 D L21^T with L = Lc diag(Lc)^-1, D = diag(Lc)^2: the
// same Schur complement as the LDL^T panel, so the two kinds of panel mix freely. Lc and X are
// left unscaled (to_unit_ldl). Returns false, with A11 restored from the copy in w (b * b
// doubles), where dpotrf stops (a pivot <= 0: the block is indefinite or singular) or a pivot is
// at or below its floor; the caller then runs the LDL^T panel, which finds the same pivot or
// factors an indefinite block.
bool cholesky_panel(double* a11, int b, int m, int ld, const double* floor, double* w) {
  copy_lower(a11, ld, w, b, b);
  int info = 0;
  dpotrf_("L", &b, a11, &ld, &info);
  if (info != 0 || !pivots_above_floor(a11, b, ld, floor)) {
    copy_lower(w, b, a11, ld, b);
    return false;
  }
  if (m > 0) {
    const double one = 1, minus_one = -1;
    double* r = a11 + b;
    dtrsm_("R", "L", "T", "N", &m, &b, &one, a11, &ld, r, &ld);                                // X = R Lc^-T
    dsyrk_("L", "N", &m, &b, &minus_one, r, &ld, &one, a11 + static_cast<int64_t>(b) * ld + b, &ld);  // A22 -= X X^T
  }
  return true;
}

// Right-looking by panels of kPanel columns [j0, j1): a positive definite panel by
// cholesky_panel; otherwise factor the diagonal block by the triple loop; below it R = A21
// becomes W = R L11^-T (kept in w, m x b column-major) and L21 = W D1^-1 (over R), since A21 =
// L21 D1 L11^T; then A22 -= W L21^T, lower triangle, with dgemm by column panels. Same arithmetic
// as the unblocked loop up to the order of the sums (and, in Cholesky panels, the square roots).
// The leading Cholesky panels stay Lc (their count of columns in `cholesky`: n when the block is
// positive definite), so that factor_supernode can go on with Lc as LAPACK would; a Cholesky
// panel after an LDL^T one is made unit at once. Returns the first bad pivot or -1.
int panels(double* a, int n, int ld, const double* floor, double* inv_d, double* w, int& cholesky) {
  cholesky = 0;
  for (int j0 = 0; j0 < n; j0 += kPanel) {
    const int b = std::min(kPanel, n - j0), m = n - j0 - b;
    double* a11 = a + static_cast<int64_t>(j0) * ld + j0;
    if (cholesky_panel(a11, b, m, ld, floor + j0, w)) {
      if (cholesky == j0)
        cholesky += b;
      else
        to_unit_ldl(a11, b, m, ld, inv_d + j0, w);
      continue;
    }
    const int bad = ldl_unblocked(a11, b, ld, floor + j0, inv_d + j0);
    if (bad >= 0) return j0 + bad;
    if (m == 0) break;
    double* r = a11 + b;  // A21: m x b, leading dimension ld
    const double one = 1, minus_one = -1;
    dtrsm_("R", "L", "T", "U", &m, &b, &one, a11, &ld, r, &ld);  // W = R L11^-T
    for (int c = 0; c < b; ++c) {
      double* rc = r + static_cast<int64_t>(c) * ld;
      double* wc = w + static_cast<int64_t>(c) * m;
      for (int i = 0; i < m; ++i) {
        wc[i] = rc[i];
        rc[i] *= inv_d[j0 + c];
      }
    }
    // A22[i0:, i0:i1] -= W[i0:, :] L21[i0:i1, :]^T by column panels; dgemm writes the upper
    // triangle of each diagonal panel too, which is set back to zero: in a node that no other
    // supernode updates, the other triangle stays zero, and Numeric::load does not zero it.
    double* a22 = r + static_cast<int64_t>(b) * ld;
    for (int i0 = 0; i0 < m; i0 += kRowPanel) {
      const int cols = std::min(kRowPanel, m - i0), rows = m - i0;
      double* c = a22 + static_cast<int64_t>(i0) * ld + i0;
      dgemm_("N", "T", &rows, &cols, &b, &minus_one, w + i0, &m, r + i0, &ld, &one, c, &ld);
      for (int j = 1; j < cols; ++j) std::fill_n(c + static_cast<int64_t>(j) * ld, j, 0.0);
    }
  }
  return -1;
}

}  // namespace

// Children's updates (kernels.h, row-major lower) over the node's strictly upper column-major
// triangle, added into its column-major lower one, by 32 x 32 tiles: a(i, j) += a'(j, i).
void fold_updates(double* node, int d) {
  constexpr int kTile = 32;
  for (int j0 = 0; j0 < d; j0 += kTile)
    for (int i0 = j0; i0 < d; i0 += kTile)
      for (int j = j0; j < std::min(d, j0 + kTile); ++j)
        for (int i = std::max(i0, j + 1); i < std::min(d, i0 + kTile); ++i)
          node[static_cast<int64_t>(j) * d + i] += node[static_cast<int64_t>(i) * d + j];
}

// A positive definite node block as CHOLMOD does a supernode: Lc by panels of LAPACK's Cholesky,
// X = E Lc^-T by blocked forward substitution (solve_rows), C = X X^T by dsyrk, then Lc and X
// rescaled to L and Y = X diag(Lc)^-1 (E = Y D L^T with D = diag(Lc)^2, and C = Y D Y^T = W Y^T). Any other: unit L from the panels,
// then begin_l and lower_product.
int factor_supernode(double* node, int d, int h, const double* floor, double* inv_d, double* w) {
  double* e = node + static_cast<int64_t>(d) * d;
  double* c = w + static_cast<int64_t>(h) * d;
  int cholesky = 0;
  const int bad = panels(node, d, d, floor, inv_d, w, cholesky);
  if (bad >= 0 || cholesky < d) {
    to_unit_ldl(node, cholesky, d - cholesky, d, inv_d, w);
    if (bad >= 0) return bad;
    begin_l(e, w, node, inv_d, h, d);
    lower_product(w, e, h, d, c);
    return -1;
  }
  if (h > 0) {
    const double one = 1, zero = 0;
    solve_rows(false, node, d, d, e, h, d);               // X = E Lc^-T
    dsyrk_("U", "T", &h, &d, &one, e, &d, &zero, c, &h);  // C = X X^T, row-major lower triangle
  }
  // To unit L, D and Y = X diag(Lc)^-1.
  to_unit_ldl(node, d, 0, d, inv_d, w);
  for (int64_t i = 0; i < h; ++i)
    for (int j = 0; j < d; ++j) e[i * d + j] *= w[j];
  return -1;
}

void begin_l(double* e, double* w, const double* node, const double* inv_d, int h, int n) {
  solve_rows(true, node, n, n, e, h, n);
  for (int64_t r = 0; r < h; ++r) {
    double* er = e + r * n;
    double* wr = w + r * n;
    for (int c = 0; c < n; ++c) {
      wr[c] = er[c];
      er[c] *= inv_d[c];
    }
  }
}


void lower_product(const double* w, const double* y, int h, int n, double* c) { lower_gemm(1, w, n, y, n, h, n, 0, c, h); }

// l (Y, the rows below the node) is h x n row-major: BLAS sees Y^T, n x h, so Y y_t is dgemv('T') and Y^T z is
// dgemv('N'). The node's unit-lower L is column-major, BLAS's own "L".
void forward_column(double* y, const double* yt, const double* l, const int* rows, int h, int n, double* tmp) {
  if (h == 0) return;
  const double one = 1, zero = 0;
  const int inc = 1;
  dgemv_("T", &n, &h, &one, l, &n, yt, &inc, &zero, tmp, &inc);
  for (int r = 0; r < h; ++r) y[rows[r]] -= tmp[r];
}

void forward_node(const double* node, double* x, int n) {
  const int inc = 1;
  dtrsv_("L", "N", "U", &n, node, &n, x, &inc);  // x <- L^-1 x
}

void backward_node(const double* node, double* x, int n) {
  const int inc = 1;
  dtrsv_("L", "T", "U", &n, node, &n, x, &inc);  // x <- L^-T x
}

void backward_column(const double* y, double* yt, const double* l, const int* rows, int h, int n, double* tmp) {
  if (h == 0) return;
  const double minus_one = -1, one = 1;
  const int inc = 1;
  for (int r = 0; r < h; ++r) tmp[r] = y[rows[r]];
  dgemv_("N", &n, &h, &minus_one, l, &n, tmp, &inc, &one, yt, &inc);
}

}  // namespace ldlpgs::dense
