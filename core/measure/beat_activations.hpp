// Activation times of every cell, beat by beat, from V sampled at a fixed
// interval (output.reentry, docs/topics/arrhythmia.md "Beats"): per-beat
// activation maps, conduction block per beat and the cycle length.
//
//   activation   an upward crossing of V* between two samples, its time
//                interpolated linearly, by a cell whose V has fallen below
//                V* - kActivationRearm_mV since its last activation: V
//                hovering about V* (the cells at a spiral's tip, a wave
//                failing at a collagen void) crosses it many times in one
//                excitation, and each crossing would count as a beat
//   beat window  from one distinct stimulus onset to the next (the last to
//                the end of the record); activations before the first onset
//                form a window of their own
//   beat         within a window, wave k holds each cell's (k+1)-th
//                activation in it: wave 0 is the wave the stimulus starts,
//                waves 1, 2, ... are re-excitations without a stimulus
//                (re-entry). Beats are numbered 0, 1, ... in window, then
//                wave, order.
//   unreached    the fraction of the counted cells (excitable: myocytes)
//                without an activation in the beat
//   cycle length per cell, the median interval between its successive
//                activations over the whole record
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "measure/cell_frames.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

inline constexpr double kActivationRearm_mV = 10;

// Every cell's activations, in time order.
std::vector<std::vector<double>> activation_times(const VoltageFrames& frames, double V_star_mV);

struct BeatMap {
  int beat = 0;
  std::optional<double> onset_ms;  // the stimulus onset opening its window; none before the first
  int wave = 0;                    // 0: the stimulus' wave; k > 0: the k-th re-excitation in the window
  std::vector<float> activation_ms;  // per cell; NaN where the beat has no activation
  std::size_t counted = 0;         // cells counted (excitable)
  std::size_t reached = 0;         // of those, activated in this beat
  double first_ms = 0, last_ms = 0;  // the beat's earliest and latest activation (counted cells)
  double unreached_fraction() const { return counted ? 1.0 - static_cast<double>(reached) / counted : 0.0; }
};

struct BeatActivations {
  std::vector<BeatMap> beats;           // only beats with at least one activation
  std::vector<double> cycle_length_ms;  // per cell; NaN with fewer than two activations
};

// `onsets_ms` the stimulus onsets (any order, repeats allowed); `counted`
// per cell, whether it counts towards block and cycle length.
BeatActivations assign_beats(const std::vector<std::vector<double>>& activations,
                             const std::vector<double>& onsets_ms, const std::vector<bool>& counted);

// summary.json's reentry "beats" (per beat: beat, onset_ms, wave,
// first_activation_ms, last_activation_ms, reached, counted,
// unreached_fraction) and the cycle length (the spatial median of the
// per-cell medians, their range, the cells measured).
json beats_summary(const BeatActivations& beats);

// The maps drawn of the beats (run/reentry_maps.hpp), found by the report by
// name: the first kMostBeatMaps beats, beat k's picture activation_beat_<k>.png,
// k zero-padded to 3 digits.
inline constexpr std::size_t kMostBeatMaps = 24;
std::string beat_map_name(int beat);

}  // namespace fibrodem
