#pragma once
// The one place that talks to CHOLMOD: a RAII cholmod_common, views and copies between
// SymmetricCsc and cholmod_sparse, CHOLMOD's own Matrix Market reader (a reference for our
// reader), and the symbolic counts CHOLMOD computes for a given permutation (the reference for
// ordering/metrics).
#include <cholmod.h>

#include <span>
#include <string>

#include "sparse/csc.h"

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

}  // namespace ldlpgs
