#include "run/run_record.hpp"

#include "run/simulation.hpp"

namespace fibrodem {

RunRecord record_of(const Simulation& simulation, std::string label) {
  RunRecord r;
  r.label = std::move(label);
  r.times_ms = simulation.trace_times();
  r.columns = simulation.trace_column_names();
  r.samples = simulation.trace_samples();
  r.beats = simulation.biomarkers();
  const json summary = simulation.summary();
  r.mean_biomarkers = summary["mean_biomarkers"];
  if (summary["cv_cm_per_s"].is_number()) r.cv_cm_per_s = summary["cv_cm_per_s"].get<double>();
  return r;
}

}  // namespace fibrodem
