#include "measure/summary_metrics.hpp"

#include <cmath>
#include <initializer_list>
#include <limits>

namespace fibrodem {

namespace {
double number_at(const json& summary, std::initializer_list<const char*> path) {
  const json* node = &summary;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return std::numeric_limits<double>::quiet_NaN();
    node = &(*node)[key];
  }
  if (node->is_boolean()) return node->get<bool>() ? 1.0 : 0.0;
  return node->is_number() ? node->get<double>() : std::numeric_limits<double>::quiet_NaN();
}

// The share of a type's cell-beats that did not fire (a summary written
// before beats_not_fired existed counted every beat as measured).
double not_fired_fraction(const json& summary, const char* type) {
  const double measured = number_at(summary, {"mean_biomarkers", type, "beats_measured"});
  double not_fired = number_at(summary, {"mean_biomarkers", type, "beats_not_fired"});
  if (std::isnan(not_fired) && measured >= 0) not_fired = 0;
  return not_fired / (measured + not_fired);
}
}  // namespace

const std::vector<SummaryMetric>& summary_metrics() {
  static const std::vector<SummaryMetric> list = [] {
    std::vector<SummaryMetric> l = {{"fm_ratio", [](const json& s) { return number_at(s, {"fm_ratio"}); }}};
    for (const char* type : {"myocyte", "fibroblast"})
      for (const char* m : {"rmp_mV", "apo_mV", "apd90_ms", "dvdt_max_mV_per_ms"})
        l.push_back({std::string(type) + "_" + m,
                     [type, m](const json& s) { return number_at(s, {"mean_biomarkers", type, m}); }});
    l.push_back({"cv_cm_per_s", [](const json& s) { return number_at(s, {"cv_cm_per_s"}); }});
    l.push_back({"peak_eps_xx", [](const json& s) { return number_at(s, {"peak_strain", "xx"}); }});
    l.push_back({"peak_eps_yy", [](const json& s) { return number_at(s, {"peak_strain", "yy"}); }});
    // 1 or 0, so that its mean over a sweep's seeds is the probability of
    // inducing re-entry.
    l.push_back({"reentry_detected", [](const json& s) { return number_at(s, {"reentry", "detected"}); }, true});
    l.push_back({"reentry_duration_ms", [](const json& s) { return number_at(s, {"reentry", "duration_ms"}); }});
    // Last, so that the columns before keep their places in a sweep's table.
    for (const char* type : {"myocyte", "fibroblast"})
      l.push_back({std::string(type) + "_not_fired_fraction",
                   [type](const json& s) { return not_fired_fraction(s, type); }, false, false});
    return l;
  }();
  return list;
}

}  // namespace fibrodem
