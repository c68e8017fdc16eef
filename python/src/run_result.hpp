// What a finished (or stopped) Simulation holds, as Python objects: sample
// times and traces as numpy arrays, biomarkers as one array per column of
// biomarkers.csv, summary.json as a dict. Call with the GIL held.
#pragma once

#include <pybind11/pybind11.h>

#include "run/simulation.hpp"

namespace fibrodem::python {

// {"t_ms", "columns" (name -> array), "biomarkers" (column -> array),
//  "cell_types" (list of str, one per cell), "summary" (dict, unless
//  with_summary is false)}
pybind11::dict collect_result(const Simulation& simulation, bool with_summary);

}  // namespace fibrodem::python
