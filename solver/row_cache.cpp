// W J^T row by row and diag(H) = diag(J W J^T), once per step, for the row sweeps.
#include "solver/row_cache.h"

namespace ldlpgs {

void RowCache::update(const System& system) {
  wjt.assign(12 * static_cast<size_t>(system.num_rows), 0.0);
  diag.assign(system.num_rows, 0.0);
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r) {
      const int i = b.position + r;
      for (int side = 0; side < 2; ++side) {
        const int col = side == 0 ? b.column_a : b.column_b;
        if (col < 0) continue;
        const double* j = (side == 0 ? system.cell_a(k) : system.cell_b(k)) + 6 * r;
        const double* w = system.inverse_mass.data() + 36 * col;
        double* out = wjt.data() + 12 * static_cast<size_t>(i) + 6 * side;
        for (int x = 0; x < 6; ++x) {
          double s = 0;
          for (int c = 0; c < 6; ++c) s += w[6 * x + c] * j[c];
          out[x] = s;
          diag[i] += j[x] * s;
        }
      }
    }
  }
}

}  // namespace ldlpgs
