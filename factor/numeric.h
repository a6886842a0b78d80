#pragma once
// The numeric phase of the block LDL^T (the talk: every frame). Takes a Symbolic and cannot
// change its structure; all memory is allocated by the constructor, none by factorize or solve.
//
// Factorization, per pivot k in order (the talk's block Gaussian elimination):
//   N_k = L_kk D_k L_kk^T in place; W = E_{*,k} L_kk^-T into a scratch buffer and Y = W D_k^-1
//   over E; S -= E_{*,k} L_{*,k}^T = W Y^T through the RSI (kernels::begin_l, reduce_runs).
// The result is H = L N L^T with L block unit-lower and N = blockdiag(N_k), each N_k kept as its
// own L_kk D_k L_kk^T. Below the node the factor keeps Y_k = L_{*,k} L_kk, which is the scalar
// LDL^T's L there (CHOLMOD's: L_scalar = L blockdiag(L_kk), D = D_k), and the solve applies
// L_{*,k} z as Y_k (L_kk^-1 z); forming L_{*,k} = Y_k L_kk^-1 would cost a back substitution per
// row of E. The one exception is a fused chain column (kernels::eliminate_single), which keeps
// L_{*,k} (kernels::end_l): there the solve's L_kk^-1 z would sit on the chain's critical path
// (kernels.h, begin_l). scalar_ldl() expands either to CHOLMOD's convention.
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <string>
#include <vector>

#include "ldlpgs/factor/passes.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

struct FactorOptions {
  // The talk's compliance: factor H + eps diag(H). 0 factors H exactly.
  double regularization = 0;
  // A pivot d of scalar row r counts as zero when |d| <= zero_pivot * |H_rr| (H regularized; the
  // largest |H_ii| when H_rr = 0): at 1e-12 the pivot has lost all but four digits to
  // cancellation, and a solve through it would be noise. A pivot at or below the smallest normal
  // double (2.2e-308, of H scaled into range: Numeric::prepare) is zero whatever this says.
  double zero_pivot = 1e-12;
};

enum class FactorStatus {
  ok,           // all pivots positive: H is positive definite
  indefinite,   // completed, some pivots negative (the first is named): H = L D L^T still holds
  zero_pivot,   // stopped at a zero pivot (singular H: e.g. redundant constraints, no compliance)
  not_finite,   // stopped at a NaN or infinite value (in the input or a pivot)
};
const char* to_string(FactorStatus status);

struct Inertia {
  int positive = 0, negative = 0, zero = 0;  // pivots counted so far (all of them when completed)
};

struct FactorInfo {
  FactorStatus status = FactorStatus::ok;
  int block = -1;   // original block of the first failing (or, if indefinite, negative) pivot
  int row = -1;     // its original scalar row
  double pivot = 0; // its value (for not_finite caused by the input: the offending entry)
  Inertia inertia;
  double min_pivot_ratio = 0;  // min over pivots of |d_r| / |H_rr|: near 0 means nearly singular
  bool usable() const { return status == FactorStatus::ok || status == FactorStatus::indefinite; }
  std::string message() const;  // one line naming the status, block, row and pivot
};

// The kernels the numeric phase runs (factor/passes.h), process-wide: "avx2" (4 lanes per vector)
// on a CPU with AVX2 in an x86-64 build, else "sse2" (2 lanes; the name of the portable build
// elsewhere). The values are the same bit for bit either way; only the speed differs.
const char* kernel_isa();
// Chooses the kernels: "auto" (the default: the best this CPU runs), "sse2" or "avx2".
// ArgumentError for another name or one this CPU or build cannot run. For benchmarks and tests
// that compare the two; not thread-safe against a running factorization.
void set_kernel_isa(const std::string& isa);
// Whether the chosen kernels are 4 lanes wide or wider ("avx2", "avx512"): the one CPU-feature
// dispatch of the build, which solver/'s contact lanes follow too (same values either way).
bool kernels_use_avx2();

namespace detail {
// Cache-line-aligned storage for the numeric phase's arrays, so that where a 4-lane load of the
// packed values splits a cache line depends on the Symbolic's layout only, not on where malloc
// put the array in this run (papers/factor.md "Four lanes with AVX2").
template <class T>
struct CacheAligned {
  using value_type = T;
  static constexpr std::align_val_t kAlign{64};
  CacheAligned() = default;
  template <class U>
  CacheAligned(const CacheAligned<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlign)); }
  void deallocate(T* p, size_t) { ::operator delete(p, kAlign); }
  friend bool operator==(const CacheAligned&, const CacheAligned&) { return true; }
};
template <class T>
using AlignedVector = std::vector<T, CacheAligned<T>>;
}  // namespace detail

class Numeric {
 public:
  explicit Numeric(const Symbolic& symbolic);  // the symbolic object must outlive this one
  Numeric(const Symbolic&&) = delete;          // so a temporary one is refused at compile time

  // Loads a and factors it. a must have the symbolic phase's pattern (checked in every build:
  // ArgumentError); a NaN or infinite entry is the status not_finite naming it.
  FactorInfo factorize(const SymmetricCsc& a, const FactorOptions& options = {});
  const FactorInfo& info() const { return info_; }
  bool factored() const { return factored_; }  // a factorization ran: info() is its outcome
  // Loading without a matrix (a caller assembling H straight into the factor's storage):
  // begin_load() zeroes the packed values and returns them; the caller adds each stored entry p
  // of the symbolic phase's pattern at symbolic().load_map()[p]; factorize_loaded() factors them.
  std::span<double> begin_load();
  FactorInfo factorize_loaded(const FactorOptions& options = {});

  // x = H^-1 b in place, b in the original row order; `nrhs` columns of length n, column-major
  // with leading dimension ld >= n (0: n). ArgumentError unless the last factorization is usable
  // and nrhs >= 0, ld >= n; the pointer form cannot check b's length, the span form checks that
  // b holds exactly nrhs columns of n.
  void solve(double* b, int nrhs = 1, int ld = 0);
  void solve(std::span<double> b, int nrhs = 1);

  // The factor expanded to CHOLMOD's scalar convention for the permuted matrix P H P^T
  // (perm = symbolic().perm()): strictly-lower unit L with D on the diagonal, every block dense.
  SymmetricCsc scalar_ldl() const;

  const Symbolic& symbolic() const { return *symbolic_; }
  // The packed factor. After a factorization that stopped, the values it did not reach are
  // unspecified (loaded, partly reduced, or left by the factorization before).
  std::span<const double> values() const { return values_; }

 private:
  bool load(const SymmetricCsc& a, const FactorOptions& options);  // false: a non-finite entry
  void prepare(const FactorOptions& options);  // regularization and zero-pivot thresholds
  FactorInfo eliminate();                      // the elimination and the inertia, into info_
  FactorInfo finish();                         // eliminate(), the pivot named at H's scale
  const FactorInfo& refuse_not_finite(int row, double value);  // status not_finite for that entry
  // What eliminate(), prepare() and solve() read of supernode t, packed into one record per
  // supernode (built by the constructor; the Symbolic is immutable): the Symbolic's
  // accessors read ten arrays, two of them through sn_begin_, per supernode; on a chain (one
  // small pivot per supernode) those lookups and the tests choosing the kernel were a tenth of
  // the factorization (perf, papers/factor.md "Per-pivot overhead").
  passes::Factor passes_factor();
  void mark_first_writes(std::vector<uint8_t>& loaded) const;  // the constructor's zeroing plan
  const Symbolic* symbolic_;
  std::vector<passes::Step> steps_;  // (size symbolic.num_supernodes())
  std::vector<int> edge_targets_;   // mapped steps' targets and columns (passes::Factor; size their edge blocks)
  std::vector<int> edge_columns_;
  // The values load() must zero: offset and length of each run of entries that no stored entry
  // of the pattern loads and no run writes first (fill blocks, an E's or a node's zeros, a BLAS
  // node's row-major lower triangle, where other supernodes' updates gather: dense.h).
  // A per-block node's upper triangle is not among them: nothing reads or writes it, so it stays
  // the zero the constructor put there (zeroing all values was 4 % of chain-300's factorization).
  std::vector<int64_t> zero_runs_;  // (size 2 x runs)
  std::vector<int32_t> diag_pos_;   // value offset of each permuted row's diagonal (size n)
  detail::AlignedVector<double> values_;   // packed blocks (size symbolic.num_values())
  detail::AlignedVector<double> scratch_;  // W = E_{*,k} L_kk^-T for the reduction (kernels::begin_l; size symbolic.scratch_size())
  detail::AlignedVector<double> floor_;    // zero-pivot threshold per permuted row (size n)
  detail::AlignedVector<double> diag_;     // |H_rr| regularized, per permuted row (size n)
  detail::AlignedVector<double> work_;     // permuted right-hand side (size n)
  detail::AlignedVector<double> inv_d_;    // 1 / D per permuted row (size n)
  std::vector<int32_t> map_;     // a mapped supernode's target: value offset of each of its rows (size n if any is mapped)
  int scale_ = 0;                // the factored matrix is 2^-scale_ H (prepare(): H out of range)
  FactorInfo info_;
  bool factored_ = false;        // a factorization ran (info_ is its outcome)
};

}  // namespace ldlpgs
