// One dense front on OpenBLAS (papers/factor.md, the unshattered star-60 in the targets at 061c918): LAPACK's
// dpotrf("L") of an n x n positive definite block, and right-looking panels of nb columns
// (dpotrf of the diagonal block, the rows below by dtrsm or by the diagonal block's explicit
// inverse and dtrmm, dsyrk for the rest). Best of 50, us and GFlop/s (n^3 / 3 flops).
//   g++ -O2 -o /tmp/dense_front papers/scripts/dense_front.cpp -llapack -lblas && taskset -c 1 /tmp/dense_front
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "lower_inverse.h"

extern "C" {
void dpotrf_(const char*, const int*, double*, const int*, int*);
void dtrsm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
void dtrmm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
void dsyrk_(const char*, const char*, const int*, const int*, const double*, const double*, const int*, const double*,
            double*, const int*);
}

void panels(double* a, int n, int nb, bool inverse, double* inv) {
  const double one = 1, minus_one = -1;
  int info = 0;
  for (int k = 0; k < n; k += nb) {
    const int b = std::min(nb, n - k), m = n - k - b;
    double* akk = a + static_cast<long>(k) * n + k;
    dpotrf_("L", &b, akk, &n, &info);
    if (m == 0) break;
    double* below = akk + b;
    if (inverse) {
      invert_lower(akk, n, b, inv);
      dtrmm_("R", "L", "T", "N", &m, &b, &one, inv, &b, below, &n);
    } else {
      dtrsm_("R", "L", "T", "N", &m, &b, &one, akk, &n, below, &n);
    }
    dsyrk_("L", "N", &m, &b, &minus_one, below, &n, &one, akk + static_cast<long>(b) * n + b, &n);
  }
}

int main() {
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {64, 128, 183, 256, 400}) {
    std::vector<double> g(n * n), spd(n * n), inv(64 * 64);
    for (double& v : g) v = u(gen);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double s = i == j ? n : 0;
        for (int k = 0; k < n; ++k) s += g[i * n + k] * g[j * n + k];
        spd[i * n + j] = s;
      }
    auto best_us = [&](auto f) {
      double best = 1e30;
      for (int r = 0; r < 50; ++r) {
        std::vector<double> a = spd;
        const auto t0 = std::chrono::steady_clock::now();
        f(a.data());
        best = std::min(best, std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
      }
      return best;
    };
    int info = 0;
    const double t = best_us([&](double* a) { dpotrf_("L", &n, a, &n, &info); });
    std::printf("n %3d  dpotrf %7.1f us %5.1f GFlop/s", n, t, n * static_cast<double>(n) * n / 3 / t / 1e3);
    for (int nb : {16, 32, 64})
      std::printf("  | panels of %d: dtrsm %7.1f, inverse %7.1f", nb,
                  best_us([&](double* a) { panels(a, n, nb, false, inv.data()); }),
                  best_us([&](double* a) { panels(a, n, nb, true, inv.data()); }));
    std::printf("\n");
  }
}
