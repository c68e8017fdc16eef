#include "measure/reentry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <stdexcept>
#include <string>

#include "io/csv_writer.hpp"
#include "measure/cell_holes.hpp"
#include "measure/cell_triangles.hpp"
#include "measure/dominant_frequency.hpp"
#include "measure/driver_maps.hpp"
#include "measure/singularity_tracking.hpp"
#include "measure/spiral_measures.hpp"

namespace fibrodem {

json unreached_fractions(const std::vector<BeatBiomarkers>& beats) {
  std::map<int, std::pair<int, int>> by_beat;  // beat -> (unreached, measured) myocytes
  for (const auto& b : beats) {
    if (b.type != CellType::myocyte) continue;
    auto& [unreached, measured] = by_beat[b.beat];
    ++measured;
    if (!fired(b)) ++unreached;
  }
  json out = json::array();
  for (const auto& [beat, counts] : by_beat)
    out.push_back({{"beat", beat},
                   {"fraction", static_cast<double>(counts.first) / counts.second},
                   {"myocytes", counts.second}});
  return out;
}

namespace {
// The fibre stretch at a PS of frame k: the mean of the cells' around it
// (its triangle's or its hole's rim's; analyse_reentry).
double stretch_at(const StretchFrames& stretch, std::size_t k, std::span<const int> cells) {
  const float* frame = stretch.frame(k);
  double sum = 0;
  int n = 0;
  for (int c : cells)
    if (std::isfinite(frame[c])) sum += frame[c], ++n;
  return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

void check_same_times(const VoltageFrames& frames, const StretchFrames& stretch) {
  const bool same = stretch.t_ms == frames.t_ms && (frames.count() == 0 || stretch.cells == frames.cells);
  if (!same)
    throw std::invalid_argument("re-entry: the stretch was sampled at " + std::to_string(stretch.count()) +
                                " times, V at " + std::to_string(frames.count()) +
                                " (expected the same times, every cell)");
}

// The PS of every frame, tracked; rows of phase_singularities.csv if dir is
// given, with each PS's stretch if given.
SingularityTracker track_singularities(const Tissue& tissue, const VoltageFrames& frames, const ReentrySettings& s,
                                       const std::filesystem::path& dir, const StretchFrames* stretch) {
  const auto triangles = cell_triangles(tissue);
  const auto holes = cell_holes(tissue, triangles);
  const std::size_t delay = static_cast<std::size_t>(std::llround(s.tau_ms / s.every_ms));
  CsvWriter csv;
  if (!dir.empty()) {
    std::vector<std::string> columns{"t_ms", "id", "x_mm", "y_mm", "chirality"};
    if (stretch) columns.emplace_back("stretch");
    csv = CsvWriter(dir / "phase_singularities.csv", columns);
  }
  SingularityTracker tracker(s.link_mm);
  std::vector<double> phase(frames.cells);
  for (std::size_t k = delay; k < frames.count(); ++k) {
    const float* now = frames.frame(k);
    const float* before = frames.frame(k - delay);
    for (std::size_t c = 0; c < frames.cells; ++c) phase[c] = embedding_phase(now[c], before[c], s.V_star_mV);
    const auto found = find_phase_singularities(tissue, triangles, phase, holes);
    const auto ids = tracker.add_frame(frames.t_ms[k], found);
    if (!csv.is_open()) continue;
    for (std::size_t j = 0; j < found.size(); ++j) {
      csv.cell(frames.t_ms[k]).cell(static_cast<long long>(ids[j])).cell(found[j].x_mm).cell(found[j].y_mm)
          .cell(static_cast<long long>(found[j].chirality));
      if (stretch) csv.cell(stretch_at(*stretch, k, cells_around(found[j], triangles, holes)));
      csv.end_row();
    }
  }
  if (csv.is_open()) csv.flush();
  return tracker;
}

// Of every cell's activations at or after `after_ms`: the latest anywhere,
// and the most any cell has.
std::pair<double, int> activations_after(const std::vector<std::vector<double>>& activations, double after_ms) {
  double last = -std::numeric_limits<double>::infinity();
  int most = 0;
  for (const auto& a : activations) {
    const auto first = std::lower_bound(a.begin(), a.end(), after_ms);
    if (first == a.end()) continue;
    last = std::max(last, a.back());
    most = std::max(most, static_cast<int>(a.end() - first));
  }
  return {last, most};
}

json dominant_frequency_summary(const DominantFrequencies& df) {
  std::vector<double> found;
  for (double f : df.per_cell_hz)
    if (std::isfinite(f)) found.push_back(f);
  json out = {{"dominant_frequency_hz", nullptr}, {"dominant_frequency_range_hz", nullptr},
              {"frequency_resolution_hz", df.resolution_hz > 0 ? json(df.resolution_hz) : json(nullptr)},
              {"cells_in_spectrum", found.size()}};
  if (found.empty()) return out;
  std::sort(found.begin(), found.end());
  out["dominant_frequency_hz"] = found[found.size() / 2];  // the median over cells (upper of two middles)
  out["dominant_frequency_range_hz"] = {found.front(), found.back()};
  return out;
}

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json spiral_json(const SpiralMeasures& m) {
  return {{"id", m.id}, {"chirality", m.chirality}, {"birth_ms", m.birth_ms}, {"lifetime_ms", m.lifetime_ms},
          {"rotations", m.rotations}, {"period_ms", number_or_null(m.period_ms)}, {"rotor", m.rotor},
          {"x_mm", m.x_mm}, {"y_mm", m.y_mm}, {"drift_mm", m.drift_mm},
          {"drift_speed_mm_per_s", number_or_null(m.drift_speed_mm_per_s)},
          {"meander_extent_mm", m.meander_extent_mm}, {"meander_area_mm2", m.meander_area_mm2}};
}

// Each track's spiral measures, the PS density and the rotor time, for
// summary.json (docs/topics/arrhythmia.md "Spiral measures", "Drivers"); their
// CSV files into dir unless it is empty.
json spiral_summary(const Tissue& tissue, const VoltageFrames& frames, const SingularityTracker& tracker,
                    const std::vector<std::vector<double>>& activations, const ReentrySettings& s,
                    const std::filesystem::path& dir, ReentryMaps* maps) {
  std::vector<SpiralMeasures> spirals;
  for (const auto& track : tracker.tracks())
    spirals.push_back(spiral_measures(track, rotation_period_ms(track, tissue, activations)));
  const std::size_t delay = static_cast<std::size_t>(std::llround(s.tau_ms / s.every_ms));
  const std::vector<double> searched(frames.t_ms.begin() + std::min(delay, frames.count()), frames.t_ms.end());
  const auto b = tissue.bounds_um();
  const PsDensityGrid grid =
      ps_density(tracker.tracks(), {b[0] / 1000, b[1] / 1000, b[2] / 1000, b[3] / 1000}, s.ps_density_bin_mm, s.every_ms);
  if (!dir.empty()) {
    write_spiral_measures_csv(dir / "phase_singularity_tracks.csv", spirals);
    write_ps_density_csv(dir / "phase_singularity_density.csv", grid);
  }
  if (maps) maps->ps_density_per_cm2 = grid.per_cell_per_cm2(tissue);
  // The longest-lived track, the first of equal lives.
  const SpiralMeasures* longest = nullptr;
  for (const auto& m : spirals)
    if (!longest || m.lifetime_ms > longest->lifetime_ms) longest = &m;
  double ps_seconds = 0, densest = 0;
  for (double x : grid.ps_seconds) ps_seconds += x, densest = std::max(densest, x / grid.bin_area_cm2());
  return {{"longest_track", longest ? spiral_json(*longest) : json(nullptr)},
          {"rotors", std::count_if(spirals.begin(), spirals.end(), [](const auto& m) { return m.rotor; })},
          {"rotor_time_fraction", number_or_null(rotor_time_fraction(spirals, searched))},
          {"phase_singularity_seconds", ps_seconds},
          {"ps_density_bin_mm", s.ps_density_bin_mm},
          {"ps_density_max_per_cm2", densest}};
}

// The clinical band's dominant frequency: its median over cells and the highest site.
json clinical_summary(const Tissue& tissue, const DominantFrequencies& df, const ReentrySettings& s) {
  const json median = dominant_frequency_summary(df);
  const HighestFrequencySite site = highest_frequency_site(tissue, df.per_cell_hz);
  return {{"clinical_band_hz", {s.clinical_f_min_hz, s.clinical_f_max_hz}},
          {"clinical_dominant_frequency_hz", median["dominant_frequency_hz"]},
          {"clinical_dominant_frequency_range_hz", median["dominant_frequency_range_hz"]},
          {"highest_dominant_frequency",
           site.cells == 0 ? json(nullptr)
                           : json{{"frequency_hz", site.frequency_hz}, {"cells", site.cells},
                                  {"x_mm", site.x_mm}, {"y_mm", site.y_mm}}}};
}
}  // namespace

json analyse_reentry(const Tissue& tissue, const VoltageFrames& frames, const ReentrySettings& s,
                     const std::vector<double>& onsets, const std::vector<BeatBiomarkers>& beats,
                     const std::filesystem::path& dir, ReentryMaps* maps, const StretchFrames* stretch) {
  if (stretch) check_same_times(frames, *stretch);
  const SingularityTracker tracker = track_singularities(tissue, frames, s, dir, stretch);
  double longest_ms = 0;
  for (const auto& track : tracker.tracks()) longest_ms = std::max(longest_ms, track.death_ms - track.birth_ms);

  const double last_onset = onsets.empty() ? 0.0 : onsets.back();
  const auto activations = activation_times(frames, s.V_star_mV);
  const auto [last_activation, most] = activations_after(activations, last_onset);
  const bool active = std::isfinite(last_activation);
  const double duration = active ? std::max(0.0, last_activation - last_onset) : 0.0;
  const json cycle = onsets.size() >= 2 ? json(onsets.back() - onsets[onsets.size() - 2]) : json(nullptr);

  json out = {{"detected", !cycle.is_null() && duration > cycle.get<double>()},
              {"duration_ms", duration},
              {"cycle_length_ms", cycle},
              {"last_stimulus_ms", onsets.empty() ? json(nullptr) : json(last_onset)},
              {"last_activation_ms", active ? json(last_activation) : json(nullptr)},
              {"activations_after_last_stimulus_max", most},
              {"phase_singularities_max", tracker.max_per_frame()},
              {"phase_singularities_tracked", tracker.tracks().size()},
              {"longest_phase_singularity_ms", longest_ms},
              {"samples", frames.count()},
              {"every_ms", s.every_ms},
              {"tau_ms", s.tau_ms},
              {"V_star_mV", s.V_star_mV}};
  out.update(spiral_summary(tissue, frames, tracker, activations, s, dir, maps));
  auto df = dominant_frequencies(frames.values, frames.cells, frames.count(), s.every_ms,
                                 {{s.f_min_hz, s.f_max_hz}, {s.clinical_f_min_hz, s.clinical_f_max_hz}});
  out.update(dominant_frequency_summary(df[0]));
  out.update(clinical_summary(tissue, df[1], s));
  out["unreached_fraction_per_beat"] = unreached_fractions(beats);
  std::vector<bool> excitable(tissue.cell_count());
  for (std::size_t c = 0; c < excitable.size(); ++c) excitable[c] = tissue.type[c] == CellType::myocyte;
  auto per_beat = assign_beats(activations, onsets, excitable);
  out.update(beats_summary(per_beat));
  if (maps) {
    maps->beats = std::move(per_beat);
    maps->dominant_frequency_hz = std::move(df[0].per_cell_hz);
    maps->clinical_dominant_frequency_hz = std::move(df[1].per_cell_hz);
    maps->tracks = tracker.tracks();
  }
  return out;
}

}  // namespace fibrodem
