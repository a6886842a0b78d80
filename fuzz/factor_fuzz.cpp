// Fuzz target: the block LDL^T (Symbolic, Numeric) of a fuzzed symmetric matrix of n <= 8 rows
// against dense Eigen. Bytes: n, ordering, partition, a global power-of-two scale and a
// diagonal shift, then per lower entry a kind byte and its value (absent, a small integer, a
// power of two times one, or eight raw bytes: any double, NaN, inf and subnormals included).
//
// Findings are only what cannot be rounding (the theorems behind each check below):
// - an exception other than InputError/ArgumentError; a crash (ASan, UBSan);
// - a non-finite input entry not reported as not_finite;
// - status ok on a matrix Eigen finds clearly indefinite: with all pivots positive the computed
//   L D L^T is A + E, |E| <= c n eps sqrt(A_ii A_jj) (Cholesky's backward error; Higham 10.1),
//   so lambda_min(A) >= -1e-9 max |lambda|;
// - a positive definite matrix with cond_2 <= 1e10 (Eigen's eigenvalues) not factored ok, or
//   solved with a relative error above max(1e-8, 1000 n eps cond_2) (the forward error of a
//   Cholesky solve is c n eps cond_2, Higham 10.3): its pivots are >= lambda_min >= 1e-10
//   max A_ii, above the 1e-12 zero-pivot floor, at any scale of double.
#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <vector>

#include "fuzz/fuzz_common.h"
#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/ordering/ordering.h"
#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/partition.h"

using namespace ldlpgs;

namespace {

struct Bytes {
  const uint8_t* data;
  size_t size;
  uint8_t next() {
    if (size == 0) return 0;
    --size;
    return *data++;
  }
};

// Eigen's view of the same matrix, moved by a power of two (exact but for subnormals, which
// scale up exactly) to where Eigen's solvers work: largest |entry| in [1, 2).
struct Reference {
  Eigen::MatrixXd a;
  int exponent = 0;  // a = 2^-exponent A
};

Reference reference(const SymmetricCsc& m) {
  Reference r;
  r.a = Eigen::MatrixXd::Zero(m.n, m.n);
  double largest = 0;
  for (double v : m.values) largest = std::max(largest, std::abs(v));
  r.exponent = largest > 0 ? std::ilogb(largest) : 0;
  for (int c = 0; c < m.n; ++c)
    for (int p = m.col_ptr[c]; p < m.col_ptr[c + 1]; ++p)
      r.a(m.row_idx[p], c) = r.a(c, m.row_idx[p]) = std::ldexp(m.values[p], -r.exponent);
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in{data, size};
  const int n = 1 + in.next() % 8;
  const std::span<const OrderingInfo> all = orderings();
  const OrderingInfo& ordering = all[in.next() % all.size()];
  const int partition = in.next() % 4;  // rows, auto, pairs, one block
  const int scale = static_cast<int8_t>(in.next()) * 9;  // 2^-1152 .. 2^1143: every binade of double
  const bool dominant = in.next() & 1;

  std::vector<Triplet> entries;
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) {
      double v = 0;
      switch (in.next() % 4) {
        case 0: continue;  // not stored
        case 1: v = static_cast<int8_t>(in.next()) / 4.0; break;
        case 2: v = std::ldexp(static_cast<int8_t>(in.next()) % 2 ? 1.0 : -1.0, static_cast<int8_t>(in.next())); break;
        case 3: {
          uint64_t bits = 0;
          for (int k = 0; k < 8; ++k) bits |= uint64_t{in.next()} << (8 * k);
          v = std::bit_cast<double>(bits);
          break;
        }
      }
      entries.push_back({i, j, v});
    }
  }
  // Diagonally dominant on request (positive definite, and well-conditioned when the margin is
  // not lost to rounding): each diagonal entry becomes 1 + the sum of its row's |off-diagonals|.
  if (dominant) {
    std::vector<double> row_sum(n, 1.0);
    for (const Triplet& t : entries)
      if (t.row != t.col) row_sum[t.row] += std::abs(t.value), row_sum[t.col] += std::abs(t.value);
    std::erase_if(entries, [](const Triplet& t) { return t.row == t.col; });
    for (int i = 0; i < n; ++i) entries.push_back({i, i, row_sum[i]});
  }
  for (Triplet& t : entries) t.value = std::ldexp(t.value, scale);
  const SymmetricCsc a = csc_from_triplets(n, entries);
  bool finite = true;
  for (double v : a.values) finite = finite && std::isfinite(v);

  std::vector<int> sizes;
  switch (partition) {
    case 0: sizes = partition_uniform(n, 1); break;
    case 1: sizes = partition_auto(a); break;
    case 2: sizes = partition_uniform(n, 2); break;
    case 3: sizes = partition_uniform(n, n); break;
  }
  // What a finding prints after its reason: the case, to reproduce it without the fuzzer.
  auto fail = [&](const std::string& why, const Eigen::VectorXd& lambda) {
    std::string what = why + "\n  n " + std::to_string(n) + ", ordering " + std::string(ordering.name) +
                       ", partition " + std::to_string(partition) + ", entries (row col value):";
    char buf[64];
    for (int c = 0; c < n; ++c)
      for (int p = a.col_ptr[c]; p < a.col_ptr[c + 1]; ++p) {
        std::snprintf(buf, sizeof buf, " (%d %d %.17g)", a.row_idx[p], c, a.values[p]);
        what += buf;
      }
    what += "\n  eigenvalues (of 2^-e A):";
    for (double l : lambda) {
      std::snprintf(buf, sizeof buf, " %.6g", l);
      what += buf;
    }
    std::fprintf(stderr, "%s\n", what.c_str());
    fuzz::finding(why);
  };
  fuzz::accepted([&] {
    const BlockPattern blocks = BlockPattern::from_scalar(a, sizes);
    const Symbolic s = Symbolic::analyze(a, blocks, compute_ordering(ordering, blocks, a));
    Numeric f(s);
    const FactorInfo info = f.factorize(a);
    if (!finite) {
      if (info.status != FactorStatus::not_finite) fail("a non-finite entry factored as " + info.message(), {});
      return;
    }
    const Reference r = reference(a);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(r.a, Eigen::EigenvaluesOnly);
    // (Eigen's QL iteration can fail to converge on strongly graded matrices, 1 beside 1e-168:
    // its eigenvalues are then garbage, and nothing can be judged against them.)
    if (eig.info() != Eigen::Success) return;
    const Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
    const double largest = lambda.cwiseAbs().maxCoeff();
    if (info.status == FactorStatus::ok && lambda[0] < -1e-9 * largest)
      fail("status ok on an indefinite matrix: lambda_min " + std::to_string(lambda[0] / largest) +
                    " of the largest; " + info.message(), lambda);
    const bool well_conditioned_spd = largest > 0 && lambda[0] > 1e-10 * largest;
    if (!well_conditioned_spd) return;
    if (info.status != FactorStatus::ok)
      fail("a positive definite matrix of condition <= 1e10 factored as " + info.message(), lambda);
    const double tolerance = std::max(1e-8, 1e3 * n * 2.2e-16 * largest / lambda[0]);
    // b = 2^exponent A_ref (1, -1, ...)^T at A's scale, and the reference's b is 2^-exponent of
    // that b, exactly (b may be rounded to a subnormal on the way down, not on the way up).
    Eigen::VectorXd x_true(n);
    for (int i = 0; i < n; ++i) x_true[i] = i % 2 ? -1.0 : 1.0;
    Eigen::VectorXd b_ref = r.a * x_true;
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) {
      x[i] = std::ldexp(b_ref[i], r.exponent);
      if (!std::isfinite(x[i])) return;  // b itself overflows: nothing to solve
      b_ref[i] = std::ldexp(x[i], -r.exponent);
    }
    f.solve(x);
    const Eigen::VectorXd x_ref = r.a.llt().solve(b_ref);
    double diff = 0;
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(x[i])) fail("a non-finite solution after status ok: " + info.message(), lambda);
      diff = std::max(diff, std::abs(x[i] - x_ref[i]));
    }
    if (x_ref.lpNorm<Eigen::Infinity>() > 0) diff /= x_ref.lpNorm<Eigen::Infinity>();
    if (diff > tolerance) fail("the solution differs from Eigen's by " + std::to_string(diff) + " (relative)", lambda);
  });
  return 0;
}
