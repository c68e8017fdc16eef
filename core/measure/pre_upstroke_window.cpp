#include "measure/pre_upstroke_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrodem {

namespace {
constexpr int kBucketsPerWindow = 8;
}

PreUpstrokeWindow::PreUpstrokeWindow(std::size_t cells, double window_ms, double gap_ms)
    : cells_(cells), window_ms_(window_ms), gap_ms_(gap_ms), bucket_ms_(window_ms / kBucketsPerWindow) {
  // The window, the gap, a bucket of alignment and two windows of lag (the
  // time from the activation to the step that finds it is one step).
  ring_ = static_cast<long long>(std::ceil(gap_ms / bucket_ms_)) + 3 * kBucketsPerWindow + 2;
  integral_.assign(static_cast<std::size_t>(ring_) * cells_, 0.0);
}

void PreUpstrokeWindow::advance_to(long long bucket) {
  if (newest_ < 0) newest_ = bucket - 1;
  // A step longer than the ring clears every row (at most ring_ of them).
  for (long long k = std::max(newest_ + 1, bucket - ring_ + 1); k <= bucket; ++k)
    std::fill_n(row(k), cells_, 0.0);
  newest_ = std::max(newest_, bucket);
}

void PreUpstrokeWindow::add_step(double t_old, double t_new, const double* V_old, const double* V_new) {
  if (!(t_new > t_old)) return;
  if (newest_ < 0) t_first_ = t_old;
  const double h = t_new - t_old;
  // The step split at the bucket boundaries: each piece a trapezoid of the
  // linear V between the step's ends.
  for (double a = t_old; a < t_new;) {
    const long long bucket = static_cast<long long>(std::floor(a / bucket_ms_ + 1e-12));
    const double b = std::min(t_new, (bucket + 1) * bucket_ms_);
    advance_to(bucket);
    double* r = row(bucket);
    const double wa = (a - t_old) / h, wb = (b - t_old) / h, width = b - a;
    for (std::size_t c = 0; c < cells_; ++c) {
      const double dv = V_new[c] - V_old[c];
      r[c] += 0.5 * ((V_old[c] + wa * dv) + (V_old[c] + wb * dv)) * width;
    }
    a = b;
  }
}

double PreUpstrokeWindow::mean_before(std::size_t c, double t_act_ms) const {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The window's last bucket ends at the boundary at or before t_act - gap.
  const long long end = static_cast<long long>(std::floor((t_act_ms - gap_ms_) / bucket_ms_ + 1e-12));
  const long long first = end - kBucketsPerWindow;
  if (newest_ < 0 || first * bucket_ms_ < t_first_ - 1e-9 || first <= newest_ - ring_ || end - 1 > newest_)
    return nan;
  double sum = 0;
  for (long long k = first; k < end; ++k) sum += row(k)[c];
  return sum / window_ms_;
}

void PreUpstrokeWindow::save(CheckpointFields& fields) const {
  fields.put(kIntegralField, integral_);
  fields.put_integer("biomarkers.pre_upstroke.newest", newest_);
  fields.put("biomarkers.pre_upstroke.t_first", t_first_);
}

void PreUpstrokeWindow::load(const CheckpointFields& fields) {
  if (!fields.has(kIntegralField))
    throw CheckpointError("it was written without output.biomarkers.rmp \"pre_upstroke\" (no window of V to resume)");
  std::vector<double> integral(integral_.size());
  fields.read_into(kIntegralField, integral);
  integral_ = std::move(integral);
  newest_ = fields.integer("biomarkers.pre_upstroke.newest");
  t_first_ = fields.number("biomarkers.pre_upstroke.t_first");
}

}  // namespace fibrodem
