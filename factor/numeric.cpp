// Numeric phase: load, eliminate pivot by pivot with the kernels of kernels.h, solve.
#include "ldlpgs/factor/numeric.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

#include "ldlpgs/sparse/error.h"

#include "ldlpgs/factor/passes.h"

namespace ldlpgs {

const char* to_string(FactorStatus status) {
  switch (status) {
    case FactorStatus::ok: return "ok";
    case FactorStatus::indefinite: return "indefinite";
    case FactorStatus::zero_pivot: return "zero pivot";
    case FactorStatus::not_finite: return "not finite";
  }
  return "?";
}

std::string FactorInfo::message() const {
  std::ostringstream out;
  out << to_string(status);
  if (block >= 0) out << " at block " << block << " (row " << row << "), pivot " << pivot;
  out << "; inertia +" << inertia.positive << " -" << inertia.negative << " 0:" << inertia.zero
      << ", smallest pivot ratio " << min_pivot_ratio;
  return out.str();
}

namespace {
// (__builtin_cpu_init: the first call may come from a static initializer, before libgcc's.)
#ifdef LDLPGS_HAVE_AVX2_PASSES
bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}
#else
bool cpu_has_avx2() { return false; }
#endif
#ifdef LDLPGS_HAVE_AVX512_PASSES
bool cpu_has_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
}
#else
bool cpu_has_avx512() { return false; }
#endif
const passes::Passes* best_passes() {
#ifdef LDLPGS_HAVE_AVX2_PASSES
  if (cpu_has_avx2()) return &passes::kAvx2;
#endif
  return &passes::kSse2;
}
// The passes in use: a function's static, so that a factorization in another translation unit's
// static initializer finds them set.
const passes::Passes*& current_passes() {
  static const passes::Passes* p = best_passes();
  return p;
}

// 1 if x is NaN or infinite, else 0: an IEEE double is so exactly when its 11 exponent bits are
// all ones. OR-ed over many values (latency 1) instead of a branch per entry or a floating-point
// sum (its 4-cycle chain made the load a fifth of a small factorization).
inline uint64_t not_finite_bit(double x) { return (((std::bit_cast<uint64_t>(x) >> 52) & 0x7ff) + 1) >> 11; }

}  // namespace

const char* kernel_isa() { return current_passes()->isa; }

bool kernels_use_avx2() { return current_passes() != &passes::kSse2; }

void set_kernel_isa(const std::string& isa) {
  if (isa == "auto") {
    current_passes() = best_passes();
  } else if (isa == "sse2") {
    current_passes() = &passes::kSse2;
  } else if (isa == "avx2") {
#ifdef LDLPGS_HAVE_AVX2_PASSES
    if (!cpu_has_avx2()) throw ArgumentError("kernels: this CPU has no AVX2");
    current_passes() = &passes::kAvx2;
#else
    throw ArgumentError("kernels: this build has no AVX2 kernels");
#endif
  } else if (isa == "avx512") {
#ifdef LDLPGS_HAVE_AVX512_PASSES
    if (!cpu_has_avx512()) throw ArgumentError("kernels: this CPU has no AVX-512F");
    current_passes() = &passes::kAvx512;
#else
    throw ArgumentError("kernels: this build has no AVX-512 kernels");
#endif
  } else {
    throw ArgumentError("kernels: unknown '" + isa + "' (auto, sse2, avx2, avx512)");
  }
}

Numeric::Numeric(const Symbolic& symbolic)
    : symbolic_(&symbolic),
      values_(symbolic.num_values()),
      scratch_(symbolic.scratch_size()),
      floor_(symbolic.num_rows()),
      diag_(symbolic.num_rows()),
      work_(symbolic.num_rows()),
      inv_d_(symbolic.num_rows()),
      map_(symbolic.any_mapped() ? symbolic.num_rows() : 0) {
  const Symbolic& s = symbolic;
  steps_.resize(s.num_supernodes());
  diag_pos_.reserve(s.num_rows());
  using passes::Kind;
  for (int t = 0; t < s.num_supernodes(); ++t) {
    passes::Step& st = steps_[t];
    st.node = s.node_offset(t);
    st.rsi = s.rsi(t);
    st.rows = s.edge_rows(t);
    st.sizes = s.edge_sizes(t);
    st.erows = s.column_rows(t);
    st.d = s.supernode_size(t);
    st.h = s.supernode_height(t);
    st.r0 = s.supernode_row_start(t);
    st.m = static_cast<int>(s.supernode_edges(t).size());
    st.single = 0;
    st.fold = 0;
    st.edges = static_cast<int>(edge_targets_.size());
    if (s.supernode_blas(t)) {
      st.kind = s.supernode_mapped(t) ? Kind::blas_mapped : Kind::blas;
    } else if (s.supernode_mapped(t)) {
      st.kind = Kind::blocks_mapped;
    } else if (st.m == 1 && st.d <= 6 && st.sizes[0] <= 6 && st.rsi[0] == 1 && st.rsi[3] == 0 && st.rsi[4] == st.h) {
      // One edge block, one run onto its target's diagonal: a chain's pivot (kernels.h).
      st.kind = Kind::single;
      st.single = static_cast<uint8_t>(6 * (st.d - 1) + st.sizes[0] - 1);
    } else {
      st.kind = Kind::blocks;
    }
    if (st.kind == Kind::blocks_mapped || st.kind == Kind::blas_mapped)
      for (const int b : s.supernode_edges(t)) {
        const int u = s.supernode_of(b);
        edge_targets_.push_back(u);
        edge_columns_.push_back(s.row_start(b) - s.supernode_row_start(u));
      }
    for (int l = 0; l < st.d; ++l) diag_pos_.push_back(static_cast<int32_t>(st.node + int64_t{l} * st.d + l));
  }
  // A BLAS node block that other supernodes update gathers their sums in its row-major lower
  // triangle, to be added to its column-major one (dense.h).
  for (int t = 0; t < s.num_supernodes(); ++t)
    for (const int b : s.supernode_edges(t)) steps_[s.supernode_of(b)].fold = 1;
  // What load() zeroes: every value the load map misses, but for those a run writes first
  // (Symbolic::rsi) and for the triangle of a node block that stays zero: the upper one where the
  // kernels of kernels.h eliminate (they read and write the lower triangle only), the row-major
  // lower one of a BLAS node that no other supernode updates (dense.h: the factorization leaves
  // it zero).
  std::vector<uint8_t> loaded(values_.size(), 0);
  for (const int32_t q : s.load_map()) loaded[q] = 1;
  mark_first_writes(loaded);
  for (int t = 0; t < s.num_supernodes(); ++t) {
    const passes::Step& st = steps_[t];
    if (is_blas(st) && st.fold) continue;
    for (int64_t r = 0; r < st.d; ++r)
      for (int64_t c = r + 1; c < st.d; ++c) loaded[s.node_entry(t, r, c)] = 1;
  }
  for (int64_t q = 0; q < std::ssize(loaded);) {
    if (loaded[q]) {
      ++q;
      continue;
    }
    const int64_t begin = q;
    while (q < std::ssize(loaded) && !loaded[q]) ++q;
    // Zeroing a loaded value is harmless (the scatter overwrites it), as is one a run writes
    // first (it stores there): a run starting within kGap values of the last one extends it. bcsstk13's zeros (partly zero blocks, fill) were
    // 6,586 runs, and as many calls cost more than one memset of all values.
    constexpr int64_t kGap = 64;
    const size_t k = zero_runs_.size();
    if (k > 0 && begin - (zero_runs_[k - 2] + zero_runs_[k - 1]) <= kGap) {
      zero_runs_[k - 1] = q - zero_runs_[k - 2];
    } else {
      zero_runs_.push_back(begin);
      zero_runs_.push_back(q - begin);
    }
  }
}

// The entries of the runs that write their target first (Symbolic::rsi, rows negated) join
// `loaded`: those runs store there (kernels::reduce_runs), so load() need not zero them.
void Numeric::mark_first_writes(std::vector<uint8_t>& loaded) const {
  if (symbolic_->any_mapped()) return;  // (no flags then, and a mapped step has no runs)
  for (const passes::Step& st : steps_)
    for_each_run(st.rsi, st.sizes, st.m, [&](const int32_t* run, int i, int ld, int db) {
      if (run[2] < 0) for_each_run_entry(run, i, ld, db, [&](int64_t q) { loaded[q] = 1; });
    });
}

bool Numeric::load(const SymmetricCsc& a, const FactorOptions& options) {
  const Symbolic& s = *symbolic_;
  assert(a.n == s.num_rows() && a.nnz() == s.pattern_nnz());
  for (size_t i = 0; i < zero_runs_.size(); i += 2)
    std::fill_n(values_.begin() + zero_runs_[i], zero_runs_[i + 1], 0.0);
  // Scatter, and check finiteness on the way (passes.inc).
  if (!current_passes()->scatter(values_.data(), s.load_map().data(), a.values.data(), a.nnz())) return false;
  prepare(options);
  return true;
}

// H + eps diag(H), scaled into range when it is not, and the zero-pivot thresholds relative to
// its diagonal.
void Numeric::prepare(const FactorOptions& options) {
  const Symbolic& s = *symbolic_;
  // H + eps diag(H), and the largest and the smallest nonzero |H_ii| (passes.inc).
  const int n = s.num_rows();
  double largest = 0, smallest = 0;
  current_passes()->diagonal(values_.data(), diag_pos_.data(), n, 1 + options.regularization, diag_.data(), largest,
                             smallest);
  // At the edges of double the elimination breaks though the matrix is fine: 1 / d overflows for
  // a subnormal pivot (1e-314: "ok", then a NaN solution), 1e-12 |H_rr| underflows to 0, a
  // Schur update overflows near 1e308. Factoring 2^-e H instead is exact (a power of
  // two) and gives the same L and 2^-e D; solve() scales b alike, so x is unchanged. e centres
  // the nonzero diagonal's binades on 1, but keeps every entry below 2^1000. Inside
  // [2^-500, 2^500] nothing can go out of range (pivot ratios, the 1e-12 floor and the fill
  // stay hundreds of binades from it), so the usual matrix is not touched: no pass, no rounding.
  constexpr int kSafe = 500, kHighest = 1000;
  scale_ = 0;
  if (largest > std::ldexp(1.0, kSafe) || smallest < std::ldexp(1.0, -kSafe)) {
    // The largest |entry| of H: the loaded values' (the rest is zero, or stale where a run
    // writes its target first, Symbolic::rsi).
    double amax = 0;
    for (const int32_t q : s.load_map()) amax = std::max(amax, std::abs(values_[q]));
    if (amax > 0) {
      const int top = std::ilogb(amax);
      scale_ = std::max(std::midpoint(std::ilogb(smallest), std::ilogb(largest)), top - kHighest);
      if (scale_ != 0) {
        for (double& x : values_) x = std::ldexp(x, -scale_);
        for (double& h : diag_) h = std::ldexp(h, -scale_);
        largest = std::ldexp(largest, -scale_);
      }
    }
  }
  // A pivot at or below the smallest normal double counts as zero whatever the threshold: its
  // reciprocal is inf (1 / 1e-314) or nearly, and the solve through it NaN. After the scaling
  // that is a pivot below 2^-1022 of a diagonal centred on 1, a zero pivot in any reading.
  current_passes()->floors(diag_.data(), n, options.zero_pivot, largest, floor_.data());
}

std::span<double> Numeric::begin_load() {
  std::fill(values_.begin(), values_.end(), 0.0);
  return values_;
}

FactorInfo Numeric::factorize_loaded(const FactorOptions& options) {
  const Symbolic& s = *symbolic_;
  info_ = FactorInfo{};
  factored_ = true;
  info_.min_pivot_ratio = s.num_rows() ? std::numeric_limits<double>::infinity() : 0;
  uint64_t not_finite = 0;  // over every packed value (fill and unused entries are 0)
  for (const double x : values_) not_finite |= not_finite_bit(x);
  if (not_finite) {
    // The first offending entry's supernode t holds its offset, in the node block (row l) or in
    // row r of its E: that permuted row, in the original order, names it.
    const int64_t at = std::find_if(values_.begin(), values_.end(), [](double x) { return !std::isfinite(x); }) -
                       values_.begin();
    int t = 0;
    while (s.node_offset(t + 1) <= at) ++t;
    const int64_t d = s.supernode_size(t);
    const int64_t local = at - s.node_offset(t);
    const int64_t node_row = s.supernode_blas(t) ? local % d : local / d;  // (column-major: dense.h)
    const int row = local < d * d ? s.supernode_row_start(t) + static_cast<int>(node_row)
                                  : s.column_rows(t)[(local - d * d) / d];
    return refuse_not_finite(s.perm()[row], values_[at]);
  }
  prepare(options);
  return finish();
}

FactorInfo Numeric::factorize(const SymmetricCsc& a, const FactorOptions& options) {
  const Symbolic& s = *symbolic_;
  s.check_pattern(a, "factorize");
  info_ = FactorInfo{};
  factored_ = true;
  info_.min_pivot_ratio = s.num_rows() ? std::numeric_limits<double>::infinity() : 0;
  if (!load(a, options)) {
    for (int c = 0; c < a.n; ++c)
      for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p)
        if (!std::isfinite(a.values[p])) return refuse_not_finite(a.row_idx[p], a.values[p]);
    return refuse_not_finite(-1, 0);  // (unreachable: load() saw one)
  }
  return finish();
}

// The elimination, and the pivot it names back at H's scale (prepare() scaled H by 2^-scale_).
FactorInfo Numeric::finish() {
  eliminate();
  info_.pivot = std::ldexp(info_.pivot, scale_);
  return info_;
}

// A NaN or infinity in the input is the input's fault: the status names the entry's original row
// and the block holding it.
const FactorInfo& Numeric::refuse_not_finite(int row, double value) {
  const Symbolic& s = *symbolic_;
  info_.status = FactorStatus::not_finite;
  info_.row = row;
  info_.pivot = value;
  const auto perm = s.perm();
  for (int k = 0; k < s.num_pivots(); ++k)
    for (int l = 0; l < s.size(k); ++l)
      if (perm[s.row_start(k) + l] == row) info_.block = s.block(k);
  info_.min_pivot_ratio = 0;
  return info_;
}

passes::Factor Numeric::passes_factor() {
  return {steps_.data(),  static_cast<int>(steps_.size()), values_.data(),        scratch_.data(), floor_.data(),
          inv_d_.data(),  map_.data(),                       edge_targets_.data(), edge_columns_.data()};
}

FactorInfo Numeric::eliminate() {
  const Symbolic& s = *symbolic_;
  int processed = s.num_rows();  // rows with a completed pivot
  int bad = -1;
  if (const int t = current_passes()->eliminate(passes_factor(), bad); t >= 0) {
    const passes::Step& st = steps_[t];
    const int row = st.r0 + bad;
    const double pivot = values_[st.node + int64_t{bad} * st.d + bad];
    processed = row;
    info_.status = std::isfinite(pivot) ? FactorStatus::zero_pivot : FactorStatus::not_finite;
    info_.block = s.block(s.pivot_of_row(row));
    info_.row = s.perm()[row];
    info_.pivot = pivot;
    info_.inertia.zero = 1;
    if (diag_[row] > 0) info_.min_pivot_ratio = std::abs(pivot) / diag_[row];
  }
  // Inertia and min |d_r| / |H_rr| (passes.inc), in one pass after the elimination.
  double largest = 0;
  const int negative = current_passes()->inertia(inv_d_.data(), diag_.data(), processed, largest);
  info_.inertia.negative = negative;
  info_.inertia.positive = processed - negative;
  if (largest > 0) info_.min_pivot_ratio = std::min(info_.min_pivot_ratio, 1.0 / largest);
  if (negative > 0 && info_.status == FactorStatus::ok) {
    int r = 0;
    while (inv_d_[r] > 0) ++r;
    const int k = s.pivot_of_row(r), t = s.supernode_of(k);
    info_.status = FactorStatus::indefinite;
    info_.block = s.block(k);
    info_.row = s.perm()[r];
    const int64_t l = r - s.supernode_row_start(t), d = s.supernode_size(t);
    info_.pivot = values_[s.node_offset(t) + l * d + l];
  }
  if (!std::isfinite(info_.min_pivot_ratio)) info_.min_pivot_ratio = 0;
  return info_;
}

void Numeric::solve(std::span<double> b, int nrhs) {
  const int64_t n = symbolic_->num_rows();
  if (nrhs < 0 || std::ssize(b) != n * nrhs)
    throw ArgumentError("solve: a right-hand side of " + std::to_string(b.size()) + " entries for " +
                        std::to_string(nrhs) + " column(s) of " + std::to_string(n) + " rows");
  solve(b.data(), nrhs, static_cast<int>(n));
}

void Numeric::solve(double* b, int nrhs, int ld) {
  const Symbolic& s = *symbolic_;
  const int n = s.num_rows();
  if (ld == 0) ld = n;
  if (!factored_) throw ArgumentError("solve: nothing is factored yet");
  if (!info_.usable())
    throw ArgumentError("solve: the last factorization is not usable (" + info_.message() + ")");
  if (nrhs < 0 || ld < n)
    throw ArgumentError("solve: nrhs " + std::to_string(nrhs) + ", leading dimension " + std::to_string(ld) +
                        " for " + std::to_string(n) + " rows");
  const std::span<const int> perm = s.perm();
  double* w = work_.data();
  const passes::Factor f = passes_factor();
  for (int j = 0; j < nrhs; ++j) {
    double* x = b + static_cast<int64_t>(j) * ld;
    for (int i = 0; i < n; ++i) w[i] = x[perm[i]];
    if (scale_ != 0)  // (2^-e H)^-1 (2^-e b) = H^-1 b (prepare)
      for (int i = 0; i < n; ++i) w[i] = std::ldexp(w[i], -scale_);
    // H = L N L^T: forward through L and N, then back through L^T (passes.inc).
    current_passes()->forward(f, w);
    current_passes()->backward(f, w);
    for (int i = 0; i < n; ++i) x[perm[i]] = w[i];
  }
}

SymmetricCsc Numeric::scalar_ldl() const {
  const Symbolic& s = *symbolic_;
  SymmetricCsc l;
  l.n = s.num_rows();
  l.col_ptr.assign(1, 0);
  const double* v = values_.data();
  // The blocks of pivot k's column (L's block structure): a relaxed supernode (SymbolicOptions::
  // relax_max_zeros) stores its columns over the union of their rows, and its explicit zeros
  // are left out, as CHOLMOD's own relaxed zeros are not in its simplicial L.
  std::vector<uint8_t> in_column(s.num_pivots(), 0);  // (size num_pivots)
  for (int t = 0; t < s.num_supernodes(); ++t) {
    const int64_t d = s.supernode_size(t), h = s.supernode_height(t);
    const int r0 = s.supernode_row_start(t);
    const double* node = v + s.node_offset(t);
    const double* lb = v + s.column_offset(t);
    const int* rows = s.column_rows(t);
    const bool single = keeps_l(steps_[t]);
    for (int k = s.supernode_begin(t); k < s.supernode_begin(t + 1); ++k) {
      for (const int j : s.edges(k)) in_column[j] = 1;
      in_column[k] = 1;
      for (int64_t c = s.row_start(k) - r0; c < s.row_start(k + 1) - r0; ++c) {
        l.row_idx.push_back(r0 + static_cast<int>(c));
        l.values.push_back(std::ldexp(node[c * d + c], scale_));  // D of H, not of 2^-e H
        for (int64_t r = c + 1; r < d; ++r) {
          if (!in_column[s.pivot_of_row(r0 + static_cast<int>(r))]) continue;
          l.row_idx.push_back(r0 + static_cast<int>(r));
          l.values.push_back(v[s.node_entry(t, r, c)]);
        }
        // Below the node the scalar L is Y = L_{*,k} L_kk: stored as it is, but for a fused
        // chain column, which holds L_{*,k} (numeric.h).
        for (int64_t r = 0; r < h; ++r) {
          if (!in_column[s.pivot_of_row(rows[r])]) continue;
          double sum = lb[r * d + c];
          if (single)
            for (int64_t m = c + 1; m < d; ++m) sum += lb[r * d + m] * node[m * d + c];
          l.row_idx.push_back(rows[r]);
          l.values.push_back(sum);
        }
        l.col_ptr.push_back(static_cast<int>(l.row_idx.size()));
      }
      for (const int j : s.edges(k)) in_column[j] = 0;
      in_column[k] = 0;
    }
  }
  return l;
}

}  // namespace ldlpgs
