// A/B over the same tissues (fibrodem compare --seeds K): per metric of the
// runs' summaries, the paired differences B - A with their mean, 95 %
// confidence interval and a paired t-test (paired.csv, paired.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// a[k] and b[k]: the summaries of A and B on tissue k. Writes dir/paired.csv
// and dir/paired.md; returns the markdown table.
std::string write_paired_comparison(const std::vector<json>& a, const std::vector<json>& b,
                                    const std::vector<long long>& seeds, const std::filesystem::path& dir);

}  // namespace fibrodem
