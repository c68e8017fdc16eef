// A/B over the same tissues (fibrodem compare --seeds K): per metric of the
// runs' summaries, the paired differences B - A with their mean, 95 %
// confidence interval and a paired t-test (paired.csv, paired.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "measure/sample_statistics.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

// One metric of summary_metrics() over the pairs (paired.csv's row).
struct PairedRow {
  std::string metric;
  double a_mean, b_mean;     // over the tissues
  SampleSummary difference;  // of B - A (its n: the pairs)
  double t, p;               // paired t-test, two-sided; NaN when undefined
};

// a[k] and b[k]: the summaries of A and B on tissue k. One row per metric
// the scene measures, in summary_metrics() order.
std::vector<PairedRow> paired_rows(const std::vector<json>& a, const std::vector<json>& b);

// a[k] and b[k]: the summaries of A and B on tissue k. Writes dir/paired.csv
// and dir/paired.md; returns the markdown table.
std::string write_paired_comparison(const std::vector<json>& a, const std::vector<json>& b,
                                    const std::vector<long long>& seeds, const std::filesystem::path& dir);

}  // namespace fibrodem
