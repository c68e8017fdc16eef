#include "measure/dominant_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fibrodem {

namespace {
// The bins k / T inside a band, [lo, hi]; hi < lo when none.
std::pair<long, long> band_bins(const FrequencyBand& band, double T_s, std::size_t samples) {
  return {std::max(1L, static_cast<long>(std::ceil(band.f_min_hz * T_s - 1e-9))),
          std::min(static_cast<long>(samples / 2), static_cast<long>(std::floor(band.f_max_hz * T_s + 1e-9)))};
}
}  // namespace

DominantFrequencies dominant_frequencies(const std::vector<float>& frames, std::size_t cells, std::size_t samples,
                                         double every_ms, double f_min_hz, double f_max_hz, double min_range_mV) {
  return dominant_frequencies(frames, cells, samples, every_ms, {FrequencyBand{f_min_hz, f_max_hz}}, min_range_mV)
      .front();
}

std::vector<DominantFrequencies> dominant_frequencies(const std::vector<float>& frames, std::size_t cells,
                                                      std::size_t samples, double every_ms,
                                                      const std::vector<FrequencyBand>& bands, double min_range_mV) {
  std::vector<DominantFrequencies> out(bands.size());
  for (auto& df : out) df.per_cell_hz.assign(cells, std::numeric_limits<double>::quiet_NaN());
  const double T_s = static_cast<double>(samples) * every_ms / 1000.0;
  if (samples < 4 || T_s <= 0 || bands.empty()) return out;
  for (auto& df : out) df.resolution_hz = 1.0 / T_s;
  // The bins of every band, from the lowest to the highest.
  long k_lo = std::numeric_limits<long>::max(), k_hi = std::numeric_limits<long>::min();
  for (const auto& band : bands) {
    const auto [lo, hi] = band_bins(band, T_s, samples);
    if (hi < lo) continue;
    k_lo = std::min(k_lo, lo);
    k_hi = std::max(k_hi, hi);
  }
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
  // Each band's largest peak (the lowest of equal ones).
  for (std::size_t n = 0; n < bands.size(); ++n) {
    const auto [band_lo, band_hi] = band_bins(bands[n], T_s, samples);
    for (std::size_t c = 0; c < cells; ++c) {
      if (!(hi[c] - lo[c] >= min_range_mV)) continue;
      double best = -1;
      for (long k = band_lo; k <= band_hi; ++k) {
        const std::size_t at = static_cast<std::size_t>(k - k_lo) * cells + c;
        const double power = re[at] * re[at] + im[at] * im[at];
        if (power > best) {
          best = power;
          out[n].per_cell_hz[c] = static_cast<double>(k) / T_s;
        }
      }
    }
  }
  return out;
}

}  // namespace fibrodem
