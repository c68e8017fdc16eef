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

// Of finite values that are each 0 or 1 (an event that happened or not):
// the proportion, the sample SD, and Wilson's 95 % score interval (Wilson
// 1927, J Am Stat Assoc 22:209), which stays within [0, 1] and is not empty
// at 0 or n events, where the t interval of the mean is neither. As
// summarize() if any value is neither 0 nor 1.
SampleSummary summarize_proportion(const std::vector<double>& values);

struct PairedTest {
  SampleSummary difference;  // of b - a over the pairs where both are finite
  double t, p;               // t = mean / (sd / sqrt(n)), two-sided p; NaN when undefined
};

PairedTest paired_t_test(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace fibrodem
