// phase_singularity_paths.png (output.reentry): the tracked phase
// singularities' tip paths drawn over a map of the tissue coloured by one
// value per cell: V at the last sample by default, or any other per-cell
// field (a strain map). Paths of chirality +1 are white, -1 red, each
// ending in a dot at the tip's last position; the kMostTipPaths
// longest-lived tracks are drawn (the title says how many there are), so
// that a fibrillating run's picture stays readable.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "measure/singularity_tracking.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

inline constexpr std::size_t kMostTipPaths = 20;

// The map under the paths: one value per cell, its colour bar's label
// ("V (mV)") and what it shows, for the title ("V at t = 995 ms").
struct MapField {
  std::vector<double> values;
  std::string value_label, what;
};

void write_tip_path_map(const std::filesystem::path& file, const std::string& scene_name, const Tissue& tissue,
                        const std::vector<SingularityTrack>& tracks, const MapField& field);

}  // namespace fibrodem
