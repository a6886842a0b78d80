// The passes with the x86-64 baseline's kernels (SSE2, 2 lanes): every CPU runs these.
#include "passes.inc"

namespace ldlpgs::passes {
void forward_sse2(const Factor& f, double* w) { forward(f, w); }
void backward_sse2(const Factor& f, double* w) { backward(f, w); }
constinit const Passes kSse2{"sse2", &eliminate, &forward, &backward, &scatter, &diagonal, &floors, &inertia};
}  // namespace ldlpgs::passes
