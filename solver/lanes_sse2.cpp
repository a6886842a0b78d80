// The groups' sweep for the x86-64 baseline (lanes_sweep.h).
#define LDLPGS_LANES_NAMESPACE sse2
#include "lanes_sweep.inc"

namespace ldlpgs::lanes {
void sweep_groups_sse2(const SweepData& data) { sse2::sweep_groups(data); }
}  // namespace ldlpgs::lanes
