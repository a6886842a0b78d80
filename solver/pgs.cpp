// pgs: projected Gauss-Seidel in the talk's impulse (Kaczmarz) form. H is never built: each row
// reads J_i dV and writes dV += W J_i^T dlambda, so a sweep costs O(rows), not O(nnz(H)).
#include "ldlpgs/solver/row_cache.h"

namespace ldlpgs {

void pgs_sweep(const System& system, const RowCache& cache, std::span<double> lambda, std::span<double> dv,
               bool inequality_only) {
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    if (inequality_only && b.equality) continue;
    for (int r = 0; r < b.size; ++r) pgs_row(system, cache, k, r, lambda, dv);
  }
}

}  // namespace ldlpgs
