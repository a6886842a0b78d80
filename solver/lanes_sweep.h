#pragma once
// Internal to solver/: the groups' sweep, compiled twice (lanes_sweep.inc): for the x86-64
// baseline (a vector of four doubles as two SSE2 halves) and with -mavx2 (one register), chosen
// by the CPU. Both give the same values bit for bit (no FMA, as factor/'s passes). The kernels see
// plain records and pointers only, so the AVX2 object instantiates nothing the linker could merge
// with the baseline's copies and run on a CPU without AVX2.
#include "ldlpgs/solver/lanes.h"

namespace ldlpgs::lanes {

struct SweepData {
  const ContactLanes::Group* groups;
  int num_groups;
  const ContactLanes::Slot* slots;
  const RowBlock* blocks;
  const double* compliance;  // (the rows swept one by one: the rest is in the slots)
  double* lambda;
  double* dv;
};

void sweep_groups_sse2(const SweepData& data);
void sweep_groups_avx2(const SweepData& data);

}  // namespace ldlpgs::lanes
