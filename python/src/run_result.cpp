#include "run_result.hpp"

#include <pybind11/numpy.h>

#include "py_json.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {

py::array_t<double> to_array(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

// The columns of biomarkers.csv (in its order), one array each.
py::dict biomarker_columns(const std::vector<BeatBiomarkers>& beats) {
  const auto n = static_cast<py::ssize_t>(beats.size());
  py::array_t<long long> cell(n), beat(n);
  py::list type;
  std::vector<double> activation(beats.size()), rmp(beats.size()), apo(beats.size()), apd90(beats.size()),
      dvdt(beats.size()), apd50(beats.size());
  auto c = cell.mutable_unchecked<1>();
  auto b = beat.mutable_unchecked<1>();
  for (std::size_t i = 0; i < beats.size(); ++i) {
    c(static_cast<py::ssize_t>(i)) = beats[i].cell;
    b(static_cast<py::ssize_t>(i)) = beats[i].beat;
    type.append(cell_type_name(beats[i].type));
    activation[i] = beats[i].activation_ms, rmp[i] = beats[i].rmp_mV, apo[i] = beats[i].apo_mV;
    apd90[i] = beats[i].apd90_ms, dvdt[i] = beats[i].dvdt_max_mV_per_ms, apd50[i] = beats[i].apd50_ms;
  }
  py::dict d;
  d["cell"] = cell;
  d["type"] = type;
  d["beat"] = beat;
  d["activation_ms"] = to_array(activation);
  d["rmp_mV"] = to_array(rmp);
  d["apo_mV"] = to_array(apo);
  d["apd90_ms"] = to_array(apd90);
  d["dvdt_max_mV_per_ms"] = to_array(dvdt);
  d["apd50_ms"] = to_array(apd50);
  return d;
}

}  // namespace

py::dict collect_result(const Simulation& simulation, bool with_summary) {
  py::dict result;
  result["t_ms"] = to_array(simulation.trace_times());
  py::dict columns;
  const auto names = simulation.trace_column_names();
  const auto& samples = simulation.trace_samples();
  for (std::size_t k = 0; k < names.size(); ++k) columns[py::str(names[k])] = to_array(samples[k]);
  result["columns"] = columns;
  result["biomarkers"] = biomarker_columns(simulation.biomarkers());
  py::list types;
  for (CellType t : simulation.tissue().type) types.append(cell_type_name(t));
  result["cell_types"] = types;
  if (with_summary) result["summary"] = to_python(simulation.summary());
  return result;
}

}  // namespace fibrodem::python
