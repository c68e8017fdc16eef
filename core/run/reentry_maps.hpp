// The maps of output.reentry (docs/topics/arrhythmia.md "Maps"): the dominant
// frequency of every cell (in the band asked for and in the clinical band),
// the phase singularities' density and each beat's activation times, as
// pictures (dominant_frequency_map.png, clinical_dominant_frequency_map.png,
// phase_singularity_density_map.png, activation_beat_<k>.png) and one
// ParaView file (reentry_maps.vtk, or .vtp with vtk_format "xml") holding
// them all with each cell's cycle length; and the tip paths over a map
// (phase_singularity_paths.png, run/tip_path_map.hpp). At most
// kMostBeatMaps beats are drawn (measure/beat_activations.hpp, which names
// their pictures), so that a long fibrillating run writes a bounded number
// of files; every beat stays in summary.json.
#pragma once

#include <filesystem>
#include <string>

#include "measure/reentry.hpp"
#include "run/tip_path_map.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

// Returns the number of beats drawn. The tip paths are drawn over
// `under_paths` unless it holds no value per cell.
std::size_t write_reentry_maps(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                               const ReentryMaps& maps, const std::string& vtk_format,
                               const MapField& under_paths = {});

}  // namespace fibrodem
