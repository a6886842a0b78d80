// The passes with 4-lane kernels, compiled with -mavx2 (factor/CMakeLists.txt); Numeric calls
// them only on a CPU that has AVX2 (kernel_isa()). No FMA: -mavx2 does not enable it, and
// -ffp-contract=off keeps any later -mfma from fusing (kernels.h).
#ifndef LDLPGS_KERNELS_AVX2
#error "passes_avx2.cpp is compiled with -mavx2 -DLDLPGS_KERNELS_AVX2 (factor/CMakeLists.txt)"
#endif
#include "passes.inc"

namespace ldlpgs::passes {
// The solve keeps the SSE2 passes: built here with 4 lanes it was slower on 26 of factor_bench's 38
// problems, by 1-12 % (by less than the run-to-run noise on most; pairs built here did no
// better), where the factorization was 8-31 % faster on the mechanisms (papers/factor.md "Four
// lanes with AVX2"). constinit: this table is data, not code run at start-up (passes.h).
constinit const Passes kAvx2{"avx2", &eliminate, &forward_sse2, &backward_sse2, &scatter, &diagonal, &floors, &inertia};
}  // namespace ldlpgs::passes
