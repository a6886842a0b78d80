#pragma once
// The numeric phase's three passes over the supernodes: the elimination, and the solve's forward
// and backward substitutions, each a straight walk over Steps calling the kernels of kernels.h.
// They are compiled three times (passes.inc): for the x86-64 baseline (SSE2, kernels of 2 lanes),
// with -mavx2 (4 lanes; its solve is the baseline's, passes_avx2.cpp) and with -mavx512f (8 lanes,
// passes_avx512.cpp), and Numeric picks one per call from the CPU (kernel_isa()). The AVX2 elimination was 8-31 % faster than the SSE2 one on
// factor_bench's mechanisms on an AMD EPYC (papers/factor.md "Four lanes with AVX2"); both give
// the same values bit for bit (kernels.h), which numeric_test checks on every case of its harness.
//
// Internal to the factor library: Numeric builds the Steps from its Symbolic. The passes see no
// Symbolic (only these plain records), so the AVX2 translation unit instantiates nothing of
// Symbolic or of the standard library that the linker could merge with the baseline's copies and
// run on a CPU without AVX2: every weak symbol of passes_avx2.cpp.o is in kernels::avx2 (nm -C).
#include <cstdint>

namespace ldlpgs::passes {

// What a pass reads of supernode t (one record per supernode, in elimination order).
enum class Kind : uint8_t {
  single,         // one edge block, one run onto its target's diagonal: kernels::eliminate_single
  blocks,         // per-block kernels, reductions through the RSI runs
  blocks_mapped,  // per-block kernels, reductions through a relative map of each target
  blas,           // dense.h (BLAS level 3), scattered through the RSI runs
  blas_mapped,    // dense.h, scattered through a relative map
};
struct Step {
  int64_t node;          // offset of the node block in the values
  const int32_t* rsi;    // its runs (Symbolic::rsi)
  const int* rows;       // first row in E of each edge block (Symbolic::edge_rows)
  const int* sizes;      // rows of each edge block (Symbolic::edge_sizes)
  const int* erows;      // permuted row of each row of E (Symbolic::column_rows)
  int edges;             // mapped kinds: the first of its m entries in Factor::targets and ::columns
  int d, h, r0, m;       // rows of the node, rows of E, first permuted row, edge blocks
  Kind kind;
  uint8_t single;        // kernels::kSingle index when kind == single
  uint8_t fold;          // BLAS kinds: other supernodes update the node block (dense::fold_updates)
};
// (static: no function here may be shared between the SSE2 and AVX2 objects, kernels.h)
static inline bool is_blas(const Step& s) { return s.kind == Kind::blas || s.kind == Kind::blas_mapped; }
// Below the node the factor keeps L_{*,k}, not Y = L_{*,k} L_kk (numeric.h).
static inline bool keeps_l(const Step& s) { return s.kind == Kind::single; }

struct Factor {
  const Step* steps;  // (size count)
  int count;
  double* values;     // the packed blocks
  double* scratch;    // W and the BLAS product (Symbolic::scratch_size())
  const double* floor;  // zero-pivot threshold per permuted row
  double* inv_d;        // 1 / D per permuted row
  int32_t* map;         // a mapped target's relative map (size n if any step is mapped)
  // Per edge block of the mapped steps (Step::edges): the supernode of its target, and its
  // first column there.
  const int* targets;
  const int* columns;
};

// Eliminates the steps in order; returns the first step whose pivot `bad` (local row) is zero or
// not finite, or -1 with bad = -1 when all are done.
using EliminateFn = int (*)(const Factor& f, int& bad);
// w <- L^-1 w then D^-1 (forward), w <- L^-T w (backward), w in the permuted order. scratch as
// for the factorization (the BLAS steps' gathered rows).
using SolveFn = void (*)(const Factor& f, double* w);

// The passes over all entries or rows around the elimination (Numeric::load, prepare,
// eliminate), built twice like it: with AVX2 they made chain-300's factorization 4 % faster
// (papers/factor.md "Four lanes with AVX2").
// v[map[p]] = x[p] for p < nnz; false when some x[p] is NaN or infinite.
using ScatterFn = bool (*)(double* v, const int32_t* map, const double* x, int64_t nnz);
// v[pos[i]] *= grow and diag[i] = |v[pos[i]]| for i < n; the largest diag and the smallest
// nonzero one (+inf when none is).
using DiagonalFn = void (*)(double* v, const int32_t* pos, int n, double grow, double* diag, double& largest,
                            double& smallest);
// floor[i] = max(smallest normal double, zero_pivot (diag[i] > 0 ? diag[i] : largest)).
using FloorsFn = void (*)(const double* diag, int n, double zero_pivot, double largest, double* floor);
// Over the first `rows` pivots: returns how many are negative, and sets largest = max |1/d_r| diag_r.
using InertiaFn = int (*)(const double* inv_d, const double* diag, int rows, double& largest);

struct Passes {
  const char* isa;  // "sse2", "avx2" or "avx512"
  EliminateFn eliminate;
  SolveFn forward, backward;
  ScatterFn scatter;
  DiagonalFn diagonal;
  FloorsFn floors;
  InertiaFn inertia;
};
// Both tables are constant-initialized (constinit: nothing runs at start-up, so the AVX2 object
// executes no instruction before Numeric has checked the CPU); the AVX2 one solves with the SSE2
// functions, named here for it.
extern const Passes kSse2;
void forward_sse2(const Factor& f, double* w);
void backward_sse2(const Factor& f, double* w);
#ifdef LDLPGS_HAVE_AVX2_PASSES
extern const Passes kAvx2;
#endif
#ifdef LDLPGS_HAVE_AVX512_PASSES
extern const Passes kAvx512;
#endif

}  // namespace ldlpgs::passes
