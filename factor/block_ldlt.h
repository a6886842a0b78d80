#pragma once
// BlockLDLT: the block LDL^T behind Eigen's sparse-solver conventions (SimplicialLDLT,
// CholmodSupernodalLLT): analyzePattern, factorize, compute, solve, info. For users who hold an
// Eigen::SparseMatrix<double>: its lower triangle is read (Eigen's default UpLo = Lower, CHOLMOD's
// stype = -1), entries above the diagonal are ignored. Underneath are the two phases
// (factor.h): analyzePattern partitions the rows into blocks, orders them and builds the
// Symbolic; factorize loads values into the Numeric.
//
//   ldlpgs::BlockLDLT solver({.ordering = "meca-w"});
//   solver.compute(A);
//   if (solver.info() != Eigen::Success) ...;  // solver.factor_info().message() says why
//   Eigen::VectorXd x = solver.solve(b);
//
// Errors: a call the object cannot honour (factorize of a matrix with another size or pattern
// than analyzePattern saw, solve before a usable factorization or with b of another row count, a
// non-square matrix) throws ArgumentError, in every build; an unknown ordering name or a
// partition file that cannot be read throws InputError; numerical failure (zero pivot, NaN or
// infinite entry) is info() == Eigen::NumericalIssue with factor_info() naming the block.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ldlpgs/factor/numeric.h"
#include "ldlpgs/factor/symbolic.h"
#include "ldlpgs/ordering/ordering.h"

namespace ldlpgs {

struct BlockLDLTOptions {
  std::string blocks = "auto";    // "auto" (identical consecutive rows), N (uniform), or a file of block sizes
  std::vector<int> block_sizes{}; // the partition itself, in row order (if given, `blocks` is not read)
  int max_block = 6;              // the largest block "auto" forms
  std::string ordering = "best";  // a name of orderings() (ordering/ordering.h)
  FactorOptions factor{};         // regularization eps diag(H), zero-pivot threshold
};

// The named ordering of an Eigen matrix's lower triangle, its rows grouped into blocks as
// BlockLDLTOptions::blocks says.
Ordering compute_ordering(std::string_view name, const Eigen::SparseMatrix<double>& a,
                          const std::string& blocks = "auto", int max_block = 6);
// ... or into the given block sizes (row order; they must cover the rows: ArgumentError).
Ordering compute_ordering(std::string_view name, const Eigen::SparseMatrix<double>& a,
                          const std::vector<int>& block_sizes);

class BlockLDLT {
 public:
  using MatrixType = Eigen::SparseMatrix<double>;

  BlockLDLT() = default;
  explicit BlockLDLT(BlockLDLTOptions options) : options_(std::move(options)) {}
  explicit BlockLDLT(const MatrixType& a, BlockLDLTOptions options = {}) : options_(std::move(options)) { compute(a); }

  BlockLDLT& analyzePattern(const MatrixType& a);
  BlockLDLT& factorize(const MatrixType& a);
  BlockLDLT& compute(const MatrixType& a) { return analyzePattern(a).factorize(a); }

  // x = A^-1 b for one or many right-hand sides (b's columns). Not thread-safe: the solve uses
  // the factor's work vector.
  template <typename Rhs>
  Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime> solve(const Eigen::MatrixBase<Rhs>& b) const {
    Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime> x = b;
    solve_in_place(x.data(), x.rows(), x.cols());
    return x;
  }

  // Success after a usable factorization (positive definite or indefinite: L D L^T exists),
  // NumericalIssue after a zero pivot or a non-finite value, InvalidInput before any.
  Eigen::ComputationInfo info() const;
  const FactorInfo& factor_info() const;  // status, failing block, inertia, pivot ratio
  Eigen::Index rows() const { return symbolic_ ? symbolic_->num_rows() : 0; }
  Eigen::Index cols() const { return rows(); }

  // P (A + eps diag(A)) P^T = L D L^T, as Eigen's SimplicialLDLT names them: L unit lower
  // triangular (every block dense), D its diagonal, P the fill-reducing permutation.
  MatrixType matrixL() const;
  Eigen::VectorXd vectorD() const;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutationP() const;

  const BlockLDLTOptions& options() const { return options_; }
  const Ordering& ordering() const;
  const Symbolic& symbolic() const;
  const Numeric& numeric() const;

 private:
  void solve_in_place(double* x, Eigen::Index rows, Eigen::Index cols) const;
  BlockLDLTOptions options_;
  Ordering ordering_;
  std::unique_ptr<Symbolic> symbolic_;  // on the heap: numeric_ points to it, and this object may move
  std::unique_ptr<Numeric> numeric_;
};

}  // namespace ldlpgs
