// W J^T row by row and diag(H) = diag(J W J^T), once per step, for the row sweeps.
#include "ldlpgs/solver/row_cache.h"

#include <algorithm>

namespace ldlpgs {

void RowCache::update(const System& system) {
  wjt.resize(12 * static_cast<size_t>(system.num_rows));
  diag.resize(system.num_rows);
  // A velocity block whose W has zero coupling blocks (W_12 = W_21 = 0: a rigid body about its
  // centre of mass, W = blockdiag(I/m, R I^-1 R^T)) takes two 3x3 products, half the 6x6 one;
  // checked per block every step, so a general W stays exact. (The 6x6 product was a fifth of a
  // 100-link chain's whole step: callgrind, ldlpgs peers heavy-chain-100-1000.)
  separable.resize(system.num_columns);
  for (int c = 0; c < system.num_columns; ++c) {
    const double* w = system.inverse_mass.data() + 36 * c;
    bool zero = true;
    for (int x = 0; x < 3; ++x)
      for (int y = 3; y < 6; ++y) zero = zero && w[6 * x + y] == 0 && w[6 * y + x] == 0;
    separable[c] = zero;
  }
  for (int k = 0; k < static_cast<int>(system.blocks.size()); ++k) {
    const RowBlock& b = system.blocks[k];
    for (int r = 0; r < b.size; ++r) {
      const int i = b.position + r;
      double d = 0;
      for (int side = 0; side < 2; ++side) {
        const int col = side == 0 ? b.column_a : b.column_b;
        double* out = wjt.data() + 12 * static_cast<size_t>(i) + 6 * side;
        if (col < 0) {
          std::fill(out, out + 6, 0.0);
          continue;
        }
        const double* j = (side == 0 ? system.cell_a(k) : system.cell_b(k)) + 6 * r;
        const double* w = system.inverse_mass.data() + 36 * col;
        if (separable[col]) {
          for (int half = 0; half < 6; half += 3)
            for (int x = half; x < half + 3; ++x)
              out[x] = w[6 * x + half] * j[half] + w[6 * x + half + 1] * j[half + 1] + w[6 * x + half + 2] * j[half + 2];
        } else {
          for (int x = 0; x < 6; ++x) {
            double s = 0;
            for (int c = 0; c < 6; ++c) s += w[6 * x + c] * j[c];
            out[x] = s;
          }
        }
        for (int x = 0; x < 6; ++x) d += j[x] * out[x];
      }
      diag[i] = d;
    }
  }
  lanes.update(system, *this);
}

}  // namespace ldlpgs
