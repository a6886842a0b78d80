#pragma once
// factor/: the sparse block LDL^T of the talk ("Physics Solver in Roblox", GDC), in two phases
// with two types, as CSparse (cs_schol / cs_chol), Eigen (analyzePattern / factorize) and MuJoCo
// (mju_cholFactorSymbolic / Numeric) split them:
//
//   symbolic.h  Symbolic: block structure of L with fill, supernodes (runs of pivots with nested
//               structure), packed layout (column-major blocks, row-major elements),
//               reduction-scattering indices, load map. Once per pattern.
//   numeric.h   Numeric: factorize (regularization eps diag(H), status, inertia), solve with one
//               or many right-hand sides, the factor in CHOLMOD's scalar convention. Every frame.
//   kernels.h   the per-pivot kernels templated on the block size 1..6, generic path above.
//   passes.h    the elimination and the solve's two passes over the supernodes, built twice
//               (SSE2 and AVX2 kernels: 2 or 4 lanes) and chosen by the CPU (kernel_isa()).
//   dense.h     the same steps for wide supernodes with level-3 BLAS (dtrsm, dgemm).
//   verify.h    the factor against CHOLMOD's simplicial LDL^T and the backward error of both.
//   block_ldlt.h BlockLDLT: both phases behind Eigen's sparse-solver interface, for users who
//               hold an Eigen::SparseMatrix (analyzePattern, factorize, compute, solve, info).
//
// Typical use:
//   Ordering o = compute_ordering(find_ordering("meca"), blocks, h);
//   Symbolic s = Symbolic::analyze(h, blocks, o);
//   Numeric f(s);
//   if (FactorInfo info = f.factorize(h, {.regularization = 1e-8}); info.usable()) f.solve(b);
#include "ldlpgs/factor/block_ldlt.h"
#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/factor/symbolic.h"
