#pragma once
// The supernodal kernels: the same three steps as kernels.h (node LDL^T, W = E L^-T with
// Y = W D^-1 kept as the factor's rows below the node, the reduction's product), for a supernode wide enough that level-3 BLAS
// (dtrsm, dgemm) beats the unrolled loops. The node block d x d is column-major lower, BLAS's
// own "L" as CHOLMOD stores a supernode (entry (i, j), i >= j, at j * d + i; the load map puts H
// there); its other triangle, the row-major lower one where kernels.h and the RSI write, gathers
// the updates of other supernodes until fold_updates adds them in. E, h x d, is row-major as in
// kernels.h: to column-major BLAS its transpose d x h, which is what the calls below pass.
// Nothing here allocates: the scratch comes from the numeric phase (sizes in the comments).
namespace ldlpgs::dense {

// Columns of a panel of the blocked LDL^T (the unblocked triple loop inside it, dtrsm below it,
// dgemm for the trailing matrix), and rows of a panel of the lower-triangular products. Measured
// on heavy-253's single 976-row supernode (papers/factor.md, "Supernodes").
inline constexpr int kPanel = 64;
inline constexpr int kRowPanel = 128;
// Columns of a diagonal block of the rows' solve E L^-T, whose triangle is inverted explicitly
// (papers/factor.md, "The rows' solve by blocks").
inline constexpr int kSolveBlock = 16;

// The node block's strictly row-major lower triangle (other supernodes' updates) added into its
// column-major lower one, which the functions below factor: a(i, j) += a[i * d + j] for i > j.
void fold_updates(double* node, int d);

// A supernode's elimination. Its d x d node block (column-major lower) gets LDL^T without
// pivoting in place, as kernels::ldl_node: unit-lower L below the diagonal, D on it, inv_d = 1 / D,
// floor[j] the zero-pivot threshold of pivot j. By panels of kPanel columns: a positive definite
// panel runs LAPACK's Cholesky (dpotrf, dtrsm, dsyrk on column-major lower blocks, CHOLMOD's
// calls) and is rescaled to L and D; an indefinite one runs the LDL^T loop (papers/factor.md,
// "Small supernodes and Cholesky panels" and "Dense fronts"). Then E (h x d, following the node)
// is turned into Y and the lower triangle of C = W Y^T (h x h, row-major) left at w + h * d: a
// positive definite node keeps Cholesky's Lc through its panels, and E goes by a blocked forward
// substitution and dsyrk as in CHOLMOD's supernodes; any other, by begin_l and lower_product.
// Returns the first pivot that is zero or not finite, or -1. w: scratch of max(h * d + h * h,
// d * kPanel) doubles.
int factor_supernode(double* node, int d, int h, const double* floor, double* inv_d, double* w);

// W = E L^-T (into w, h x n row-major) and Y = W D^-1 (over e), node = L D L^T factored.
void begin_l(double* e, double* w, const double* node, const double* inv_d, int h, int n);
// The lower triangle of C = W Y^T (h x h row-major, into c), row panels of kRowPanel: the upper
// triangle inside each diagonal panel is computed too (at most kRowPanel / h more flops) and
// never read.
void lower_product(const double* w, const double* y, int h, int n, double* c);

// The solve's steps (kernels.h forward_unit, forward_column, backward_column, backward_unit) with
// dtrsv and dgemv: x <- L^-1 x and x <- L^-T x with the node's unit-lower L (column-major); y[rows] -= Y y_t;
// y_t -= Y^T y[rows] (Y: the h x n rows below the node). tmp: scratch of h doubles.
void forward_node(const double* node, double* x, int n);
void backward_node(const double* node, double* x, int n);
void forward_column(double* y, const double* yt, const double* l, const int* rows, int h, int n, double* tmp);
void backward_column(const double* y, double* yt, const double* l, const int* rows, int h, int n, double* tmp);

}  // namespace ldlpgs::dense
