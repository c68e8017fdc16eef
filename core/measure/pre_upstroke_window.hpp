// The pre-upstroke RMP (output.biomarkers.rmp "pre_upstroke"): per cell, the
// mean V over a window of window_ms that ends gap_ms before the cell's
// activation (its max dV/dt), instead of V at the stimulus onset. A far cell's
// V at the onset is its diastolic rest; just before its upstroke it may have
// been raised by the approaching front (electrotonic foot) or by a neighbour:
// this is the potential from which it actually fires.
//
// Kept without a history of samples per cell: the integral of V over fixed
// time buckets of window_ms / 8 on a global grid (one row of all cells per
// bucket, in a ring long enough for the window, the gap and two windows of
// lag), so each step adds one trapezoid per cell, and the window's mean is the
// sum of its 8 buckets divided by its length. The window is thereby aligned to
// that grid: it ends at the last bucket boundary at or before
// activation - gap_ms (at most window_ms / 8 earlier). NaN when the window
// starts before the first step recorded, or has left the ring.
#pragma once

#include <cstddef>
#include <vector>

#include "io/checkpoint_file.hpp"

namespace fibrodem {

class PreUpstrokeWindow {
 public:
  PreUpstrokeWindow(std::size_t cells, double window_ms, double gap_ms);

  // One step from t_old to t_new with V at both ends (linear in between).
  void add_step(double t_old, double t_new, const double* V_old, const double* V_new);
  // The mean V of cell c over the window before an activation at t_act_ms.
  double mean_before(std::size_t c, double t_act_ms) const;

  void save(CheckpointFields& fields) const;
  void load(const CheckpointFields& fields);
  // The field of the buckets' integrals, a row a bucket of one number a cell.
  static constexpr const char* kIntegralField = "biomarkers.pre_upstroke.integral";

 private:
  double* row(long long bucket) { return integral_.data() + static_cast<std::size_t>(bucket % ring_) * cells_; }
  const double* row(long long bucket) const {
    return integral_.data() + static_cast<std::size_t>(bucket % ring_) * cells_;
  }
  // Makes `bucket` the newest, clearing the rows it reuses.
  void advance_to(long long bucket);

  std::size_t cells_;
  double window_ms_, gap_ms_, bucket_ms_;
  long long ring_;
  std::vector<double> integral_;  // [ring_][cells_]: integral of V dt over each bucket [mV ms]
  long long newest_ = -1;         // the newest bucket written; -1: none yet
  double t_first_ = 0;            // the first time recorded
};

}  // namespace fibrodem
