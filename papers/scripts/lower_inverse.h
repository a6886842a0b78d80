#pragma once
// The stand-alone programs' copy of dense::solve_rows's triangle inverse (factor/dense.cpp).
#include <algorithm>

// The inverse of the b x b lower triangle of l (column-major, leading dimension ld) into inv.
inline void invert_lower(const double* l, int ld, int b, double* inv) {
  for (int j = 0; j < b; ++j) {
    double* x = inv + j * b;
    std::fill_n(x, b, 0.0);
    x[j] = 1;
    for (int k = j; k < b; ++k) {
      x[k] /= l[k * ld + k];
      for (int i = k + 1; i < b; ++i) x[i] -= l[k * ld + i] * x[k];
    }
  }
}
