// Re-entry measured on V of every cell sampled at a fixed interval
// (output.reentry, docs/topics/arrhythmia.md): phase singularities found and
// tracked frame by frame (phase_singularities.csv), each track's spiral
// measures (phase_singularity_tracks.csv, measure/spiral_measures.hpp), the
// driver measures of AF mapping (measure/driver_maps.hpp: PS density in
// phase_singularity_density.csv, rotor time, the highest-DF site), activity
// after the last stimulus, conduction block per beat and the dominant
// frequency, in the band asked for and in the clinical band.
//
//   activation         an upward crossing of V* between two samples (time
//                      by linear interpolation)
//   cycle length       the interval between the last two stimulus onsets
//                      (S1-S2: the coupling interval; a burst: its period);
//                      none with fewer than two onsets
//   duration_ms        last activation anywhere - last stimulus onset (>= 0)
//   detected           duration_ms > cycle length
//   unreached fraction per beat: the fraction of myocytes that did not fire
//                      in that beat (measure/biomarkers.hpp: APO - RMP below
//                      20 mV), the criterion of conduction velocity
//   beats              activation times per beat, block per beat and the
//                      activation cycle length (measure/beat_activations.hpp)
#pragma once

#include <array>
#include <filesystem>
#include <vector>

#include "measure/beat_activations.hpp"
#include "measure/biomarkers.hpp"
#include "measure/cell_frames.hpp"
#include "measure/cell_strain.hpp"
#include "measure/singularity_tracking.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

struct ReentrySettings {
  double every_ms = 1.0;      // sampling interval
  double from_ms = 0.0;       // first sample
  double tau_ms = 10.0;       // embedding delay, a multiple of every_ms
  double V_star_mV = -50.0;   // embedding origin and activation threshold
  double link_mm = 1.0;       // PS tracking: largest step between frames
  double f_min_hz = 1.0, f_max_hz = 30.0;  // dominant frequency band
  double clinical_f_min_hz = 3.0, clinical_f_max_hz = 12.0;  // the band of clinical DF maps
  double ps_density_bin_mm = 1.0;  // PS density grid
};

// The per-cell fields behind the summary, for maps.
struct ReentryMaps {
  BeatActivations beats;
  std::vector<double> dominant_frequency_hz;  // per cell; NaN where left out of the spectrum
  std::vector<double> clinical_dominant_frequency_hz;  // the same in the clinical band
  std::vector<double> ps_density_per_cm2;  // per cell, its PS density bin's
  std::vector<SingularityTrack> tracks;    // the tip paths
};

// summary.json's "reentry"; writes phase_singularities.csv (t_ms, id, x_mm,
// y_mm, chirality: one row per PS per frame), phase_singularity_tracks.csv
// and phase_singularity_density.csv into dir unless dir is empty; fills
// `maps` if given. Given the cells' fibre stretch at the same sample times
// (a run with mechanics), phase_singularities.csv's last column is
// `stretch`, each PS's: the mean over its triangle's cells that have one
// (linear interpolation at the triangle's centroid, where the PS is
// placed), or over its hole's rim, NaN if none has. Throws std::invalid_argument if the stretch
// frames' times are not the V frames'.
json analyse_reentry(const Tissue& tissue, const VoltageFrames& frames, const ReentrySettings& settings,
                     const std::vector<double>& stimulus_onsets_ms, const std::vector<BeatBiomarkers>& beats,
                     const std::filesystem::path& dir, ReentryMaps* maps = nullptr,
                     const StretchFrames* stretch = nullptr);

// Per beat, the fraction of the myocytes measured in it that it did not
// reach ([{beat, fraction, myocytes}]).
json unreached_fractions(const std::vector<BeatBiomarkers>& beats);

}  // namespace fibrodem
