// The smallest consumer (README, "Using ldlpgs from your own project"): a 2 x 2 system.
#include <cstdio>

#include <ldlpgs/factor/block_ldlt.h>

int main() {
  Eigen::SparseMatrix<double> a(2, 2);  // [4 1; 1 3], lower triangle
  a.insert(0, 0) = 4;
  a.insert(1, 0) = 1;
  a.insert(1, 1) = 3;
  ldlpgs::BlockLDLT solver(a);
  const Eigen::VectorXd x = solver.solve(Eigen::Vector2d(1, 2));
  std::printf("x = (%.6f, %.6f)\n", x[0], x[1]);  // (1/11, 7/11)
  return solver.info() == Eigen::Success ? 0 : 1;
}
