#pragma once
// The module's areas, each defined in its own file and registered by module.cpp.
#include <pybind11/pybind11.h>

namespace ldlpgs::python {

void bind_factor(pybind11::module_& m);   // factor.cpp: order, block_sizes, cholmod_counts, analyze, Factor, verify
void bind_physics(pybind11::module_& m);  // physics.cpp: Simulation, sweep_run
void bind_view(pybind11::module_& m);     // view.cpp: Simulation.record, Simulation.view (after bind_physics)

}  // namespace ldlpgs::python

namespace ldlpgs::view {
class Recording;
}

namespace ldlpgs::python {

// The recording a Simulation keeps since its record() (view.cpp), or null.
view::Recording* recording_of(pybind11::handle simulation);

}  // namespace ldlpgs::python
