#pragma once
// The one place that talks to CHOLMOD: a RAII cholmod_common, views and copies between
// SymmetricCsc and cholmod_sparse, CHOLMOD's own Matrix Market reader (a reference for our
// reader), and the symbolic counts CHOLMOD computes for a given permutation (the reference for
// ordering/metrics), and CHOLMOD's numeric simplicial LDL^T in a given order (the reference for
// factor/).
#include <cholmod.h>

#include <span>
#include <string>
#include <vector>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

class Cholmod {
 public:
  Cholmod();
  ~Cholmod();
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;
  cholmod_common* common() { return &common_; }

 private:
  cholmod_common common_;
};

// A cholmod_sparse (stype = -1, int indices, real) that points into a's arrays: no copy, valid
// while a lives and is not changed. CHOLMOD functions take it as const input.
cholmod_sparse cholmod_view(const SymmetricCsc& a);
// A cholmod_dense column (size x.size() x 1, real) that points into x, for right-hand sides and
// solutions: no copy, valid while x lives.
cholmod_dense cholmod_view(std::span<double> x);
// Copies the lower triangle of a real square cholmod_sparse of any stype (for stype = 1, the
// transpose of the stored upper triangle).
SymmetricCsc from_cholmod(const cholmod_sparse& a, Cholmod& cm);

// CHOLMOD's cholmod_read_sparse of a Matrix Market file (throws InputError if it fails).
SymmetricCsc cholmod_read(const std::string& path, Cholmod& cm);

// What cholmod_analyze_p reports for a's simplicial LDL^T under the given scalar pivot order
// (perm[k] = row eliminated k-th), with CHOLMOD told to use that order and not to postorder.
struct CholmodCounts {
  double lnz;  // Common->lnz: entries in L, diagonal included
  double fl;   // Common->fl: flop count, sum over columns of (column count)^2
};
CholmodCounts cholmod_counts(const SymmetricCsc& a, std::span<const int> perm, Cholmod& cm);

// CHOLMOD's simplicial LDL^T of P A P^T for the given scalar pivot order (perm[k] = row eliminated
// k-th; CHOLMOD_GIVEN, no postordering, simplicial, final_ll = false), and its solution of A x = b.
// CHOLMOD takes any nonzero pivot, negative ones included: an indefinite matrix factors with
// status CHOLMOD_OK. Only an exact zero D(k,k) stops it: status CHOLMOD_NOT_POSDEF, minor = k
// (a column of P A P^T), and CHOLMOD then zeroes column k and every later column of L and D.
struct CholmodLdl {
  SymmetricCsc l;         // L of P A P^T in CHOLMOD's LDL^T convention: unit diagonal not stored,
                          // the diagonal entries hold D (size n x n, lower, columns sorted)
  std::vector<double> x;  // solution of A x = b, original row order (size n); empty if b was
                          // empty or the factorization failed (D has a zero: no silent Inf/NaN)
  int status;             // Common->status after cholmod_factorize (CHOLMOD_OK, CHOLMOD_NOT_POSDEF ...)
  int minor;              // L->minor: n if the factorization completed, else the failing column
};
// b is empty or of size n. The settings of cm are left as they were.
CholmodLdl cholmod_ldl(const SymmetricCsc& a, std::span<const int> perm, std::span<const double> b,
                       Cholmod& cm);

}  // namespace ldlpgs
