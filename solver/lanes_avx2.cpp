// The groups' sweep compiled with -mavx2 (solver/CMakeLists.txt), called only on a CPU that has
// AVX2 (lanes_sweep.h).
#ifndef LDLPGS_LANES_AVX2
#error "lanes_avx2.cpp is compiled with -mavx2 -DLDLPGS_LANES_AVX2 (solver/CMakeLists.txt)"
#endif
#define LDLPGS_LANES_NAMESPACE avx2
#include "lanes_sweep.inc"

namespace ldlpgs::lanes {
void sweep_groups_avx2(const SweepData& data) { avx2::sweep_groups(data); }
}  // namespace ldlpgs::lanes
