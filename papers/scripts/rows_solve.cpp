// The rows' solve X' <- L^-1 X' of a supernode (papers/factor.md, "The rows' solve by blocks"):
// OpenBLAS's left-side dtrsm against forward substitution by diagonal blocks of nb columns, each
// block's triangle inverted explicitly and applied with dtrmm, the rows below updated with dgemm
// (what dense::solve_rows does). Prints the best of 40 times in us for a d x d Cholesky factor
// and h right-hand sides (and of the whole triangle's inverse by dtrtri, then dtrmm), then the
// residual ||X' - L Z|| / (||L|| ||Z||) of the first two on three ill-conditioned triangles.
// Build and run:
//   g++ -O2 -o /tmp/rows_solve papers/scripts/rows_solve.cpp -llapack -lblas && taskset -c 1 /tmp/rows_solve
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "lower_inverse.h"

extern "C" {
void dtrsm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
void dtrmm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
void dtrtri_(const char*, const char*, const int*, double*, const int*, int*);
void dgemm_(const char*, const char*, const int*, const int*, const int*, const double*, const double*, const int*,
            const double*, const int*, const double*, double*, const int*);
}

using Vec = std::vector<double>;

void left_trsm(const Vec& l, int d, Vec& x, int h) {
  const double one = 1;
  dtrsm_("L", "L", "N", "N", &d, &h, &one, l.data(), &d, x.data(), &d);
}

void by_blocks(const Vec& l, int d, Vec& x, int h, int nb) {
  const double one = 1, minus_one = -1;
  Vec inv(nb * nb);
  for (int k = 0; k < d; k += nb) {
    const int b = std::min(nb, d - k), below = d - k - b;
    invert_lower(l.data() + k * d + k, d, b, inv.data());
    dtrmm_("L", "L", "N", "N", &b, &h, &one, inv.data(), &b, x.data() + k, &d);
    if (below > 0)
      dgemm_("N", "N", &below, &h, &b, &minus_one, l.data() + k * d + k + b, &d, x.data() + k, &d, &one,
             x.data() + k + b, &d);
  }
}

// The whole triangle's inverse (LAPACK's dtrtri), then one dtrmm.
void whole_inverse(const Vec& l, int d, Vec& x, int h, Vec& inv) {
  const double one = 1;
  int info = 0;
  inv = l;
  dtrtri_("L", "N", &d, inv.data(), &d, &info);
  dtrmm_("L", "L", "N", "N", &d, &h, &one, inv.data(), &d, x.data(), &d);
}

template <class F>
double best_us(F f) {
  double best = 1e30;
  for (int r = 0; r < 40; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

double residual(const Vec& l, int d, const Vec& x, const Vec& z, int h) {
  long double r2 = 0, z2 = 0, l2 = 0;
  for (int c = 0; c < h; ++c)
    for (int i = 0; i < d; ++i) {
      long double s = 0;
      for (int k = 0; k <= i; ++k) s += static_cast<long double>(l[k * d + i]) * z[c * d + k];
      r2 += (x[c * d + i] - s) * (x[c * d + i] - s);
      z2 += static_cast<long double>(z[c * d + i]) * z[c * d + i];
    }
  for (double v : l) l2 += static_cast<long double>(v) * v;
  return static_cast<double>(std::sqrt(r2) / (std::sqrt(l2) * std::sqrt(z2)));
}

int main() {
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::printf("   d    h  dtrsm-left  blocks-8  blocks-16  blocks-32  dtrtri+dtrmm\n");
  for (int d : {16, 32, 64, 128})
    for (int h : {32, 128, 512}) {
      Vec l(d * d, 0), x(h * d), y;
      for (int j = 0; j < d; ++j)
        for (int i = j; i < d; ++i) l[j * d + i] = i == j ? 2 + std::abs(u(gen)) * std::sqrt(d) : u(gen);
      for (double& v : x) v = u(gen);
      std::printf("%4d %4d  %10.2f", d, h, best_us([&] { y = x; left_trsm(l, d, y, h); }));
      for (int nb : {8, 16, 32}) std::printf("  %9.2f", best_us([&] { y = x; by_blocks(l, d, y, h, nb); }));
      Vec inv;
      std::printf("  %12.2f\n", best_us([&] { y = x; whole_inverse(l, d, y, h, inv); }));
    }
  // Ill-conditioned triangles, d = 64, h = 100: unit diagonal with -1 below (cond ~ 2^64), random
  // entries below a unit diagonal, and a diagonal and entries spread over 1e-4..1e4.
  const char* names[] = {"unit, -1 below", "unit, random below", "graded 1e-4..1e4"};
  const int d = 64, h = 100;
  for (int kind = 0; kind < 3; ++kind) {
    Vec l(d * d, 0), x(h * d);
    for (int j = 0; j < d; ++j)
      for (int i = j; i < d; ++i)
        l[j * d + i] = i == j ? (kind == 2 ? std::pow(10.0, 4 * u(gen)) : 1.0)
                              : (kind == 0 ? -1.0 : kind == 1 ? u(gen) : u(gen) * std::pow(10.0, 4 * u(gen)));
    for (double& v : x) v = u(gen);
    Vec z = x;
    left_trsm(l, d, z, h);
    std::printf("%-20s dtrsm-left %.1e", names[kind], residual(l, d, x, z, h));
    for (int nb : {8, 16, 32}) {
      z = x;
      by_blocks(l, d, z, h, nb);
      std::printf("  blocks-%d %.1e", nb, residual(l, d, x, z, h));
    }
    std::printf("\n");
  }
}
