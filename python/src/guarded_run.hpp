// Sets a scene up and runs it with the GIL released, a Ctrl-C recorded by the
// core (it stops at the end of a step, outputs written) and errors sorted as
// the command line sorts them. Shared by run() and simulate_cell().
#pragma once

#include <pybind11/pybind11.h>

#include <exception>
#include <memory>
#include <string>

#include "run/simulation.hpp"

namespace fibrodem::python {

struct RunOutcome {
  std::unique_ptr<Simulation> simulation;  // null if set-up failed (then `error` is rethrown)
  std::string status = "completed";        // or "interrupted", "failed"
  std::string message;                     // why it stopped or failed
  double set_up_s = 0;                     // wall time of building the Simulation [s]
  double run_s = 0;                        // wall time of Simulation::run() [s]
  double run_cpu_s = 0;                    // CPU time of this thread in it [s] (one thread for a cell)
};

// Called with the GIL held; releases it for the set-up and the run. A
// ManifestError or PluginError of the set-up, or an exception of the progress
// callback, is rethrown (with the GIL held); a failure or interruption of the
// run is returned in the outcome with the simulation that has the partial results.
RunOutcome guarded_run(const Scene& scene, RunOptions options, bool catch_sigint);

// RunOptions::on_progress calling a Python callable with t [ms], taking the
// GIL; an exception it raises is kept in `raised` and stops the run.
std::function<void(double)> progress_callback(pybind11::object callable, std::shared_ptr<std::exception_ptr> raised);

}  // namespace fibrodem::python
