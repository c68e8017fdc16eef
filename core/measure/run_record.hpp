// What a finished run leaves for comparing it with another (A/B comparison,
// accuracy against a reference): its traces, biomarkers and tissue measures.
// run/run_record.hpp takes it from a Simulation.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "measure/biomarkers.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

struct RunRecord {
  std::string label;  // "A", "B", a method name ...
  std::vector<double> times_ms;
  std::vector<std::string> columns;          // VAR_CELL, as in traces.csv
  std::vector<std::vector<double>> samples;  // per column, one per time
  std::vector<BeatBiomarkers> beats;
  json mean_biomarkers = json::object();     // summary.json's mean_biomarkers
  std::optional<double> cv_cm_per_s;
};

}  // namespace fibrodem
