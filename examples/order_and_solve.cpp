// Example 1: a Matrix Market matrix, every ordering's fill and flops, the best one factored and
// solved, and the backward error. Usage: order_and_solve [MATRIX.mtx]
#include <Eigen/SparseCore>
#include <cstdio>
#include <string>

#include <ldlpgs/factor/factor.h>
#include <ldlpgs/sparse/eigen_adapter.h>
#include <ldlpgs/sparse/error.h>
#include <ldlpgs/sparse/matrix_market.h>

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : EXAMPLE_MATRIX;
  try {
    // The lower triangle, as CHOLMOD and Eigen's SimplicialLDLT read a symmetric matrix.
    const Eigen::SparseMatrix<double> a = ldlpgs::to_eigen(ldlpgs::read_matrix_market(path), ldlpgs::Triangle::lower);
    std::printf("%s: n = %ld, nnz(lower) = %ld\n", path.c_str(), static_cast<long>(a.rows()),
                static_cast<long>(a.nonZeros()));

    // Analysis alone (no values) gives each ordering's nnz(L), fill blocks and flops.
    std::string best;
    double best_flops = 0;
    std::printf("%-14s %10s %12s %14s\n", "ordering", "nnz(L)", "fill blocks", "flops");
    for (const ldlpgs::OrderingInfo& info : ldlpgs::orderings()) {
      ldlpgs::BlockLDLT analysis({.ordering = std::string(info.name)});
      analysis.analyzePattern(a);
      const ldlpgs::Symbolic& s = analysis.symbolic();
      std::printf("%-14s %10lld %12lld %14.0f\n", std::string(info.name).c_str(), static_cast<long long>(s.nnz_l()),
                  static_cast<long long>(s.num_fill_edges()), s.flops());
      if (best.empty() || s.flops() < best_flops) best = info.name, best_flops = s.flops();
    }

    // The best ordering, factored and solved for b = A * ones.
    ldlpgs::BlockLDLT solver({.ordering = best});
    solver.compute(a);
    if (solver.info() != Eigen::Success) {
      std::fprintf(stderr, "order_and_solve: %s\n", solver.factor_info().message().c_str());
      return 1;
    }
    const Eigen::SparseMatrix<double> full = a.selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd b = full * Eigen::VectorXd::Ones(a.rows());
    const Eigen::VectorXd x = solver.solve(b);
    // Normwise backward error |b - A x| / (|A| |x| + |b|), infinity norms.
    double norm_a = 0;
    for (Eigen::Index i = 0; i < full.outerSize(); ++i) norm_a = std::max(norm_a, full.col(i).cwiseAbs().sum());
    const double error = (b - full * x).lpNorm<Eigen::Infinity>() /
                         (norm_a * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
    std::printf("best: %s, %.0f flops, inertia +%d -%d, backward error %.2e\n", best.c_str(), best_flops,
                solver.factor_info().inertia.positive, solver.factor_info().inertia.negative, error);
    return error < 1e-12 ? 0 : 1;
  } catch (const std::exception& e) {  // InputError: the file; ArgumentError: a misuse
    std::fprintf(stderr, "order_and_solve: %s\n", e.what());
    return 2;
  }
}
