#pragma once
// The supernodal kernels: the same three steps as kernels.h (node LDL^T, W = E L^-T with
// Y = W D^-1 kept as the factor's rows below the node, the reduction's product), for a supernode wide enough that level-3 BLAS
// (dtrsm, dgemm) beats the unrolled loops. Same layout as kernels.h: node block n x n row-major
// (lower triangle read; the upper one is scratch, written by factor_supernode and the panels'
// products, read by no one after), E h x n row-major. A row-major m x n matrix with row stride
// ld is, to column-major BLAS, its transpose n x m with leading dimension ld: the calls below
// pass the transposed problem, and copy only where factor_supernode wants BLAS's other triangle.
// Nothing here allocates: the scratch comes from the numeric phase (sizes in the comments).
#include <cstdint>

namespace ldlpgs::dense {

// Columns of a panel of the blocked LDL^T (the unblocked triple loop inside it, dtrsm below it,
// dgemm for the trailing matrix), and rows of a panel of the lower-triangular products. Measured
// on heavy-253's single 976-row supernode (papers/factor.md, "Supernodes").
inline constexpr int kPanel = 64;
inline constexpr int kRowPanel = 128;
// Node blocks up to this many rows try LAPACK's Cholesky of the whole block (factor_supernode);
// wider ones go by panels. The whole block measured faster from 260 to 787 rows, level with the
// panels at 976 (papers/factor.md, "Dense fronts").
inline constexpr int kWholeCholeskyMaxRows = 800;

// LDL^T without pivoting of the n x n row-major block a (lower triangle, row stride ld), in
// place, as kernels::ldl_node: unit-lower L below the diagonal, D on it, inv_d = 1 / D, floor[j]
// the zero-pivot threshold of pivot j. Returns the first pivot that is zero or not finite, or -1.
// A panel that is positive definite runs LAPACK's Cholesky (dpotrf, dtrsm, dsyrk) and is
// rescaled to L and D; an indefinite one runs the LDL^T loop. On a random positive definite
// 260-row block 196 against 267 us for the loop alone (LAPACK's dpotrf of the whole block
// 188-201); heavy-63's factorization 227 against 290 us (papers/factor.md, "Small supernodes
// and Cholesky panels"). w: scratch of n * kPanel doubles.
int ldl_blocked(double* a, int n, int ld, const double* floor, double* inv_d, double* w);

// A supernode's elimination: its d x d node block (lower triangle) factored in place as
// ldl_blocked, E (h x d, following the node) turned into Y, and the lower triangle of C = W Y^T
// (h x h, row-major) left at w + h * d. A positive definite node of at most
// kWholeCholeskyMaxRows rows takes LAPACK's Cholesky of the whole block, as CHOLMOD's supernodes
// do, through a copy in the node's upper triangle; any other, the panels, begin_l and
// lower_product (a node that fails the Cholesky has paid for the copy and the dpotrf up to its
// first bad pivot, unless a diagonal entry at or below its floor shows it at once). Returns
// ldl_blocked's bad pivot or -1. w: scratch of max(h * d + h * h, d * kPanel) doubles.
int factor_supernode(double* node, int d, int h, const double* floor, double* inv_d, double* w);

// W = E L^-T (into w, h x n row-major) and Y = W D^-1 (over e), node = L D L^T factored.
void begin_l(double* e, double* w, const double* node, const double* inv_d, int h, int n);
// The lower triangle of C = W Y^T (h x h row-major, into c), row panels of kRowPanel: the upper
// triangle inside each diagonal panel is computed too (at most kRowPanel / h more flops) and
// never read.
void lower_product(const double* w, const double* y, int h, int n, double* c);

// The solve's steps (kernels.h forward_unit, forward_column, backward_column, backward_unit) with
// dtrsv and dgemv: x <- L^-1 x and x <- L^-T x with the node's unit-lower L; y[rows] -= Y y_t;
// y_t -= Y^T y[rows] (Y: the h x n rows below the node). tmp: scratch of h doubles.
void forward_node(const double* node, double* x, int n);
void backward_node(const double* node, double* x, int n);
void forward_column(double* y, const double* yt, const double* l, const int* rows, int h, int n, double* tmp);
void backward_column(const double* y, double* yt, const double* l, const int* rows, int h, int n, double* tmp);

}  // namespace ldlpgs::dense
