// Statistics over seeds (measure/sample_statistics.hpp) against values worked by hand.
#include <doctest/doctest.h>

#include <cmath>

#include "measure/sample_statistics.hpp"

using namespace fibrodem;

TEST_CASE("summarize: mean, sample SD and the t-based 95 % CI of the mean, non-finite values left out") {
  // 2, 4, 9: mean 5, sample SD sqrt(26/2); for 2 degrees of freedom Student's
  // t quantile has the closed form t_p = (2p - 1) / sqrt(2p(1 - p)):
  // t(0.975, 2) = 4.302652729749464.
  const SampleSummary s = summarize({2, 4, 9, NAN});
  CHECK(s.n == 3);
  CHECK(s.mean == doctest::Approx(5.0));
  CHECK(s.sd == doctest::Approx(std::sqrt(13.0)));
  const double half = 4.302652729749464 * std::sqrt(13.0) / std::sqrt(3.0);
  CHECK(s.ci95_low == doctest::Approx(5.0 - half).epsilon(1e-12));
  CHECK(s.ci95_high == doctest::Approx(5.0 + half).epsilon(1e-12));
  const SampleSummary one = summarize({3.5});
  CHECK(one.mean == 3.5);
  CHECK(std::isnan(one.sd));
  CHECK(std::isnan(one.ci95_low));
  CHECK(summarize({}).n == 0);
}

TEST_CASE("summarize_proportion: Wilson's score interval for events out of runs") {
  // 3 of 4: Wilson's interval (p + z^2/2n +- z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n),
  // z = 1.959963984540054, worked by hand: [0.300642, 0.954413].
  const SampleSummary three = summarize_proportion({1, 0, 1, 1, NAN});
  CHECK(three.n == 4);
  CHECK(three.mean == 0.75);
  CHECK(three.ci95_low == doctest::Approx(0.300642).epsilon(1e-6));
  CHECK(three.ci95_high == doctest::Approx(0.954413).epsilon(1e-6));
  // None of 4: from 0 to z^2/(n + z^2) = 0.489891, not the empty interval a t
  // interval gives.
  const SampleSummary none = summarize_proportion({0, 0, 0, 0});
  CHECK(none.ci95_low == 0.0);
  CHECK(none.ci95_high == doctest::Approx(0.489891).epsilon(1e-6));
  // Of 3 the formula's lower bound is 5e-17 in floating point; none and all
  // give exactly 0 and 1 (z^2/(n + z^2) = 0.561491 the other bound).
  CHECK(summarize_proportion({0, 0, 0}).ci95_low == 0.0);
  CHECK(summarize_proportion({1, 1, 1}).ci95_high == 1.0);
  CHECK(summarize_proportion({1, 1, 1}).ci95_low == doctest::Approx(1 - 0.561491).epsilon(1e-5));
  // Not all 0 or 1: the t interval of the mean.
  const SampleSummary other = summarize_proportion({2, 4, 9});
  CHECK(other.ci95_low == summarize({2, 4, 9}).ci95_low);
}

TEST_CASE("paired t-test: differences b - a, t and two-sided p") {
  // d = 1, 2, 3, 4: mean 2.5, SD sqrt(5/3), t = 2.5 / (SD / 2) = 3.872983346207417;
  // two-sided p for 3 degrees of freedom from the closed-form CDF
  // F(t) = 1/2 + (x / (1 + x^2) + atan x) / pi, x = t / sqrt(3): p = 0.0304662916621710.
  const PairedTest test = paired_t_test({10, 10, 10, 10}, {11, 12, 13, 14});
  CHECK(test.difference.mean == doctest::Approx(2.5));
  CHECK(test.t == doctest::Approx(3.872983346207417));
  CHECK(test.p == doctest::Approx(0.0304662916621710).epsilon(1e-9));
  // A constant shift: certain; no shift at all: p = 1.
  CHECK(paired_t_test({1, 2, 3}, {2, 3, 4}).p == 0.0);
  CHECK(paired_t_test({1, 2, 3}, {1, 2, 3}).p == 1.0);
}
