#include "measure/beat_activations.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "measure/reentry.hpp"

namespace fibrodem {

std::vector<std::vector<double>> activation_times(const VoltageFrames& frames, double V_star_mV) {
  std::vector<std::vector<double>> times(frames.cells);
  std::vector<char> armed(frames.cells, 1);
  const double rearm_mV = V_star_mV - kActivationRearm_mV;
  for (std::size_t k = 1; k < frames.count(); ++k) {
    const float* a = frames.frame(k - 1);
    const float* b = frames.frame(k);
    for (std::size_t c = 0; c < frames.cells; ++c) {
      if (b[c] < rearm_mV) armed[c] = 1;
      if (!(armed[c] && a[c] < V_star_mV && b[c] >= V_star_mV)) continue;
      armed[c] = 0;
      times[c].push_back(frames.t_ms[k - 1] +
                         (frames.t_ms[k] - frames.t_ms[k - 1]) * (V_star_mV - a[c]) / (double(b[c]) - a[c]));
    }
  }
  return times;
}

namespace {

double median_of(std::vector<double> x) {  // the upper of two middles, as the dominant frequency's
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

// The window an activation falls in: 0 before the first onset, k after the k-th.
std::size_t window_of(const std::vector<double>& onsets, double t_ms) {
  return static_cast<std::size_t>(std::upper_bound(onsets.begin(), onsets.end(), t_ms) - onsets.begin());
}

}  // namespace

BeatActivations assign_beats(const std::vector<std::vector<double>>& activations,
                             const std::vector<double>& onsets_ms, const std::vector<bool>& counted) {
  std::vector<double> onsets = onsets_ms;
  std::sort(onsets.begin(), onsets.end());
  onsets.erase(std::unique(onsets.begin(), onsets.end()), onsets.end());
  const std::size_t cells = activations.size();
  std::size_t counted_cells = 0;
  for (std::size_t c = 0; c < cells; ++c) counted_cells += counted[c];

  // waves[w][k]: window w's wave k, created when some cell first has k + 1 activations in w.
  std::vector<std::vector<BeatMap>> waves(onsets.size() + 1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  BeatActivations out;
  out.cycle_length_ms.assign(cells, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < cells; ++c) {
    const auto& times = activations[c];
    std::size_t window = onsets.size() + 1, wave = 0;  // no window yet
    for (double t : times) {
      const std::size_t w = window_of(onsets, t);
      wave = w == window ? wave + 1 : 0;
      window = w;
      auto& list = waves[w];
      while (list.size() <= wave) {
        BeatMap beat;
        if (w > 0) beat.onset_ms = onsets[w - 1];
        beat.wave = static_cast<int>(list.size());
        beat.activation_ms.assign(cells, nan);
        beat.counted = counted_cells;
        beat.first_ms = std::numeric_limits<double>::infinity();
        beat.last_ms = -std::numeric_limits<double>::infinity();
        list.push_back(std::move(beat));
      }
      BeatMap& beat = list[wave];
      beat.activation_ms[c] = static_cast<float>(t);
      if (!counted[c]) continue;
      ++beat.reached;
      beat.first_ms = std::min(beat.first_ms, t);
      beat.last_ms = std::max(beat.last_ms, t);
    }
    if (counted[c] && times.size() >= 2) {
      std::vector<double> intervals(times.size() - 1);
      for (std::size_t k = 1; k < times.size(); ++k) intervals[k - 1] = times[k] - times[k - 1];
      out.cycle_length_ms[c] = median_of(std::move(intervals));
    }
  }
  for (auto& list : waves)
    for (auto& beat : list) {
      if (beat.reached == 0) continue;  // only uncounted cells (fibroblasts) crossed V*
      beat.beat = static_cast<int>(out.beats.size());
      out.beats.push_back(std::move(beat));
    }
  return out;
}

std::string beat_map_name(int beat) { return fmt::format("activation_beat_{:03d}.png", beat); }

json beats_summary(const BeatActivations& b) {
  json per_beat = json::array();
  for (const auto& beat : b.beats)
    per_beat.push_back({{"beat", beat.beat},
                        {"onset_ms", beat.onset_ms ? json(*beat.onset_ms) : json(nullptr)},
                        {"wave", beat.wave},
                        {"first_activation_ms", beat.first_ms},
                        {"last_activation_ms", beat.last_ms},
                        {"reached", beat.reached},
                        {"counted", beat.counted},
                        {"unreached_fraction", beat.unreached_fraction()}});
  std::vector<double> cycles;
  for (double cl : b.cycle_length_ms)
    if (std::isfinite(cl)) cycles.push_back(cl);
  json out = {{"beats", per_beat},
              {"activation_cycle_length_ms", nullptr},
              {"activation_cycle_length_range_ms", nullptr},
              {"cells_with_cycle_length", cycles.size()}};
  if (cycles.empty()) return out;
  out["activation_cycle_length_ms"] = median_of(cycles);
  out["activation_cycle_length_range_ms"] = {*std::min_element(cycles.begin(), cycles.end()),
                                             *std::max_element(cycles.begin(), cycles.end())};
  return out;
}

}  // namespace fibrodem
