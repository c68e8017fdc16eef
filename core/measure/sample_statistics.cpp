#include "measure/sample_statistics.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrodem {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

SampleSummary summarize(const std::vector<double>& values) {
  SampleSummary s{0, kNaN, kNaN, kNaN, kNaN};
  double sum = 0;
  for (double v : values)
    if (std::isfinite(v)) sum += v, ++s.n;
  if (s.n == 0) return s;
  s.mean = sum / static_cast<double>(s.n);
  if (s.n < 2) return s;
  double squares = 0;
  for (double v : values)
    if (std::isfinite(v)) squares += (v - s.mean) * (v - s.mean);
  s.sd = std::sqrt(squares / static_cast<double>(s.n - 1));
  const boost::math::students_t t(static_cast<double>(s.n - 1));
  const double half = boost::math::quantile(t, 0.975) * s.sd / std::sqrt(static_cast<double>(s.n));
  s.ci95_low = s.mean - half;
  s.ci95_high = s.mean + half;
  return s;
}

SampleSummary summarize_proportion(const std::vector<double>& values) {
  SampleSummary s = summarize(values);
  for (double v : values)
    if (std::isfinite(v) && v != 0 && v != 1) return s;
  if (s.n == 0) return s;
  // p +- z sqrt(p (1 - p) / n + z^2 / (4 n^2)), centred at (p + z^2 / (2 n)),
  // all over 1 + z^2 / n; z the normal 97.5 % quantile.
  const double z = 1.959963984540054, n = static_cast<double>(s.n), p = s.mean;
  const double centre = p + z * z / (2 * n), denominator = 1 + z * z / n;
  const double half = z * std::sqrt(p * (1 - p) / n + z * z / (4 * n * n));
  // (Exactly 0 below none and 1 above all: the formula's round-off left 5e-17.)
  s.ci95_low = p == 0 ? 0.0 : std::max(0.0, (centre - half) / denominator);
  s.ci95_high = p == 1 ? 1.0 : std::min(1.0, (centre + half) / denominator);
  return s;
}

PairedTest paired_t_test(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(b[i])) d.push_back(b[i] - a[i]);
  PairedTest test{summarize(d), kNaN, kNaN};
  const SampleSummary& s = test.difference;
  if (s.n < 2) return test;
  if (s.sd == 0) {  // every pair differs by the same amount: certain unless it is zero
    test.t = s.mean == 0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), s.mean);
    test.p = s.mean == 0 ? 1.0 : 0.0;
    return test;
  }
  test.t = s.mean / (s.sd / std::sqrt(static_cast<double>(s.n)));
  test.p = 2 * boost::math::cdf(boost::math::complement(boost::math::students_t(static_cast<double>(s.n - 1)),
                                                        std::abs(test.t)));
  return test;
}

}  // namespace fibrodem
