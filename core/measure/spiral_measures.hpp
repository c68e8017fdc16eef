// The measures of one spiral wave, from its phase singularity's track
// (measure/singularity_tracking.hpp; docs/topics/arrhythmia.md "Spiral measures").
// Brocklehurst, Ni, Zhang & Ye 2017 (PLoS ONE 12:e0176607) characterise
// spirals by tip trajectory, excitation frequency and meander range; the
// definitions here are fibrodem's, each with a closed-form answer on a
// circle or a line (tests/measure/test_spiral_measures.cpp):
//
//   lifetime_ms    death_ms - birth_ms: the first and last samples it was seen in
//   period_ms      the rotation period: the activation cycle length of the
//                  cells around the tip (rotation_period_ms below): each
//                  cell around a rotor is excited once a turn. Not from the
//                  phase at the tip's own cells: there the phase is
//                  singular, and their V circles V* in small irregular loops
//   rotations      lifetime_ms / period_ms
//   rotor          rotations >= 1: the track lived at least one of its own
//                  rotation periods (a shorter-lived PS is a transient break)
//   drift_mm       the distance between the tip's mean position over its
//                  first rotation and over its last (the rotation centre's
//                  displacement, Davidenko et al. 1992, Nature 355:349, for
//                  drifting spirals); over the first and last half of the
//                  life when it is shorter than two periods
//   drift_speed_mm_per_s  drift_mm over the time between those two windows'
//                  mean times: a tip moving at constant velocity v gives |v|
//   meander_extent_mm  the path's diameter: the largest distance between two
//                  tip positions (a circular path of radius r: 2 r)
//   meander_area_mm2   the area of the convex hull of the tip positions, the
//                  region the tip sweeps around (a circular path of radius
//                  r: pi r^2, less the polygon's shortfall of the samples)
#pragma once

#include <array>
#include <filesystem>
#include <vector>

#include "measure/singularity_tracking.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct SpiralMeasures {
  int id = 0, chirality = 0;
  double birth_ms = 0, death_ms = 0, lifetime_ms = 0;
  double rotations = 0, period_ms = 0;
  bool rotor = false;
  double x_mm = 0, y_mm = 0;  // the tip's mean position
  double drift_mm = 0, drift_speed_mm_per_s = 0;
  double meander_extent_mm = 0, meander_area_mm2 = 0;
};

// Cells within kTipNeighbourhood_mm of the tip's path (of its mean position,
// plus the path's largest distance from it, each point's reach added: a PS
// in a hole is anywhere in it) are "around the tip": eight myocytes along a
// fibre, forty columns across, near enough to follow this rotor rather than
// another. Around a hole, the cells within that distance of its farthest
// rim cell from the centroid, so every cell of its rim.
inline constexpr double kTipNeighbourhood_mm = 1.0;

// The median over the cells around the tip of each one's median interval
// between successive activations within the track's life (activations_ms:
// per cell, its activation times, measure/beat_activations.hpp); NaN when
// no cell there activates twice in it (a life shorter than a turn).
double rotation_period_ms(const SingularityTrack& track, const Tissue& tissue,
                          const std::vector<std::vector<double>>& activations_ms);

// period_ms: the track's rotation period (NaN: none).
SpiralMeasures spiral_measures(const SingularityTrack& track, double period_ms);

// The convex hull of points (x, y), counter-clockwise, without repeated or
// collinear points (Andrew's monotone chain).
std::vector<std::array<double, 2>> convex_hull(std::vector<std::array<double, 2>> points);
// A simple polygon's area (shoelace), positive counter-clockwise.
double polygon_area(const std::vector<std::array<double, 2>>& polygon);

// phase_singularity_tracks.csv: one row per track, the measures above.
void write_spiral_measures_csv(const std::filesystem::path& file, const std::vector<SpiralMeasures>& spirals);

}  // namespace fibrodem
