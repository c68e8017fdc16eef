// fibrodem._core.simulate_cell: one uncoupled cell, for calibration loops. The
// same core as a run (a single_cell scene), with what a loop of thousands of
// calls must not pay for left out: no files, no summary, no JSON text.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "binding.hpp"
#include "guarded_run.hpp"
#include "py_json.hpp"
#include "run_result.hpp"
#include "scene/scene.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {

json cell_manifest(const std::string& model, const std::optional<std::string>& variant, py::handle parameters,
                   py::handle initial_state, py::handle stimulus, double duration_ms, py::handle solver,
                   const std::vector<std::string>& log, std::optional<double> log_every_ms,
                   const std::string& cell_type) {
  json cell = {{"model", model}, {"parameters", to_json(parameters, "parameters")}};
  if (variant) cell["variant"] = *variant;
  if (!initial_state.is_none()) cell["initial_state"] = to_json(initial_state, "initial_state");
  json traces = {{"cells", {0}}, {"variables", log}};
  if (log_every_ms) traces["every_ms"] = *log_every_ms;
  json manifest = {{"fibrodem", 1},
                   {"name", "simulate_cell"},
                   {"duration_ms", duration_ms},
                   {"tissue", {{"builder", "single_cell"}, {"type", cell_type}}},
                   {"cells", {{cell_type, cell}}},
                   {"stimulus", to_json(stimulus, "stimulus")},
                   {"output", {{"traces", traces}}}};
  if (!solver.is_none()) manifest["solver"] = to_json(solver, "solver");
  return manifest;
}

py::dict simulate_cell(const std::string& model, const std::optional<std::string>& variant, py::dict parameters,
                       py::object initial_state, py::object stimulus, double duration_ms, py::object solver,
                       const std::vector<std::string>& log, std::optional<double> log_every_ms,
                       const std::string& cell_type, bool catch_sigint) {
  const Scene scene = parse_scene(cell_manifest(model, variant, parameters, initial_state, stimulus, duration_ms,
                                                solver, log, log_every_ms, cell_type));
  RunOutcome outcome = guarded_run(scene, RunOptions{}, catch_sigint);
  py::dict result = collect_result(*outcome.simulation, false);
  result["status"] = outcome.status;
  result["message"] = outcome.message;
  result["run_s"] = outcome.run_s;
  result["set_up_s"] = outcome.set_up_s;
  result["run_cpu_s"] = outcome.run_cpu_s;
  return result;
}

}  // namespace

void bind_simulate_cell(py::module_& m) {
  m.def("simulate_cell", &simulate_cell, py::arg("model"), py::arg("variant"), py::arg("parameters"),
        py::arg("initial_state"), py::arg("stimulus"), py::arg("duration_ms"), py::arg("solver"), py::arg("log"),
        py::arg("log_every_ms"), py::arg("cell_type"), py::arg("catch_sigint"));
}

}  // namespace fibrodem::python
