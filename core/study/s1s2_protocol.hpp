// Reading an S1-S2 protocol from a manifest's stimulus list, for the studies
// that move S2 (restitution, vulnerable window): stimulus[0] is the S1 train
// (a finite count of pulses every period_ms), stimulus[1] the S2 pulse, its
// coupling interval measured from the last S1 onset (docs/topics/arrhythmia.md).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// The onsets of stimulus[i]'s train (start_ms, start_ms + period_ms, ...).
// ManifestError naming the path for a train without a count, or for a
// non-number.
std::vector<double> train_onsets(const json& stimulus, std::size_t i);

// The last onset of S1. ManifestError on "stimulus" when the manifest has
// fewer than two stimuli; `study` names what needs them ("the restitution
// protocol").
double last_s1_onset_ms(const json& manifest, const std::string& study);

// stimulus[1].start_ms minus the last S1 onset.
double coupling_interval_ms(const json& manifest, const std::string& study);

// The beat that starts at `onset_ms`, counted over the distinct onsets of
// every train (as biomarkers.csv and summary.json number beats).
std::optional<std::size_t> beat_of_onset(const json& manifest, double onset_ms);

// The interval to run between `low_ms` and `high_ms` when bisecting a
// boundary (S2 captured or not, re-entry or not): the midpoint on the
// resolution's grid counted from the low end (so that the probes of a scan on
// that grid stay on it), at least one resolution step above it.
double bisection_interval_ms(double low_ms, double high_ms, double resolution_ms);

// A number of an object, `otherwise` if absent; ManifestError at path.key if
// not a number.
double number_at(const json& object, const char* key, double otherwise, const std::string& path);

// Shortest text of an interval for folder names and tables ("250", "212.5").
std::string interval_text(double ms);

}  // namespace fibrodem
