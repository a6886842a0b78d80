// Verification against CHOLMOD (verify.h).
#include "ldlpgs/factor/verify.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {

// Max relative difference of two lower-triangular factors in CHOLMOD's convention (D on the
// diagonal): separately for the strictly lower part (L) and the diagonal (D).
std::pair<double, double> factor_differences(const SymmetricCsc& ours, const SymmetricCsc& ref) {
  double l_diff = 0, l_max = 0, d_diff = 0, d_max = 0;
  std::vector<double> column(ours.n, 0.0);  // one column of ours, scattered (size n)
  for (int c = 0; c < ours.n; ++c) {
    for (int p = ours.col_ptr[c]; p < ours.col_ptr[c + 1]; ++p) column[ours.row_idx[p]] = ours.values[p];
    for (int p = ref.col_ptr[c]; p < ref.col_ptr[c + 1]; ++p) {
      const int r = ref.row_idx[p];
      const double diff = std::abs(column[r] - ref.values[p]);
      column[r] = 0;
      if (r == c) {
        d_diff = std::max(d_diff, diff);
        d_max = std::max(d_max, std::abs(ref.values[p]));
      } else {
        l_diff = std::max(l_diff, diff);
        l_max = std::max(l_max, std::abs(ref.values[p]));
      }
    }
    // What remains is stored only by us (zeros of the dense blocks, up to rounding).
    for (int p = ours.col_ptr[c]; p < ours.col_ptr[c + 1]; ++p) {
      const int r = ours.row_idx[p];
      (r == c ? d_diff : l_diff) = std::max(r == c ? d_diff : l_diff, std::abs(column[r]));
      column[r] = 0;
    }
  }
  return {l_max > 0 ? l_diff / l_max : l_diff, d_max > 0 ? d_diff / d_max : d_diff};
}

// cond_1(A) = ||A||_1 ||A^-1||_1, with Hager's estimate of ||A^-1||_1 (Higham, Accuracy and
// Stability, algorithm 15.1; LAPACK's dlacon) from solves with the factorization; A is symmetric,
// so A^-T solves are A^-1 solves. The right-hand sides are multiplied by c = 2^ilogb(||A||_1), so
// the solves return c A^-1 x, of the size of cond itself: ||A^-1||_1 alone overflows for a
// well-conditioned matrix at 1e-314. c is a power of two: no rounding but subnormal.
double condition_estimate(const SymmetricCsc& a, Numeric& f) {
  const int n = a.n;
  const double norm = norm_inf(a);  // = ||A||_1 for symmetric A
  if (n == 0 || norm == 0) return 0;
  const int e = std::ilogb(norm);
  std::vector<double> x(n, 1.0 / n), y(n);
  double estimate = 0;  // of c ||A^-1||_1
  for (int iteration = 0; iteration < 5; ++iteration) {
    for (int i = 0; i < n; ++i) y[i] = std::ldexp(x[i], e);
    f.solve(y);
    estimate = 0;
    for (double v : y) estimate += std::abs(v);
    for (int i = 0; i < n; ++i) y[i] = std::ldexp(y[i] >= 0 ? 1.0 : -1.0, e);
    f.solve(y);  // z = c A^-1 sign(A^-1 x); the test below is homogeneous in c
    int j = 0;
    double zx = 0;
    for (int i = 0; i < n; ++i) {
      zx += y[i] * x[i];
      if (std::abs(y[i]) > std::abs(y[j])) j = i;
    }
    if (std::abs(y[j]) <= zx) break;
    std::fill(x.begin(), x.end(), 0.0);
    x[j] = 1;
  }
  return std::ldexp(norm, -e) * estimate;
}

}  // namespace

Verification verify_against_cholmod(const SymmetricCsc& a, const BlockPattern& blocks, const Ordering& ordering,
                                    const VerifyTolerance& tolerance, const SymbolicOptions& symbolic) {
  // A NaN or infinite tolerance turned a check off (backward inf: "agree" whatever the error) or
  // failed everything (nan: "DISAGREE"); a negative one refuses rounding itself.
  for (auto [name, value] : {std::pair{"factor", tolerance.factor}, {"per_condition", tolerance.per_condition},
                             {"backward", tolerance.backward}})
    if (!(value >= 0) || !std::isfinite(value))
      throw ArgumentError(std::string("verify_against_cholmod: the ") + name + " tolerance must be finite and >= 0, got " +
                          std::to_string(value));
  Verification v;
  v.ordering = ordering.name;
  v.chosen = ordering.chosen;
  v.tolerance = tolerance;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> x_true(a.n), b(a.n);
  for (int i = 0; i < a.n; ++i) x_true[i] = i % 2 ? -1.0 : 1.0;
  symmetric_multiply(a, x_true, b);

  const Symbolic s = Symbolic::analyze(a, blocks, ordering, symbolic);
  Numeric f(s);
  v.info = f.factorize(a);
  v.nnz_L = s.nnz_l();
  v.flops = s.flops();

  Cholmod cm;
  // CHOLMOD factors in the order we do (Symbolic::perm: the ordering's, postordered).
  const std::span<const int> perm = s.perm();
  const CholmodCounts counts = cholmod_counts(a, perm, cm);
  v.nnz_L_cholmod = static_cast<int64_t>(counts.lnz);
  v.flops_cholmod = counts.fl;
  const CholmodLdl ref = cholmod_ldl(a, perm, b, cm);
  v.cholmod_status = ref.status;
  if (ref.minor < a.n) v.cholmod_row = perm[ref.minor];
  const bool cholmod_usable = v.cholmod_factored();

  if (cholmod_usable) v.backward_error_cholmod = backward_error(a, ref.x, b);
  else v.backward_error_cholmod = nan;
  if (!v.info.usable()) {
    v.L_rel_diff = v.D_rel_diff = v.x_rel_diff = v.backward_error = nan;
    return v;
  }
  std::vector<double> x = b;
  f.solve(x);
  v.backward_error = backward_error(a, x, b);
  v.condition_estimate = condition_estimate(a, f);
  v.factor_tolerance = std::max(tolerance.factor, tolerance.per_condition * v.condition_estimate);
  // A tolerance of 1 or more lets x differ from CHOLMOD's in every digit (cond_1 >= 4.5e15 at
  // the defaults); one that is inf or NaN was not computed: neither verifies anything.
  v.verifiable = v.factor_tolerance < 1;
  if (!cholmod_usable) {
    v.L_rel_diff = v.D_rel_diff = v.x_rel_diff = nan;
    return v;
  }
  std::tie(v.L_rel_diff, v.D_rel_diff) = factor_differences(f.scalar_ldl(), ref.l);
  double dx = 0, xn = 0;
  for (int i = 0; i < a.n; ++i) {
    dx = std::max(dx, std::abs(x[i] - ref.x[i]));
    xn = std::max(xn, std::abs(ref.x[i]));
  }
  v.x_rel_diff = xn > 0 ? dx / xn : dx;
  v.ok = v.verifiable && v.L_rel_diff <= v.factor_tolerance && v.D_rel_diff <= v.factor_tolerance &&
         v.x_rel_diff <= v.factor_tolerance && v.backward_error <= tolerance.backward;
  return v;
}

}  // namespace ldlpgs
