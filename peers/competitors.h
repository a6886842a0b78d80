#pragma once
// The direct solvers ldlpgs is measured against (bench/, `ldlpgs bench`), behind one interface and
// chosen by name:
//
//   cholmod             CHOLMOD simplicial LDL^T in the given order, not postordered
//   cholmod-supernodal  CHOLMOD supernodal LL^T in the given order, postordered
//   eigen-simplicial    Eigen::SimplicialLDLT in the given order
//   eigen-dense         Eigen::LDLT on the dense matrix (its own pivoting: the order is unused)
//
// The sparse ones factor P A P^T for the caller's scalar pivot order, so that they are compared
// with ldlpgs at the same fill and flops; only cholmod-supernodal may relabel the order, by
// CHOLMOD's postordering of the elimination tree, which changes neither fill nor flops.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// A direct solver prepared for one matrix and one scalar permutation: the constructor does all
// symbolic work (analysis, permutation of the matrix), so that factor() is the numeric
// factorization alone and solve() one right-hand side in place (original row order). The solver
// keeps its own copy of the matrix: factor() factors the values a had when the solver was made.
class DirectSolver {
 public:
  virtual ~DirectSolver() = default;
  virtual std::string_view name() const = 0;
  // False when the solver reports a numerical failure (CHOLMOD_NOT_POSDEF, Eigen's
  // NumericalIssue): a zero pivot, or for the LL^T a pivot that is not positive. May be called
  // again (a benchmark factors many times); each call starts afresh.
  virtual bool factor() = 0;
  // Why the last factor() returned false, in one line naming the pivot where the solver says
  // (empty after a success): what `ldlpgs bench` prints for a solver that failed.
  virtual std::string failure() const = 0;
  // b (size n) is overwritten with x, A x = b. Only after a factor() that returned true. The
  // CHOLMOD solvers allocate nothing from their second solve on.
  virtual void solve(std::span<double> b) = 0;
};

// perm[k] = row eliminated k-th (size a.n). Throws InputError for an unknown name.
std::unique_ptr<DirectSolver> make_direct_solver(std::string_view name, const SymmetricCsc& a,
                                                 std::span<const int> perm);
// All names, in the order reports list them.
std::span<const std::string_view> direct_solver_names();

// The BLAS that CHOLMOD's supernodal factorization calls in this process (the only solver here
// that calls BLAS): the file that defines dgemm_ in the global scope, which is where CHOLMOD's
// reference binds, symlinks followed (Debian's alternatives choose libblas.so.3 at load time, so
// the link's name says nothing), then, for OpenBLAS, its openblas_get_config(). E.g.
//   /usr/lib/x86_64-linux-gnu/blas/libblas.so.3.11.0                     (reference BLAS)
//   /usr/lib/x86_64-linux-gnu/openblas-serial/libblas.so.3 (OpenBLAS 0.3.21 ...)
// A threaded OpenBLAS is pinned to one thread by the first call, and the text says so; it ends
// with OpenMP's thread limit where an OpenMP runtime is loaded ("; OpenMP thread limit 1", see
// limit_openmp_to_one_thread). Computed once; "dgemm_ not found" when no BLAS is loaded.
std::string blas_in_use();

// OpenBLAS's kernels for this process (openblas_get_corename(): "Haswell", "SkylakeX", ...; ""
// for another BLAS), and a one-line warning when they are older than the CPU (Prescott's SSE3 on
// a CPU with AVX-512, as OpenBLAS 0.3.21 does on CPUs it does not know), "" otherwise.
// OPENBLAS_CORETYPE pins them (papers/factor.md, "Which BLAS, and which of its kernels").
std::string blas_core();
std::string blas_core_warning();

// For the programs that time CHOLMOD (ldlpgs bench, factor_bench), first thing in main: where
// libgomp is loaded with a thread limit above 1 and OMP_THREAD_LIMIT is not set, re-executes the
// program (/proc/self/exe, the same argv) with OMP_THREAD_LIMIT=1, so that every solver runs on
// one core. CHOLMOD 3.0.14's supernodal factorization opens its parallel regions with
// num_threads(CHOLMOD_OMP_NUM_THREADS), 4 in Debian's cholmod_core.h, which overrides
// omp_set_num_threads and OMP_NUM_THREADS (measured); the thread limit, which libgomp reads when
// it is loaded, bounds it (omp_set_max_active_levels(0) might too, in process: not tried). With
// its 4 threads on this 2-core machine CHOLMOD supernodal took 9.5 ms on bcsstk13, 4.3 ms with
// the limit (papers/factor.md, "Speed"). A limit set by the user is kept, and setting
// OMP_THREAD_LIMIT=1 oneself avoids the restart (for valgrind or gdb, which a restart escapes).
void limit_openmp_to_one_thread(char** argv);

}  // namespace ldlpgs
