#include "run/reentry_maps.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

#include "io/tissue_picture.hpp"
#include "io/vtk_writer.hpp"
#include "io/vtk_xml_writer.hpp"

namespace fibrodem {

namespace {
// Without antialiasing a map has at most 256 colours and is written as a
// palette PNG, a fraction of the size (as the snapshots).
PictureOptions map_picture(const std::string& value_label, const std::string& title) {
  PictureOptions picture;
  picture.value_label = value_label;
  picture.title = title;
  picture.antialias = false;
  return picture;
}

std::string beat_title(const std::string& scene_name, const BeatMap& beat) {
  const std::string onset = beat.onset_ms ? fmt::format("stimulus at {:g} ms", *beat.onset_ms) : "before any stimulus";
  const std::string wave = beat.wave == 0 ? "" : fmt::format(", re-excitation {}", beat.wave);
  return fmt::format("{}: activation, beat {} ({}{}), {:.1f} % not reached", scene_name, beat.beat, onset, wave,
                     100 * beat.unreached_fraction());
}
}  // namespace

std::size_t write_reentry_maps(const std::filesystem::path& dir, const std::string& scene_name, const Tissue& tissue,
                               const ReentryMaps& maps, const std::string& vtk_format, const MapField& under_paths) {
  CellFields fields;
  if (maps.dominant_frequency_hz.size() == tissue.cell_count()) {
    write_tissue_png(tissue, dir / "dominant_frequency_map.png", &maps.dominant_frequency_hz,
                     map_picture("dominant frequency (Hz)", scene_name + ": dominant frequency per cell"));
    fields.emplace_back("dominant_frequency_hz", maps.dominant_frequency_hz);
  }
  if (maps.clinical_dominant_frequency_hz.size() == tissue.cell_count()) {
    write_tissue_png(tissue, dir / "clinical_dominant_frequency_map.png", &maps.clinical_dominant_frequency_hz,
                     map_picture("dominant frequency (Hz)",
                                 scene_name + ": dominant frequency per cell, clinical band"));
    fields.emplace_back("clinical_dominant_frequency_hz", maps.clinical_dominant_frequency_hz);
  }
  if (maps.ps_density_per_cm2.size() == tissue.cell_count()) {
    write_tissue_png(tissue, dir / "phase_singularity_density_map.png", &maps.ps_density_per_cm2,
                     map_picture("PS-s per cm2", scene_name + ": phase singularity density"));
    fields.emplace_back("ps_density_per_cm2", maps.ps_density_per_cm2);
  }
  if (under_paths.values.size() == tissue.cell_count())
    write_tip_path_map(dir / "phase_singularity_paths.png", scene_name, tissue, maps.tracks, under_paths);
  fields.emplace_back("cycle_length_ms", maps.beats.cycle_length_ms);
  const std::size_t drawn = std::min(maps.beats.beats.size(), kMostBeatMaps);
  for (std::size_t k = 0; k < drawn; ++k) {
    const BeatMap& beat = maps.beats.beats[k];
    std::vector<double> activation(beat.activation_ms.begin(), beat.activation_ms.end());
    write_tissue_png(tissue, dir / beat_map_name(beat.beat), &activation,
                     map_picture("activation (ms)", beat_title(scene_name, beat)));
    fields.emplace_back(fmt::format("activation_beat_{}_ms", beat.beat), std::move(activation));
  }
  if (vtk_format == "xml") write_tissue_vtp(tissue, dir / "reentry_maps.vtp", fields, false);
  else write_tissue_vtk(tissue, dir / "reentry_maps.vtk", fields, false);
  return drawn;
}

}  // namespace fibrodem
