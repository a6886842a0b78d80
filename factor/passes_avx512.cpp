// The passes with 8-lane kernels, compiled with -mavx512f (factor/CMakeLists.txt); Numeric calls
// them only on a CPU that has AVX-512F (kernel_isa()), and by default only where they measured
// faster than the AVX2 ones (numeric.cpp, best_passes). No FMA, as in passes_avx2.cpp.
#ifndef LDLPGS_KERNELS_AVX512
#error "passes_avx512.cpp is compiled with -mavx512f -DLDLPGS_KERNELS_AVX512 (factor/CMakeLists.txt)"
#endif
#include "passes.inc"

namespace ldlpgs::passes {
// The solve keeps the SSE2 passes, as the AVX2 table does (passes_avx2.cpp).
constinit const Passes kAvx512{"avx512", &eliminate, &forward_sse2, &backward_sse2, &scatter, &diagonal, &floors, &inertia};
}  // namespace ldlpgs::passes
