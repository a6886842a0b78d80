// BlockLDLT (block_ldlt.h): Eigen's sparse-solver interface over Symbolic and Numeric.
#include "ldlpgs/factor/block_ldlt.h"

#include <string>

#include "ldlpgs/sparse/block_pattern.h"
#include "ldlpgs/sparse/eigen_adapter.h"
#include "ldlpgs/sparse/error.h"
#include "ldlpgs/sparse/partition.h"

namespace ldlpgs {

namespace {

SymmetricCsc lower_triangle(const Eigen::SparseMatrix<double>& a, const char* what) {
  if (a.rows() != a.cols())
    throw ArgumentError(std::string(what) + ": the matrix is " + std::to_string(a.rows()) + " x " +
                        std::to_string(a.cols()) + ", not square");
  return from_eigen(a);
}

Ordering order(std::string_view name, const SymmetricCsc& a, const std::vector<int>& block_sizes,
               BlockPattern* pattern_out = nullptr) {
  const OrderingInfo& info = find_ordering(name);
  BlockPattern pattern = BlockPattern::from_scalar(a, block_sizes);
  Ordering o = compute_ordering(info, pattern, a);
  if (pattern_out) *pattern_out = std::move(pattern);
  return o;
}

}  // namespace

Ordering compute_ordering(std::string_view name, const Eigen::SparseMatrix<double>& a, const std::string& blocks,
                          int max_block) {
  const SymmetricCsc lower = lower_triangle(a, "compute_ordering");
  return order(name, lower, parse_partition(blocks, lower, max_block));
}

Ordering compute_ordering(std::string_view name, const Eigen::SparseMatrix<double>& a,
                          const std::vector<int>& block_sizes) {
  return order(name, lower_triangle(a, "compute_ordering"), block_sizes);
}

BlockLDLT& BlockLDLT::analyzePattern(const MatrixType& a) {
  const SymmetricCsc lower = lower_triangle(a, "analyzePattern");
  BlockPattern pattern;
  const std::vector<int> sizes = options_.block_sizes.empty() ? parse_partition(options_.blocks, lower, options_.max_block)
                                                              : options_.block_sizes;
  ordering_ = order(options_.ordering, lower, sizes, &pattern);
  numeric_.reset();  // it points into the symbolic object replaced here
  symbolic_ = std::make_unique<Symbolic>(Symbolic::analyze(lower, pattern, ordering_));
  numeric_ = std::make_unique<Numeric>(*symbolic_);
  return *this;
}

BlockLDLT& BlockLDLT::factorize(const MatrixType& a) {
  if (!numeric_) throw ArgumentError("factorize: call analyzePattern (or compute) first");
  numeric_->factorize(lower_triangle(a, "factorize"), options_.factor);
  return *this;
}

Eigen::ComputationInfo BlockLDLT::info() const {
  if (!numeric_) return Eigen::InvalidInput;
  // A factorization that never ran has the default (ok) status but its values are zero: solve
  // refuses it, and so does info().
  return numeric_->factored() ? (numeric_->info().usable() ? Eigen::Success : Eigen::NumericalIssue)
                              : Eigen::InvalidInput;
}

void BlockLDLT::solve_in_place(double* x, Eigen::Index rows, Eigen::Index cols) const {
  if (!numeric_) throw ArgumentError("solve: nothing is factored yet");
  if (rows != symbolic_->num_rows())
    throw ArgumentError("solve: a right-hand side of " + std::to_string(rows) + " rows for a matrix of " +
                        std::to_string(symbolic_->num_rows()));
  numeric_->solve(std::span<double>(x, static_cast<size_t>(rows * cols)), static_cast<int>(cols));
}

const FactorInfo& BlockLDLT::factor_info() const { return numeric().info(); }

const Ordering& BlockLDLT::ordering() const {
  if (!symbolic_) throw ArgumentError("ordering: call analyzePattern (or compute) first");
  return ordering_;
}
const Symbolic& BlockLDLT::symbolic() const {
  if (!symbolic_) throw ArgumentError("symbolic: call analyzePattern (or compute) first");
  return *symbolic_;
}
const Numeric& BlockLDLT::numeric() const {
  if (!numeric_) throw ArgumentError("numeric: call analyzePattern (or compute) first");
  return *numeric_;
}

BlockLDLT::MatrixType BlockLDLT::matrixL() const {
  MatrixType l = to_eigen(numeric().scalar_ldl(), Triangle::lower);  // D on the diagonal
  for (Eigen::Index j = 0; j < l.outerSize(); ++j) l.coeffRef(j, j) = 1.0;
  return l;
}

Eigen::VectorXd BlockLDLT::vectorD() const {
  const SymmetricCsc ldl = numeric().scalar_ldl();
  Eigen::VectorXd d(ldl.n);
  for (int j = 0; j < ldl.n; ++j) d[j] = ldl.values[ldl.col_ptr[j]];  // the first entry of column j is its diagonal
  return d;
}

Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> BlockLDLT::permutationP() const {
  // (P A P^T)_ij = A_{perm[i], perm[j]}: P has its one of row i in column perm[i], and Eigen's
  // indices() name, for each column, the row of its one: indices()[perm[i]] = i.
  const std::span<const int> perm = symbolic().perm();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p(static_cast<int>(perm.size()));
  for (size_t i = 0; i < perm.size(); ++i) p.indices()[perm[i]] = static_cast<int>(i);
  return p;
}

}  // namespace ldlpgs
