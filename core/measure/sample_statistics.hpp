// Statistics over repeated runs (tissue seeds): mean, SD and the 95 %
// confidence interval of the mean, and the paired t-test of A/B differences.
// Student's t quantiles and tail probabilities come from Boost.Math.
#pragma once

#include <cstddef>
#include <vector>

namespace fibrodem {

struct SampleSummary {
  std::size_t n = 0;  // finite values used
  double mean, sd, ci95_low, ci95_high;  // sd (n - 1) and the CI are NaN for n < 2; all NaN for n = 0
};

// Of the finite values: mean +- t(0.975, n - 1) sd / sqrt(n).
SampleSummary summarize(const std::vector<double>& values);

struct PairedTest {
  SampleSummary difference;  // of b - a over the pairs where both are finite
  double t, p;               // t = mean / (sd / sqrt(n)), two-sided p; NaN when undefined
};

PairedTest paired_t_test(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace fibrodem
