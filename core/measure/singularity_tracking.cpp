#include "measure/singularity_tracking.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace fibrodem {

std::vector<int> SingularityTracker::add_frame(double t_ms, const std::vector<PhaseSingularity>& found) {
  // Every (distance, previous, new) pair of one chirality within reach, closest first.
  std::vector<std::tuple<double, int, std::size_t>> pairs;
  for (int id : alive_) {
    const auto& last = tracks_[id].trajectory.back();
    for (std::size_t k = 0; k < found.size(); ++k) {
      if (found[k].chirality != tracks_[id].chirality) continue;
      const double d = std::hypot(found[k].x_mm - last.x_mm, found[k].y_mm - last.y_mm);
      if (d <= link_mm_) pairs.emplace_back(d, id, k);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> ids(found.size(), -1);
  std::vector<bool> continued(tracks_.size(), false);
  for (const auto& [d, id, k] : pairs) {
    if (ids[k] >= 0 || continued[id]) continue;
    ids[k] = id;
    continued[id] = true;
  }
  for (int id : alive_)
    if (!continued[id]) tracks_[id].alive = false;
  alive_.clear();
  for (std::size_t k = 0; k < found.size(); ++k) {
    if (ids[k] < 0) {
      ids[k] = static_cast<int>(tracks_.size());
      SingularityTrack track;
      track.id = ids[k];
      track.chirality = found[k].chirality;
      track.birth_ms = t_ms;
      tracks_.push_back(track);
    }
    SingularityTrack& track = tracks_[ids[k]];
    track.trajectory.push_back({t_ms, found[k].x_mm, found[k].y_mm, found[k].reach_mm});
    track.death_ms = t_ms;
    alive_.push_back(ids[k]);
  }
  max_per_frame_ = std::max(max_per_frame_, static_cast<int>(found.size()));
  return ids;
}

}  // namespace fibrodem
