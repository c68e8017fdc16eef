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
// dvdt_max_mV_per_ms, over the beats where the cell fired), cv_cm_per_s,
// peak_eps_xx, peak_eps_yy, reentry_detected (1 or 0), reentry_duration_ms
// (output.reentry) and <type>_not_fired_fraction (the share of the type's
// cell-beats that did not fire). NaN where the summary has none.
struct SummaryMetric {
  std::string name;
  std::function<double(const json& summary)> of;
  bool proportion = false;  // 1 or 0 per run: summarised by summarize_proportion
  bool drawn_when_zero = true;  // false: a sweep plots it only where some mean is not 0
};
const std::vector<SummaryMetric>& summary_metrics();

}  // namespace fibrodem
