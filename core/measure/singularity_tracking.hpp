// Phase singularities followed from frame to frame: each PS of a frame is
// linked to the nearest PS of the same chirality in the previous frame within
// link_mm (pairs taken closest first, each PS linked at most once); a PS
// with no such partner is born, one left without a successor has died.
#pragma once

#include <vector>

#include "measure/phase_singularities.hpp"

namespace fibrodem {

struct SingularityTrack {
  int id = 0;        // 0, 1, ... in order of birth
  int chirality = 0;
  double birth_ms = 0;
  double death_ms = 0;  // the last frame it was seen in
  bool alive = true;    // seen in the latest frame
  struct Point {
    double t_ms, x_mm, y_mm;
    double reach_mm = 0;  // PhaseSingularity::reach_mm
  };
  std::vector<Point> trajectory;
};

class SingularityTracker {
 public:
  explicit SingularityTracker(double link_mm) : link_mm_(link_mm) {}

  // The PS of the frame at t; returns the id of each, in the order given.
  std::vector<int> add_frame(double t_ms, const std::vector<PhaseSingularity>& found);

  const std::vector<SingularityTrack>& tracks() const { return tracks_; }
  // The most PS seen in one frame.
  int max_per_frame() const { return max_per_frame_; }

 private:
  double link_mm_;
  std::vector<SingularityTrack> tracks_;
  std::vector<int> alive_;  // ids seen in the latest frame
  int max_per_frame_ = 0;
};

}  // namespace fibrodem
