// Where re-entry is driven from, in the measures of clinical AF mapping
// (docs/topics/arrhythmia.md "Drivers"):
//
//   highest dominant frequency site  the cells whose dominant frequency
//       (measure/dominant_frequency.hpp) is the highest of the tissue, the
//       target of DF-guided ablation (Sanders et al. 2005, Circulation
//       112:789): that frequency, how many cells have it and their centroid
//   PS density   PS-seconds per cm^2 on a grid of square bins bin_mm wide
//       from the tissue's lower-left corner: each PS found in a sample
//       counts every_ms of PS time in the bin holding it, so the grid sums
//       to the record's PS-seconds (PS per sample x every_ms); a bin is
//       divided by its whole area, also where the tissue's edge cuts it
//   rotor time fraction  the fraction of the samples searched for PS in
//       which at least one rotor (measure/spiral_measures.hpp: a track
//       that completes a rotation) is alive; a rotor counts over its whole
//       life, its first rotation included
#pragma once

#include <array>
#include <filesystem>
#include <vector>

#include "measure/spiral_measures.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

struct HighestFrequencySite {
  double frequency_hz = 0;  // NaN with no cell in the spectrum
  std::size_t cells = 0;    // cells at that frequency (a bin of the spectrum)
  double x_mm = 0, y_mm = 0;  // their centroid
};

HighestFrequencySite highest_frequency_site(const Tissue& tissue, const std::vector<double>& per_cell_hz);

struct PsDensityGrid {
  double x0_mm = 0, y0_mm = 0, bin_mm = 1;
  int nx = 1, ny = 1;
  std::vector<double> ps_seconds;  // bin (i, j) at j * nx + i

  double bin_area_cm2() const { return bin_mm * bin_mm / 100.0; }
  // The bin holding (x, y), those outside counted in the nearest edge bin.
  std::size_t bin_of(double x_mm, double y_mm) const;
  // Each cell's bin's PS-seconds per cm^2 (for the map).
  std::vector<double> per_cell_per_cm2(const Tissue& tissue) const;
};

// bounds_mm: x_min, x_max, y_min, y_max (the tissue's, in mm). Throws
// std::invalid_argument unless bin_mm > 0.
PsDensityGrid ps_density(const std::vector<SingularityTrack>& tracks, const std::array<double, 4>& bounds_mm,
                         double bin_mm, double every_ms);

// phase_singularity_density.csv: one row per bin, its centre, PS-seconds
// and PS-seconds per cm^2.
void write_ps_density_csv(const std::filesystem::path& file, const PsDensityGrid& grid);

// NaN without a sample.
double rotor_time_fraction(const std::vector<SpiralMeasures>& spirals, const std::vector<double>& sample_times_ms);

}  // namespace fibrodem
