#pragma once
// The numeric kernels of the block LDL^T, as the talk's eliminatePivot<degree> has them: small
// free functions templated on the pivot's block size N (1..6 unrolled by the compiler; N = 0 is
// the generic path, with the size given at run time), allocating nothing. Layout (symbolic.h):
// a node block N_k is d x d row-major (only its lower triangle is read); the edge blocks below it
// are stacked into one h x d row-major matrix E, each of its rows one scalar row of L.
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

// Every loop below whose trip count is a block size is unrolled: GCC unrolls a loop of fixed
// trip count fully only when its body is small, and left the nested loops of the kernels as
// loops, with a branch per iteration (papers/factor.md, "Per-pivot overhead"). A run-time size
// (N = 0) is unrolled by 8 with a remainder; the loops over rows of E (h) carry no pragma (begin_l).
#define LDLPGS_UNROLL _Pragma("GCC unroll 8")

// Three builds of these kernels live in the library (factor/passes.h): the x86-64 baseline (SSE2,
// 2 lanes per vector), compiled with -mavx2 and LDLPGS_KERNELS_AVX2 4 lanes, and with -mavx512f
// and LDLPGS_KERNELS_AVX512 8 lanes, chosen at run time by the CPU. Each build is its own inline namespace, so the two sets of inline functions
// never merge at link time (an AVX2 copy of an inline kernel must not serve the SSE2 caller).
// For the same reason nothing here calls a standard-library function (an unoptimized build emits
// std::abs out of line, under the same name in both builds): compiler builtins instead, and the
// table of fused kernels is a plain array (tests/support/isa_symbols.sh checks the AVX2 and
// AVX-512 objects).
#if defined(LDLPGS_KERNELS_AVX512)
#define LDLPGS_KERNELS_ISA avx512
#define LDLPGS_LANES 8
#elif defined(LDLPGS_KERNELS_AVX2)
#define LDLPGS_KERNELS_ISA avx2
#define LDLPGS_LANES 4
#else
#define LDLPGS_KERNELS_ISA sse2
#define LDLPGS_LANES 2
#endif

namespace ldlpgs::kernels {
inline namespace LDLPGS_KERNELS_ISA {

// Calls f(std::integral_constant<int, N>) with N = d for d in 1..6, N = 0 otherwise: the switch
// on the pivot's size that picks the unrolled kernel (Ceres small_blas.h does the same).
template <class F>
inline void dispatch_size(int d, F&& f) {
  switch (d) {
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 2: f(std::integral_constant<int, 2>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 5: f(std::integral_constant<int, 5>{}); break;
    case 6: f(std::integral_constant<int, 6>{}); break;
    default: f(std::integral_constant<int, 0>{}); break;
  }
}

template <int N>
inline double dot(const double* x, const double* y, int n) {
  const int m = N ? N : n;
  double s = 0;
  LDLPGS_UNROLL for (int k = 0; k < m; ++k) s += x[k] * y[k];
  return s;
}

// Pivot d counts as zero at or below `floor` in magnitude, or when not finite (NaN fails every
// comparison, so the test is !(|d| > floor)). dense.cpp's zero_pivot is the same test for the
// BLAS path; this one uses builtins, as everything here must.
inline bool zero_pivot(double d, double floor) { return !(__builtin_fabs(d) > floor) || !__builtin_isfinite(d); }

// Dense LDL^T of the d x d node block in place (the talk's ldlDecompose<degree>): on return the
// strict lower triangle holds the unit-lower L, the diagonal holds D. No pivoting: the block
// ordering fixed the order. floor[j] is the magnitude at or below which pivot j counts as zero;
// returns the first pivot that is zero or not finite (its value is left on the diagonal), or -1.
// inv_d receives 1 / D: every later use multiplies instead of dividing.
// Negative pivots are allowed: LDL^T exists for indefinite matrices whose leading minors are
// nonsingular, and the caller counts them (the inertia).
template <int N>
inline int ldl_node(double* a, const double* floor, double* inv_d, int n) {
  const int m = N ? N : n;
  if constexpr (N == 0) {
    // Sizes over 6, given at run time: the recurrence below needs two m x m arrays (u and
    // u^2 / d) on the stack, unbounded here, so this path keeps l_jk l_jk d_k.
    for (int j = 0; j < m; ++j) {
      double* aj = a + j * m;
      double d = aj[j];
      for (int k = 0; k < j; ++k) d -= aj[k] * aj[k] * a[k * m + k];
      aj[j] = d;
      if (zero_pivot(d, floor[j])) return j;
      const double inv = 1.0 / d;
      inv_d[j] = inv;
      for (int i = j + 1; i < m; ++i) {
        double* ai = a + i * m;
        double s = ai[j];
        for (int k = 0; k < j; ++k) s -= ai[k] * aj[k] * a[k * m + k];
        ai[j] = s * inv;
      }
    }
  } else {
    // The pivots form a chain: d_j needs l_jk = u_jk / d_k for every k < j, u_jk = l_jk d_k
    // being the value before its scaling, and d_j = a_jj - sum_k u_jk^2 / d_k. On a chain or a
    // loop each node waits for the one before it, so the time per pivot is this chain's
    // latency: the division, then u^2 / d and the subtraction that ends d_{j+1}. u_jk^2 is
    // squared while the division runs, leaving one multiply between 1 / d_j and d_{j+1}
    // (u_jk l_jk, kept before, left two; papers/factor.md, "The pivot's latency"). u^2 overflows for |u| > 2^512 where u^2 / d does not (a positive definite
    // 3 x 3 with entries near 1e200 gave a pivot of -inf: found in review,
    // Numeric.LargeEntriesOfAPositiveDefiniteNode): a pivot that fails its check is computed
    // again from u_jk l_jk, kept in u, before it is reported, so an overflow of the squares
    // never fails a pivot that the products pass. A square that underflows (|u| < 2^-511) is
    // off by up to 2^-1075 per term, so d_i by up to (N - 1) 2^-1075 / |d_j|: above d_i's own
    // rounding only where |d_i d_j| is below about N 2^-1022, a nearly singular node block at
    // the bottom of the range (FactorOptions::zero_pivot = 0 lets d_j down to the smallest
    // normal double; prepare() leaves diagonals below 2^-500 when H's spans more than 2^1000).
    double ul[N * N];  // ul[i N + j] = u_ij^2 / d_j, i > j
    double u[N * N];   // u_ij, i > j
    LDLPGS_UNROLL for (int j = 0; j < N; ++j) {
      double* aj = a + j * N;
      double d = aj[j];
      LDLPGS_UNROLL for (int k = 0; k < j; ++k) d -= ul[j * N + k];
      if (zero_pivot(d, floor[j])) {
        d = aj[j];
        LDLPGS_UNROLL for (int k = 0; k < j; ++k) d -= u[j * N + k] * aj[k];
      }
      aj[j] = d;
      if (zero_pivot(d, floor[j])) return j;
      const double inv = 1.0 / d;
      inv_d[j] = inv;
      LDLPGS_UNROLL for (int i = j + 1; i < N; ++i) {
        double* ai = a + i * N;
        double s = ai[j];
        LDLPGS_UNROLL for (int k = 0; k < j; ++k) s -= ai[k] * (aj[k] * a[k * N + k]);
        u[i * N + j] = s;
        ul[i * N + j] = (s * s) * inv;
        ai[j] = s * inv;
      }
    }
  }
  return -1;
}

// Several at a time, one in each lane of a vector (GCC's and clang's vector extension): V of
// kLanes lanes (2 with SSE2, the x86-64 baseline every build has; 4 in the AVX2 build, 8 in the
// AVX-512 one), V4 and V2 for remainders of four and two. begin_l and end_l take kLanes rows of E, the reductions kLanes adjacent target
// columns (rows of Y), the solve's column substitutions kLanes rows of the factor below the node
// or entries of y_k. Each lane does the scalar loop's operations in its order (a separate multiply
// and add or subtract each, never fused: factor/CMakeLists.txt sets -ffp-contract=off), so the
// values are those of the row-by-row loops bit for bit, in either build (kernels_test:
// KernelsPairs, compiled once per build; numeric_test: FactorHarness, against the SSE2 build). GCC 12 vectorized none of the
// scalar forms: their dot products are ordered sums, which it may not reassociate.
// papers/factor.md, "Two rows per instruction, and the factor keeps Y" and "Four lanes with AVX2".
inline constexpr int kLanes = LDLPGS_LANES;
using V = double __attribute__((vector_size(8 * LDLPGS_LANES)));
using V2 = double __attribute__((vector_size(16)));
using V4 = double __attribute__((vector_size(32)));  // (the AVX-512 build's half pack)
// Lane i of the pack holds x[i stride + k]; scatter writes the lanes back.
template <class T>
inline T gather(const double* x, int stride, int k) {
  T v = {};  // (every lane is set: the zeros cost nothing, and GCC warns of a read without them)
  LDLPGS_UNROLL for (int i = 0; i < int{sizeof(T) / sizeof(double)}; ++i) v[i] = x[i * stride + k];
  return v;
}
// Lane i holds x[(first + i) stride + k] of rows up to DB - 1; lanes past it repeat row DB - 1.
template <int DB>
inline V gather_rows(const double* x, int stride, int first, int k) {
  V v = {};
  LDLPGS_UNROLL for (int i = 0; i < kLanes; ++i) v[i] = x[(first + i < DB ? first + i : DB - 1) * stride + k];
  return v;
}
template <class T>
inline void scatter(T v, double* x, int stride, int k) {
  LDLPGS_UNROLL for (int i = 0; i < int{sizeof(T) / sizeof(double)}; ++i) x[i * stride + k] = v[i];
}

// The substitutions with a factored node block (L D L^T in place, inv_d = 1 / D), per row x (T
// double) or pack of rows (T V or V2): forward with the unit-lower L (x <- L^-1 x), back with L^T
// (x <- L^-T x); x <- N^-1 x is forward, scale by D^-1, back.
template <int N, class T>
inline void forward_unit(const double* a, T* x, int n) {
  const int m = N ? N : n;
  LDLPGS_UNROLL for (int i = 1; i < m; ++i)
    LDLPGS_UNROLL for (int k = 0; k < i; ++k) x[i] -= a[i * m + k] * x[k];
}
template <int N, class T>
inline void backward_unit(const double* a, T* x, int n) {
  const int m = N ? N : n;
  LDLPGS_UNROLL for (int i = m - 2; i >= 0; --i)
    LDLPGS_UNROLL for (int k = i + 1; k < m; ++k) x[i] -= a[k * m + i] * x[k];
}
template <int N>
inline void solve_node(const double* a, const double* inv_d, double* x, int n) {
  const int m = N ? N : n;
  forward_unit<N>(a, x, m);
  LDLPGS_UNROLL for (int i = 0; i < m; ++i) x[i] *= inv_d[i];
  backward_unit<N>(a, x, m);
}

// The column below a pivot (the talk's computeL): L_{*,k} = E_{*,k} N_k^-1 = Y L_kk^-1 with
// Y = W D^-1 and W = E L_kk^-T, row by row w = L_kk^-1 e (forward substitution), y = D^-1 w.
// begin_l gives the reduction its operands, W (in w, the scratch) and Y (over E), since
// E L^T = E N^-1 E^T = W Y^T. Y = L_{*,k} L_kk is the scalar LDL^T's L below the node
// (CHOLMOD's convention), and the factor keeps it there except in the fused chain column
// (eliminate_single), whose end_l turns it into L_{*,k} (l = L_kk^-T y, back substitution):
// the solve applies L_{*,k} z as Y (L_kk^-1 z), and L_kk^-1 z is the node's own forward
// substitution, so Y costs the solve nothing but latency: L_kk^-1 z then stands between one
// column and the next, which on a chain, where every column waits for the previous one, slowed
// the solve more than the factorization gained (numeric.h; papers/factor.md, "Two rows per
// instruction, and the factor keeps Y"). Substitution, not the explicit inverse the talk
// multiplies by: the inverse raised the backward error of ladder and grid mechanisms by orders
// of magnitude for no speed (papers/factor.md, "What the measurements decided").
// One pack of rows (as many as T has lanes) of begin_l and end_l.
template <int N, class T>
inline void begin_pack(double* __restrict y, double* __restrict w, const double* __restrict node,
                       const double* __restrict inv_d) {
  T x[N];
  LDLPGS_UNROLL for (int c = 0; c < N; ++c) x[c] = gather<T>(y, N, c);
  forward_unit<N>(node, x, N);
  LDLPGS_UNROLL for (int c = 0; c < N; ++c) {
    scatter(x[c], w, N, c);
    scatter(x[c] * inv_d[c], y, N, c);
  }
}
template <int N, class T>
inline void end_pack(double* __restrict y, const double* __restrict node) {
  T x[N];
  LDLPGS_UNROLL for (int c = 0; c < N; ++c) x[c] = gather<T>(y, N, c);
  backward_unit<N>(node, x, N);
  LDLPGS_UNROLL for (int c = 0; c < N; ++c) scatter(x[c], y, N, c);
}
template <int N>
inline void begin_l(double* __restrict el, double* __restrict w, const double* __restrict node,
                    const double* __restrict inv_d, int h, int n) {
  const int m = N ? N : n;
  int r = 0;
  if constexpr (N > 0) {
    for (; r + kLanes <= h; r += kLanes) begin_pack<N, V>(el + r * N, w + r * N, node, inv_d);
    if constexpr (kLanes > 4)
      if (r + 4 <= h) {
        begin_pack<N, V4>(el + r * N, w + r * N, node, inv_d);
        r += 4;
      }
    if (kLanes > 2 && r + 2 <= h) {
      begin_pack<N, V2>(el + r * N, w + r * N, node, inv_d);
      r += 2;
    }
  }
  for (; r < h; ++r) {
    double* yr = el + r * m;
    forward_unit<N>(node, yr, m);
    LDLPGS_UNROLL for (int c = 0; c < m; ++c) {
      w[r * m + c] = yr[c];
      yr[c] *= inv_d[c];
    }
  }
}
template <int N>
inline void end_l(double* __restrict el, const double* __restrict node, int h, int n) {
  const int m = N ? N : n;
  int r = 0;
  if constexpr (N > 0) {
    for (; r + kLanes <= h; r += kLanes) end_pack<N, V>(el + r * N, node);
    if constexpr (kLanes > 4)
      if (r + 4 <= h) {
        end_pack<N, V4>(el + r * N, node);
        r += 4;
      }
    if (kLanes > 2 && r + 2 <= h) {
      end_pack<N, V2>(el + r * N, node);
      r += 2;
    }
  }
  for (; r < h; ++r) backward_unit<N>(node, el + r * m, m);
}

// The rows of an edge block's Y (DB rows of N) in packs for the reductions: yt[p][k] lane i =
// Y_{kLanes p + i, k}; lanes past the last row repeat it and are never stored.
template <int N, int DB>
inline void pack_rows(const double* y, V (*yt)[N]) {
  LDLPGS_UNROLL for (int p = 0; p < (DB + kLanes - 1) / kLanes; ++p)
    LDLPGS_UNROLL for (int k = 0; k < N; ++k) yt[p][k] = gather_rows<DB>(y, N, kLanes * p, k);
}
// t[c] -= w . Y_c for c < cols (<= DB): kLanes adjacent target entries per vector, each lane the
// scalar dot product's sum in its order (from 0, k ascending), then one subtraction; of a last,
// partial pack only the lanes below cols are stored. kFirst: t holds nothing yet (a run that
// writes its target first, Symbolic::rsi), so the subtraction is from zeros, which
// are not read: 0 - s, the value subtracting from zeroed entries gives.
template <int N, bool kFirst = false>
__attribute__((always_inline)) inline void subtract_row(double* __restrict t, const double* __restrict w, const V (*yt)[N], int cols) {
  int c = 0;
  LDLPGS_UNROLL for (; c + kLanes <= cols; c += kLanes) {
    V s = {};
    LDLPGS_UNROLL for (int k = 0; k < N; ++k) s += w[k] * yt[c / kLanes][k];
    V x = {};
    if constexpr (!kFirst) __builtin_memcpy(&x, t + c, sizeof x);
    x -= s;
    __builtin_memcpy(t + c, &x, sizeof x);
  }
  if (c < cols) {
    V s = {};
    LDLPGS_UNROLL for (int k = 0; k < N; ++k) s += w[k] * yt[c / kLanes][k];
    LDLPGS_UNROLL for (int i = 0; i < kLanes; ++i)
      if (c + i < cols) t[c + i] = (kFirst ? 0.0 : t[c + i]) - s[i];
  }
}

// S <- S - E L^T (the talk's reduce<degree>, most of the time) for one edge block b of the
// column, as W Y^T (begin_l): e holds W, lb the DB rows of Y of block b. `runs` is b's entry in
// the RSI (symbolic.h): the number of runs, the target's row stride ld, then per run
// (target, row, rows), which subtracts rows [row, row + rows) of W times Y_b^T from `rows` target
// rows of stride ld (the node block of b's supernode and/or rows below it). The first run starts
// with b's own DB rows landing on the diagonal (symbolic.cpp: a == b comes first), of which only
// the lower triangle is ever read: its upper DB(DB-1)/2 products are skipped, nearly half the
// reduction of a column with one edge block (a chain's). A later run with negative rows is the
// first to write its target rows (Symbolic::rsi): it stores 0 - W Y^T there
// instead of subtracting from zeros. Both sizes fixed at compile time make each
// target row DB independent unrolled dot products, kLanes per vector (subtract_row).
// Returns the end of b's entry.
template <int N, int DB>
inline const int32_t* reduce_runs(double* __restrict values, const double* __restrict e, const double* __restrict lb,
                                  const int32_t* runs, int n, int db) {
  const int count = runs[0], ld = runs[1];
  runs += 2;
  if constexpr (N > 1 && DB > 0) {
    V yt[(DB + kLanes - 1) / kLanes][N];
    pack_rows<N, DB>(lb, yt);
    for (int i = 0; i < count; ++i, runs += 3) {
      double* __restrict t = values + runs[0];
      const double* er = e + runs[1] * N;
      int r = 0;
      if (i == 0)
        LDLPGS_UNROLL for (; r < DB; ++r, t += ld, er += N) subtract_row<N>(t, er, yt, r + 1);
      if (runs[2] >= 0)
        for (; r < runs[2]; ++r, t += ld, er += N) subtract_row<N>(t, er, yt, DB);
      else
        for (; r < -runs[2]; ++r, t += ld, er += N) subtract_row<N, true>(t, er, yt, DB);
    }
  } else {
    const int m = N ? N : n;
    const int nb = DB ? DB : db;
    for (int i = 0; i < count; ++i, runs += 3) {
      double* __restrict t = values + runs[0];
      const double* er = e + runs[1] * m;
      int r = 0;
      if (i == 0)
        LDLPGS_UNROLL for (; r < nb; ++r, t += ld, er += m)
          LDLPGS_UNROLL for (int c = 0; c <= r; ++c) t[c] -= dot<N>(er, lb + c * m, m);
      if (runs[2] >= 0)
        for (; r < runs[2]; ++r, t += ld, er += m)
          LDLPGS_UNROLL for (int c = 0; c < nb; ++c) t[c] -= dot<N>(er, lb + c * m, m);
      else
        for (; r < -runs[2]; ++r, t += ld, er += m)
          LDLPGS_UNROLL for (int c = 0; c < nb; ++c) t[c] = 0.0 - dot<N>(er, lb + c * m, m);
    }
  }
  return runs;
}

// A whole column with one edge block of DB rows whose product lands in one run on a target's
// diagonal (a chain's pivot: the next one is its only neighbour), fused, both sizes fixed at
// compile time: ldl_node, begin_l's substitution with W on the stack and Y kept in packs, the
// DB(DB+1)/2 products of the lower triangle subtracted at target (row stride ld), end_l's on
// the packs. The same operations in the same order as the general path, so the same values;
// fixed sizes unroll the row loops the general path runs h times. Returns the first bad pivot,
// or -1.
template <int N, int DB>
inline int eliminate_single(double* __restrict node, double* __restrict e, double* __restrict target, int ld,
                            const double* floor, double* __restrict inv_d) {
  const int bad = ldl_node<N>(node, floor, inv_d, N);
  if (bad >= 0) return bad;
  constexpr int P = (DB + kLanes - 1) / kLanes;
  double w[P * kLanes * N];  // W, row-major (rows past DB repeat the last)
  V y[P][N];                 // Y in packs (pack_rows), then L
  LDLPGS_UNROLL for (int p = 0; p < P; ++p) {
    V x[N];
    LDLPGS_UNROLL for (int k = 0; k < N; ++k) x[k] = gather_rows<DB>(e, N, kLanes * p, k);
    forward_unit<N>(node, x, N);
    LDLPGS_UNROLL for (int c = 0; c < N; ++c) {
      scatter(x[c], w + kLanes * p * N, N, c);
      y[p][c] = x[c] * inv_d[c];
    }
  }
  LDLPGS_UNROLL for (int r = 0; r < DB; ++r, target += ld) subtract_row<N>(target, w + r * N, y, r + 1);
  LDLPGS_UNROLL for (int p = 0; p < P; ++p) {
    backward_unit<N>(node, y[p], N);
    LDLPGS_UNROLL for (int i = 0; i < kLanes; ++i)
      if (kLanes * p + i < DB) LDLPGS_UNROLL for (int k = 0; k < N; ++k) e[(kLanes * p + i) * N + k] = y[p][k][i];
  }
  return -1;
}
using SingleFn = int (*)(double*, double*, double*, int, const double*, double*);
template <class Sizes>
struct SingleTable;
template <size_t... I>
struct SingleTable<std::index_sequence<I...>> {
  static constexpr SingleFn fns[sizeof...(I)] = {&eliminate_single<static_cast<int>(I / 6) + 1, static_cast<int>(I % 6) + 1>...};
};
// kSingle[6 (N - 1) + DB - 1]: one indirect call picks both sizes (the general path switches
// twice, dispatch_size); papers/factor.md, "Per-pivot overhead".
inline constexpr const SingleFn* kSingle = SingleTable<std::make_index_sequence<36>>::fns;

// The same subtraction for a BLAS supernode (dense.h), whose product C = W Y^T is already
// computed: c points at C's column of b's first row (row stride ldc); each run subtracts its
// rows of C, nb columns wide, lower triangle only on the diagonal (or stores 0 - C, as
// reduce_runs does, in a run that writes first).
inline const int32_t* scatter_runs(double* __restrict values, const double* __restrict c, const int32_t* runs, int ldc,
                                   int nb) {
  const int count = runs[0], ld = runs[1];
  runs += 2;
  for (int i = 0; i < count; ++i, runs += 3) {
    double* __restrict t = values + runs[0];
    const double* cr = c + static_cast<int64_t>(runs[1]) * ldc;
    int r = 0;
    if (i == 0)
      for (; r < nb; ++r, t += ld, cr += ldc)
        for (int j = 0; j <= r; ++j) t[j] -= cr[j];
    if (runs[2] >= 0)
      for (; r < runs[2]; ++r, t += ld, cr += ldc)
        for (int j = 0; j < nb; ++j) t[j] -= cr[j];
    else
      for (; r < -runs[2]; ++r, t += ld, cr += ldc)
        for (int j = 0; j < nb; ++j) t[j] = 0.0 - cr[j];
  }
  return runs;
}

// The same two reductions for a mapped supernode (Symbolic::supernode_mapped): no runs, but for
// every row r of E (permuted row rows[r]) the offset map[rows[r]] of that row in the target
// supernode, at whose column `column` block b's nb columns start. Rows [first, first + nb) are
// b's own, on the target's diagonal (lower triangle); the rest, to h, land below.
template <int N, int DB>
inline void reduce_mapped(double* __restrict values, const double* __restrict e, const double* __restrict lb,
                          const int* __restrict rows, const int32_t* __restrict map, int first, int h, int column,
                          int n, int db) {
  if constexpr (N > 1 && DB > 0) {
    V yt[(DB + kLanes - 1) / kLanes][N];
    pack_rows<N, DB>(lb, yt);
    const double* er = e + int64_t{first} * N;
    int r = first;
    LDLPGS_UNROLL for (int i = 0; i < DB; ++i, ++r, er += N) subtract_row<N>(values + map[rows[r]] + column, er, yt, i + 1);
    for (; r < h; ++r, er += N) subtract_row<N>(values + map[rows[r]] + column, er, yt, DB);
  } else {
    const int m = N ? N : n;
    const int nb = DB ? DB : db;
    const double* er = e + int64_t{first} * m;
    int r = first;
    LDLPGS_UNROLL for (int i = 0; i < nb; ++i, ++r, er += m) {
      double* __restrict t = values + map[rows[r]] + column;
      LDLPGS_UNROLL for (int c = 0; c <= i; ++c) t[c] -= dot<N>(er, lb + c * m, m);
    }
    for (; r < h; ++r, er += m) {
      double* __restrict t = values + map[rows[r]] + column;
      LDLPGS_UNROLL for (int c = 0; c < nb; ++c) t[c] -= dot<N>(er, lb + c * m, m);
    }
  }
}
// c points at C's column of b's first row, as for scatter_runs.
inline void scatter_mapped(double* __restrict values, const double* __restrict c, const int* __restrict rows,
                           const int32_t* __restrict map, int first, int h, int column, int ldc, int nb) {
  const double* cr = c + int64_t{first} * ldc;
  int r = first;
  for (int i = 0; i < nb; ++i, ++r, cr += ldc) {
    double* __restrict t = values + map[rows[r]] + column;
    for (int j = 0; j <= i; ++j) t[j] -= cr[j];
  }
  for (; r < h; ++r, cr += ldc) {
    double* __restrict t = values + map[rows[r]] + column;
    for (int j = 0; j < nb; ++j) t[j] -= cr[j];
  }
}

// Forward substitution through pivot k's column: y[rows[r]] -= L_r . y_k for each row r of L,
// kLanes rows per vector (then a pair) with N fixed (each lane the scalar dot product in its order). y_k is none
// of the rows written (they are later pivots' rows), so it is read once.
template <int N, class T>
inline void forward_pack(double* y, const double* x, const double* l, const int* rows) {
  T s = {};
  LDLPGS_UNROLL for (int k = 0; k < N; ++k) s += gather<T>(l, N, k) * x[k];
  LDLPGS_UNROLL for (int i = 0; i < int{sizeof(T) / sizeof(double)}; ++i) y[rows[i]] -= s[i];
}
template <int N>
inline void forward_column(double* y, const double* yk, const double* l, const int* rows, int h, int n) {
  const int m = N ? N : n;
  int r = 0;
  if constexpr (N > 1) {
    double x[N];
    LDLPGS_UNROLL for (int k = 0; k < N; ++k) x[k] = yk[k];
    for (; r + kLanes <= h; r += kLanes) forward_pack<N, V>(y, x, l + r * N, rows + r);
    if constexpr (kLanes > 4)
      if (r + 4 <= h) {
        forward_pack<N, V4>(y, x, l + r * N, rows + r);
        r += 4;
      }
    if (kLanes > 2 && r + 2 <= h) {
      forward_pack<N, V2>(y, x, l + r * N, rows + r);
      r += 2;
    }
  }
  for (; r < h; ++r) y[rows[r]] -= dot<N>(l + r * m, yk, m);
}

// Back substitution through pivot k's column: y_k -= L^T y[rows], row by row in order; with N
// fixed y_k is held in registers, kLanes of its entries per vector, then four (8 lanes), a pair,
// one.
template <int N>
inline void backward_column(const double* y, double* yk, const double* l, const int* rows, int h, int n) {
  if constexpr (N > 1) {
    // packs, a quad, a pair, a last entry, and where the quad and the pair start
    constexpr int P = N / kLanes, Q4 = kLanes > 4 && N % kLanes >= 4, Q = N % kLanes - 4 * Q4 >= 2, R = N % 2;
    constexpr int at4 = kLanes * P, at2 = at4 + 4 * Q4;
    V x[P > 0 ? P : 1];
    V4 x4 = {};
    V2 x2 = {};
    double last = R ? yk[N - 1] : 0;
    LDLPGS_UNROLL for (int p = 0; p < P; ++p) __builtin_memcpy(&x[p], yk + kLanes * p, sizeof x[p]);
    if constexpr (Q4) __builtin_memcpy(&x4, yk + at4, sizeof x4);
    if (Q) __builtin_memcpy(&x2, yk + at2, sizeof x2);
    for (int r = 0; r < h; ++r) {
      const double yr = y[rows[r]];
      const double* lr = l + r * N;
      LDLPGS_UNROLL for (int p = 0; p < P; ++p) {
        V lv;
        __builtin_memcpy(&lv, lr + kLanes * p, sizeof lv);
        x[p] -= lv * yr;
      }
      if constexpr (Q4) {
        V4 lv;
        __builtin_memcpy(&lv, lr + at4, sizeof lv);
        x4 -= lv * yr;
      }
      if (Q) {
        V2 lv;
        __builtin_memcpy(&lv, lr + at2, sizeof lv);
        x2 -= lv * yr;
      }
      if (R) last -= lr[N - 1] * yr;
    }
    LDLPGS_UNROLL for (int p = 0; p < P; ++p) __builtin_memcpy(yk + kLanes * p, &x[p], sizeof x[p]);
    if constexpr (Q4) __builtin_memcpy(yk + at4, &x4, sizeof x4);
    if (Q) __builtin_memcpy(yk + at2, &x2, sizeof x2);
    if (R) yk[N - 1] = last;
  } else {
    const int m = N ? N : n;
    for (int r = 0; r < h; ++r) {
      const double yr = y[rows[r]];
      const double* lr = l + r * m;
      LDLPGS_UNROLL for (int c = 0; c < m; ++c) yk[c] -= lr[c] * yr;
    }
  }
}

}  // namespace LDLPGS_KERNELS_ISA
}  // namespace ldlpgs::kernels

#undef LDLPGS_UNROLL
