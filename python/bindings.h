#pragma once
// The module's areas, each defined in its own file and registered by module.cpp.
#include <pybind11/pybind11.h>

namespace ldlpgs::python {

void bind_factor(pybind11::module_& m);   // factor.cpp: order, block_sizes, cholmod_counts, analyze, Factor, verify
void bind_physics(pybind11::module_& m);  // physics.cpp: Simulation, sweep_run

}  // namespace ldlpgs::python
