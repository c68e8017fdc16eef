// The numbers of a run's summary.json (run/run_summary.hpp writes it), by
// name, for tables and comparisons over many runs.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// A number summary.json reports, by name (sweep tables, paired comparisons):
// fm_ratio, <type>_<biomarker> per cell type (rmp_mV, apo_mV, apd90_ms,
// dvdt_max_mV_per_ms), cv_cm_per_s, peak_eps_xx, peak_eps_yy, reentry_detected
// (1 or 0) and reentry_duration_ms (output.reentry). NaN where the summary has
// none.
struct SummaryMetric {
  std::string name;
  std::function<double(const json& summary)> of;
  bool proportion = false;  // 1 or 0 per run: summarised by summarize_proportion
};
const std::vector<SummaryMetric>& summary_metrics();

}  // namespace fibrodem
