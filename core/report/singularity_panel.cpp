#include "report/singularity_panel.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "report/trace_panels.hpp"

namespace fibrodem {

std::optional<PlotPanel> singularity_trajectories(const CsvTable& table) {
  const auto t = table.column("t_ms"), id = table.column("id"), x = table.column("x_mm"), y = table.column("y_mm"),
             chirality = table.column("chirality");
  if (!t || !id || !x || !y || !chirality || table.rows.empty()) return std::nullopt;
  const auto ts = table.numbers(*t), ids = table.numbers(*id), xs = table.numbers(*x), ys = table.numbers(*y),
             cs = table.numbers(*chirality);
  struct Track {
    PlotSeries series;
    double first = INFINITY, last = -INFINITY;
  };
  std::map<long long, Track> tracks;
  for (std::size_t r = 0; r < ids.size(); ++r) {
    if (!std::isfinite(ids[r])) continue;
    Track& track = tracks[std::llround(ids[r])];
    if (track.series.label.empty())
      track.series.label = "PS " + std::to_string(std::llround(ids[r])) + (cs[r] > 0 ? " (+1)" : " (-1)");
    track.series.x.push_back(xs[r]);
    track.series.y.push_back(ys[r]);
    track.series.markers = false;
    track.first = std::min(track.first, ts[r]);
    track.last = std::max(track.last, ts[r]);
  }
  std::vector<Track*> longest;
  for (auto& [k, track] : tracks) longest.push_back(&track);
  // Longest-lived first; equal lives in order of id (the map's order).
  std::stable_sort(longest.begin(), longest.end(),
                   [](const Track* a, const Track* b) { return a->last - a->first > b->last - b->first; });
  PlotPanel panel;
  panel.title = "Phase singularity trajectories (" + std::to_string(tracks.size()) + " tracked" +
                (tracks.size() > kMostSeriesPerPanel ? ", the " + std::to_string(kMostSeriesPerPanel) + " longest shown"
                                                     : std::string()) + ")";
  panel.x_label = "x [mm]";
  panel.y_label = "y [mm]";
  panel.log_x = panel.log_y = false;
  for (std::size_t k = 0; k < std::min(kMostSeriesPerPanel, longest.size()); ++k)
    panel.series.push_back(std::move(longest[k]->series));
  return panel;
}

}  // namespace fibrodem
