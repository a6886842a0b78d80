#include "peers/competitors.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdlib>
#include <stdexcept>
#include <string_view>
#include <string>
#include <vector>

#include "ldlpgs/sparse/cholmod_adapter.h"
#include "ldlpgs/sparse/eigen_adapter.h"
#include "ldlpgs/sparse/error.h"

namespace ldlpgs {

namespace {

constexpr std::array<std::string_view, 4> kNames = {"cholmod", "cholmod-supernodal",
                                                    "eigen-simplicial", "eigen-dense"};

// CHOLMOD, simplicial LDL^T or supernodal LL^T, in the given order.
//
// The work CHOLMOD would otherwise repeat in every cholmod_factorize is done once here: with a
// fill-reducing permutation stored in the factor, cholmod_factorize first builds the permuted
// matrix (one or two cholmod_ptranspose, allocated and freed at each call). Instead the
// constructor permutes A once, C = Q A Q^T, and analyzes C in its natural order, which is the
// same analysis (same elimination tree, fill and supernodes: only the labels changed). C is kept
// in the triangle that cholmod_factorize reads as it is for the natural ordering
// (cholmod_factorize.c): the upper one (stype +1) for the row-by-row simplicial factorization,
// the lower one (stype -1) for the supernodal one.
//
// Q is the caller's order for the simplicial LDL^T. For the supernodal LL^T it is that order
// followed by CHOLMOD's weighted postorder of the elimination tree (L->Perm of an analysis with
// CHOLMOD_GIVEN and postorder on): CHOLMOD finds its supernodes as runs of consecutive columns
// each the parent of the one before, and merges (relaxed amalgamation) a supernode only with the
// one that follows it; postordering makes every subtree a run of consecutive columns, so that
// supernodes are found and merged. It relabels within the elimination tree: fill and flops are
// those of the given order.
class CholmodSolver final : public DirectSolver {
 public:
  CholmodSolver(const SymmetricCsc& a, std::span<const int> perm, bool supernodal)
      : supernodal_(supernodal), n_(a.n), q_(perm.begin(), perm.end()), bq_(a.n) {
    cholmod_common* c = cm_.common();
    // Silent: a refused pivot is factor()'s return value, and CHOLMOD's other failures throw.
    // (At print = 1, "errors only", CHOLMOD 3 still prints the not-positive-definite warning,
    // labelled as an error.)
    c->print = 0;
    c->nmethods = 1;
    c->supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c->final_asis = true;  // keep the factor as computed: LDL^T simplicial, LL^T supernodal
    c->final_ll = false;   // the simplicial factorization computes LL^T if this is set
    cholmod_sparse view = cholmod_view(a);
    if (supernodal) {
      c->method[0].ordering = CHOLMOD_GIVEN;
      c->postorder = true;
      cholmod_factor* given = cholmod_analyze_p(&view, q_.data(), nullptr, 0, c);
      check(given != nullptr, "cholmod_analyze_p");
      const int* postordered = static_cast<const int*>(given->Perm);
      q_.assign(postordered, postordered + n_);
      cholmod_free_factor(&given, c);
    }
    // cholmod_ptranspose of the lower triangle gives A(q,q)^T = A(q,q) as its upper triangle.
    held_.c = cholmod_ptranspose(&view, 1, q_.data(), nullptr, 0, c);
    check(held_.c != nullptr, "cholmod_ptranspose");
    if (supernodal) {
      cholmod_sparse* lower = cholmod_transpose(held_.c, 1, c);
      check(lower != nullptr, "cholmod_transpose");
      cholmod_free_sparse(&held_.c, c);
      held_.c = lower;
    }
    c->method[0].ordering = CHOLMOD_NATURAL;
    c->postorder = false;  // C is in its final order; CHOLMOD postorders even the natural one
    held_.l = cholmod_analyze(held_.c, c);
    check(held_.l != nullptr, "cholmod_analyze");
    b_ = cholmod_view(std::span<double>(bq_));
  }

  std::string_view name() const override { return supernodal_ ? kNames[1] : kNames[0]; }

  bool factor() override {
    cholmod_common* c = cm_.common();
    cholmod_factorize(held_.c, held_.l, c);
    // A pivot CHOLMOD refuses is a warning (CHOLMOD_NOT_POSDEF > 0); below CHOLMOD_OK is out
    // of memory or misuse, not a numerical failure.
    check(c->status >= CHOLMOD_OK, "cholmod_factorize");
    status_ = c->status;
    factored_ = c->status == CHOLMOD_OK && static_cast<int>(held_.l->minor) == n_;
    return factored_;
  }

  // L->minor is the column of C = A(q,q) where the factorization stopped: row q[minor] of A (q
  // postordered for the supernodal one). A failure without a minor column is its status alone.
  std::string failure() const override {
    if (factored_) return "";
    const int k = static_cast<int>(held_.l->minor);
    const std::string status = "CHOLMOD status " + std::to_string(status_);
    if (k >= n_) return status;
    return std::string(supernodal_ ? "not positive definite" : "zero pivot") + " (" + status + ") at row " +
           std::to_string(q_[k]) + ", column " + std::to_string(k) + " of the order CHOLMOD factors in";
  }

  void solve(std::span<double> b) override {
    assert(factored_ && static_cast<int>(b.size()) == n_);
    for (int k = 0; k < n_; ++k) bq_[k] = b[q_[k]];
    // cholmod_solve2 keeps X and its workspace Y, E between calls (allocated by the first) where
    // cholmod_solve would allocate them each time. L's own permutation is the identity.
    //
    // The simplicial solve asks cholmod_ensure_dense for Y of shape 4 x n (leading dimension 4:
    // up to four right-hand sides at a time, transposed), then reshapes Y's header to 1 x n for
    // our one column (ptrans in cholmod_solve.c); the next call finds the wrong shape and frees
    // and reallocates Y. Giving the header back the shape it was allocated with (its memory
    // holds 4 n entries) keeps it. Should CHOLMOD change that shape, it reallocates as before
    // (tests/peers/competitors_test.cpp counts the allocations).
    if (!supernodal_ && held_.y != nullptr && held_.y->nzmax >= 4 * static_cast<size_t>(n_)) {
      held_.y->nrow = held_.y->d = 4;
      held_.y->ncol = static_cast<size_t>(n_);
    }
    const int ok = cholmod_solve2(CHOLMOD_A, held_.l, &b_, nullptr, &held_.x, nullptr, &held_.y,
                                  &held_.e, cm_.common());
    check(ok != 0, "cholmod_solve2");
    const double* x = static_cast<const double*>(held_.x->x);
    for (int k = 0; k < n_; ++k) b[q_[k]] = x[k];
  }

 private:
  // What CHOLMOD allocated for this solver, freed through cm (declared after it, so destroyed
  // first, also when the constructor throws).
  struct Held {
    Cholmod& cm;
    cholmod_sparse* c = nullptr;  // one triangle of A(q,q), see above
    cholmod_factor* l = nullptr;
    cholmod_dense* x = nullptr;  // solution and workspace of cholmod_solve2, kept between solves
    cholmod_dense* y = nullptr;
    cholmod_dense* e = nullptr;
    ~Held() {
      cholmod_free_factor(&l, cm.common());
      cholmod_free_sparse(&c, cm.common());
      cholmod_free_dense(&x, cm.common());
      cholmod_free_dense(&y, cm.common());
      cholmod_free_dense(&e, cm.common());
    }
  };

  // CHOLMOD failing for other reasons than the matrix's values: out of memory, or misuse.
  void check(bool ok, const char* what) {
    if (!ok) throw std::runtime_error(std::string(what) + " failed with status " + std::to_string(cm_.common()->status));
  }

  Cholmod cm_;
  Held held_{cm_};
  bool supernodal_;
  int n_;
  std::vector<int> q_;      // the order CHOLMOD factors in: C = A(q,q) (size n)
  std::vector<double> bq_;  // permuted right-hand side, viewed by b_ (size n)
  cholmod_dense b_{};
  int status_ = CHOLMOD_OK;  // Common->status after the last cholmod_factorize
  bool factored_ = false;
};

// Eigen's up-looking simplicial LDL^T in the given order. The matrix is permuted once here and
// stored as the upper triangle of P A P^T: with the natural ordering and Upper, factorize() reads
// the matrix as it is, where Lower (or an ordering) would copy it into a permuted upper
// triangle at every call (SimplicialCholeskyBase::factorize).
class EigenSimplicialSolver final : public DirectSolver {
 public:
  EigenSimplicialSolver(const SymmetricCsc& a, std::span<const int> perm)
      : perm_(perm.begin(), perm.end()), bq_(a.n), xq_(a.n) {
    std::vector<int> inverse(a.n);  // inverse[row] = its position in P A P^T
    for (int k = 0; k < a.n; ++k) inverse[perm[k]] = k;
    std::vector<Eigen::Triplet<double>> upper;
    upper.reserve(a.nnz());
    for (int j = 0; j < a.n; ++j) {
      for (int p = a.col_ptr[j]; p < a.col_ptr[j + 1]; ++p) {
        const int r = inverse[a.row_idx[p]], s = inverse[j];
        upper.emplace_back(std::min(r, s), std::max(r, s), a.values[p]);
      }
    }
    upper_.resize(a.n, a.n);
    upper_.setFromTriplets(upper.begin(), upper.end());
    ldlt_.analyzePattern(upper_);
  }

  std::string_view name() const override { return kNames[2]; }

  bool factor() override {
    ldlt_.factorize(upper_);
    factored_ = ldlt_.info() == Eigen::Success;
    return factored_;
  }

  std::string failure() const override { return factored_ ? "" : "Eigen::NumericalIssue (a zero pivot)"; }

  void solve(std::span<double> b) override {
    const int n = static_cast<int>(perm_.size());
    assert(factored_ && static_cast<int>(b.size()) == n);
    for (int k = 0; k < n; ++k) bq_[k] = b[perm_[k]];
    xq_ = ldlt_.solve(bq_);
    for (int k = 0; k < n; ++k) b[perm_[k]] = xq_[k];
  }

 private:
  std::vector<int> perm_;                  // perm[k] = row eliminated k-th (size n)
  Eigen::SparseMatrix<double> upper_;      // upper triangle of P A P^T
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt_;
  Eigen::VectorXd bq_, xq_;                // permuted right-hand side and solution (size n)
  bool factored_ = false;
};

// Eigen's dense LDL^T with symmetric (diagonal) pivoting on the full matrix. It chooses its own
// pivots at factorization time, so the given order has nothing to say. Eigen reports failure only
// when a zero pivot is followed by a nonzero one (ldlt_inplace::unblocked); a singular matrix
// whose zero pivots all come last factors, and solve() uses the pseudo-inverse of D.
class EigenDenseSolver final : public DirectSolver {
 public:
  explicit EigenDenseSolver(const SymmetricCsc& a) : a_(to_eigen(a, Triangle::full)), ldlt_(a.n) {}

  std::string_view name() const override { return kNames[3]; }

  bool factor() override {
    ldlt_.compute(a_);
    factored_ = ldlt_.info() == Eigen::Success;
    return factored_;
  }

  std::string failure() const override { return factored_ ? "" : "Eigen::NumericalIssue (a zero pivot)"; }

  void solve(std::span<double> b) override {
    assert(factored_ && b.size() == static_cast<size_t>(a_.rows()));
    Eigen::Map<Eigen::VectorXd> x(b.data(), a_.rows());
    ldlt_.solveInPlace(x);
  }

 private:
  Eigen::MatrixXd a_;  // the full symmetric matrix (size n x n)
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  bool factored_ = false;
};

std::string known_names() {
  std::string s;
  for (std::string_view name : kNames) s += (s.empty() ? "" : ", ") + std::string(name);
  return s;
}

// A function of the process's global scope by name, null if no loaded library defines it.
template <class F>
F* global_function(const char* name) {
  return reinterpret_cast<F*>(dlsym(RTLD_DEFAULT, name));
}

// OpenMP's thread limit in this process, for blas_in_use()'s text ("" when no OpenMP runtime is
// loaded).
std::string openmp_limit() {
  const auto limit = global_function<int()>("omp_get_thread_limit");
  return limit == nullptr ? "" : "; OpenMP thread limit " + std::to_string(limit());
}

std::string find_blas() {
  void* dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
  Dl_info info{};
  if (dgemm == nullptr || dladdr(dgemm, &info) == 0 || info.dli_fname == nullptr) return "dgemm_ not found";
  std::string blas = info.dli_fname;
  if (char* real = realpath(info.dli_fname, nullptr)) {
    blas = real;
    std::free(real);
  }
  // OpenBLAS's own entry points (openblas_config.h); get_parallel: 0 sequential, 1 pthreads,
  // 2 OpenMP.
  const auto config = global_function<char*()>("openblas_get_config");
  if (config == nullptr) return blas;
  blas += std::string(" (") + config();
  const auto parallel = global_function<int()>("openblas_get_parallel");
  const auto threads = global_function<int()>("openblas_get_num_threads");
  const auto set_threads = global_function<void(int)>("openblas_set_num_threads");
  if (parallel != nullptr && parallel() != 0 && threads != nullptr && set_threads != nullptr) {
    blas += ", " + std::to_string(threads()) + " threads pinned to 1";
    set_threads(1);
  }
  return blas + ")";
}

}  // namespace

std::string blas_in_use() {
  static const std::string blas = find_blas() + openmp_limit();
  return blas;
}

std::string blas_core() {
  const auto corename = global_function<char*()>("openblas_get_corename");
  return corename == nullptr ? "" : corename();
}

namespace {
// The widest vectors an OpenBLAS core type's kernels use: 3 AVX-512, 2 AVX2, 1 AVX, 0 older
// (OpenBLAS's DYNAMIC_ARCH names, driver/others/dynamic.c); -1 for a name not listed here.
int core_vector_level(std::string_view core) {
  for (std::string_view name : {"SkylakeX", "Cooperlake", "SapphireRapids"})
    if (core == name) return 3;
  for (std::string_view name : {"Haswell", "Zen", "Excavator"})
    if (core == name) return 2;
  for (std::string_view name : {"Sandybridge", "Bulldozer", "Piledriver", "Steamroller"})
    if (core == name) return 1;
  for (std::string_view name : {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem", "Atom", "Athlon", "Opteron",
                                "Opteron(SSE3)", "Barcelona", "Bobcat", "Nano", "Katmai", "Coppermine", "Northwood", "Banias"})
    if (core == name) return 0;
  return -1;
}

int cpu_vector_level() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return 3;
  if (__builtin_cpu_supports("avx2")) return 2;
  if (__builtin_cpu_supports("avx")) return 1;
#endif
  return 0;
}
}  // namespace

std::string blas_core_warning() {
  const std::string core = blas_core();
  const int level = core_vector_level(core), cpu = cpu_vector_level();
  if (core.empty() || level < 0 || level >= cpu) return "";
  static constexpr const char* kLevel[] = {"SSE", "AVX", "AVX2", "AVX-512"};
  return "OpenBLAS runs its " + core + " kernels (" + kLevel[level] + ") on a CPU with " + kLevel[cpu] +
         ": CHOLMOD supernodal and our supernodes are slower than they could be; set OPENBLAS_CORETYPE (e.g. " +
         (cpu == 3 ? "SkylakeX" : cpu == 2 ? "Haswell" : "Sandybridge") + ") for every solver of a comparison";
}

void limit_openmp_to_one_thread(char** argv) {
  const auto limit = global_function<int()>("omp_get_thread_limit");
  if (limit == nullptr || limit() <= 1 || std::getenv("OMP_THREAD_LIMIT") != nullptr) return;
  if (setenv("OMP_THREAD_LIMIT", "1", 1) != 0) return;  // (the variable is what ends the restarts)
  execv("/proc/self/exe", argv);  // returns only on failure: then the limit stays, and is printed
}

std::span<const std::string_view> direct_solver_names() { return kNames; }

std::unique_ptr<DirectSolver> make_direct_solver(std::string_view name, const SymmetricCsc& a,
                                                 std::span<const int> perm) {
  assert(static_cast<int>(perm.size()) == a.n);
  if (name == kNames[0]) return std::make_unique<CholmodSolver>(a, perm, false);
  if (name == kNames[1]) return std::make_unique<CholmodSolver>(a, perm, true);
  if (name == kNames[2]) return std::make_unique<EigenSimplicialSolver>(a, perm);
  if (name == kNames[3]) return std::make_unique<EigenDenseSolver>(a);
  throw InputError("unknown direct solver '" + std::string(name) + "' (known: " + known_names() + ")");
}

}  // namespace ldlpgs
