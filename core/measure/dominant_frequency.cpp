#include "measure/dominant_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fibrodem {

DominantFrequencies dominant_frequencies(const std::vector<float>& frames, std::size_t cells, std::size_t samples,
                                         double every_ms, double f_min_hz, double f_max_hz, double min_range_mV) {
  DominantFrequencies out;
  out.per_cell_hz.assign(cells, std::numeric_limits<double>::quiet_NaN());
  const double T_s = static_cast<double>(samples) * every_ms / 1000.0;
  if (samples < 4 || T_s <= 0) return out;
  out.resolution_hz = 1.0 / T_s;
  const long k_lo = std::max(1L, static_cast<long>(std::ceil(f_min_hz * T_s - 1e-9)));
  const long k_hi = std::min(static_cast<long>(samples / 2), static_cast<long>(std::floor(f_max_hz * T_s + 1e-9)));
  if (k_hi < k_lo) return out;
  const std::size_t bins = static_cast<std::size_t>(k_hi - k_lo + 1);

  std::vector<double> mean(cells, 0.0), lo(cells, std::numeric_limits<double>::infinity()),
      hi(cells, -std::numeric_limits<double>::infinity());
  for (std::size_t m = 0; m < samples; ++m)
    for (std::size_t c = 0; c < cells; ++c) {
      const double v = frames[m * cells + c];
      mean[c] += v;
      lo[c] = std::min(lo[c], v);
      hi[c] = std::max(hi[c], v);
    }
  for (auto& x : mean) x /= static_cast<double>(samples);

  // Re and Im of each bin, bin-major: the frame loop's inner loop runs over cells.
  std::vector<double> re(bins * cells, 0.0), im(bins * cells, 0.0);
  const double N = static_cast<double>(samples);
  for (std::size_t m = 0; m < samples; ++m) {
    const double hann = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(m) / (N - 1));
    const float* frame = &frames[m * cells];
    for (std::size_t b = 0; b < bins; ++b) {
      const double angle = -2 * std::numbers::pi * static_cast<double>(k_lo + static_cast<long>(b)) *
                           static_cast<double>(m) / N;
      const double wc = hann * std::cos(angle), ws = hann * std::sin(angle);
      double* r = &re[b * cells];
      double* i = &im[b * cells];
      for (std::size_t c = 0; c < cells; ++c) {
        const double v = frame[c] - mean[c];
        r[c] += wc * v;
        i[c] += ws * v;
      }
    }
  }
  for (std::size_t c = 0; c < cells; ++c) {
    if (!(hi[c] - lo[c] >= min_range_mV)) continue;
    double best = -1;
    for (std::size_t b = 0; b < bins; ++b) {
      const double power = re[b * cells + c] * re[b * cells + c] + im[b * cells + c] * im[b * cells + c];
      if (power > best) {
        best = power;
        out.per_cell_hz[c] = static_cast<double>(k_lo + static_cast<long>(b)) / T_s;
      }
    }
  }
  return out;
}

}  // namespace fibrodem
