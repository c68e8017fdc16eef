#include "measure/conduction_velocity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrodem {

namespace {

// Which way the wave runs from the stimulated region, and its length to the
// farther tissue edge.
struct Path {
  bool downwards = false;
  double stim_lo = 0, stim_hi = 0, length = 0;
  double distance(double position_um) const { return downwards ? stim_lo - position_um : position_um - stim_hi; }
};

std::optional<Path> wave_path(const std::vector<ConductionSample>& cells) {
  double stim_lo = std::numeric_limits<double>::infinity(), stim_hi = -stim_lo;
  double lo = stim_lo, hi = -stim_lo;
  for (const auto& c : cells) {
    lo = std::min(lo, c.position_um);
    hi = std::max(hi, c.position_um);
    if (c.stimulated) {
      stim_lo = std::min(stim_lo, c.position_um);
      stim_hi = std::max(stim_hi, c.position_um);
    }
  }
  if (!std::isfinite(stim_lo) || !(hi > lo)) return std::nullopt;
  Path p;
  p.downwards = (stim_lo - lo) > (hi - stim_hi);
  p.stim_lo = stim_lo;
  p.stim_hi = stim_hi;
  p.length = p.downwards ? stim_lo - lo : hi - stim_hi;
  if (p.length <= 0) return std::nullopt;
  return p;
}

// The stretch of the path both measurements use: its length less a margin
// at each end (the stimulated region's edge, the far tissue edge).
ConductionFit measured_stretch(const Path& path, double margin_fraction) {
  ConductionFit fit;
  fit.from_um = margin_fraction * path.length;
  fit.to_um = (1 - margin_fraction) * path.length;
  return fit;
}

}  // namespace

std::optional<ConductionFit> transit_conduction_velocity(const std::vector<ConductionSample>& cells,
                                                         double margin_fraction, double band_fraction) {
  const auto path = wave_path(cells);
  if (!path) return std::nullopt;
  ConductionFit fit = measured_stretch(*path, margin_fraction);
  const double band = band_fraction * path->length;
  double n_near = 0, d_near = 0, t_near = 0, n_far = 0, d_far = 0, t_far = 0;
  for (const auto& c : cells) {
    if (c.stimulated || !c.activated) continue;
    const double d = path->distance(c.position_um);
    if (d >= fit.from_um && d <= fit.from_um + band) {
      n_near += 1;
      d_near += d;
      t_near += c.activation_ms;
    } else if (d <= fit.to_um && d >= fit.to_um - band) {
      n_far += 1;
      d_far += d;
      t_far += c.activation_ms;
    }
  }
  fit.cells_used = static_cast<int>(n_near + n_far);
  if (n_near == 0 || n_far == 0) return std::nullopt;  // the wave did not reach the far band
  const double distance_um = d_far / n_far - d_near / n_near, transit_ms = t_far / n_far - t_near / n_near;
  if (!(distance_um > 0) || !(transit_ms > 0)) return std::nullopt;
  fit.cv_cm_per_s = 0.1 * distance_um / transit_ms;  // 1 um/ms = 0.1 cm/s
  fit.r_squared = std::numeric_limits<double>::quiet_NaN();
  return fit;
}

std::optional<ConductionFit> fit_conduction_velocity(const std::vector<ConductionSample>& cells,
                                                     double margin_fraction, int minimum_cells) {
  const auto path = wave_path(cells);
  if (!path) return std::nullopt;
  ConductionFit fit = measured_stretch(*path, margin_fraction);

  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (const auto& c : cells) {
    if (c.stimulated || !c.activated) continue;
    const double d = path->distance(c.position_um);
    if (d < fit.from_um || d > fit.to_um) continue;
    n += 1;
    sx += d;
    sy += c.activation_ms;
    sxx += d * d;
    sxy += d * c.activation_ms;
    syy += c.activation_ms * c.activation_ms;
  }
  fit.cells_used = static_cast<int>(n);
  if (fit.cells_used < minimum_cells) return std::nullopt;
  const double vxx = sxx - sx * sx / n, vxy = sxy - sx * sy / n, vyy = syy - sy * sy / n;
  if (vxx <= 0 || vxy <= 0) return std::nullopt;  // no spread, or no propagation away from the stimulus
  const double slope_ms_per_um = vxy / vxx;
  fit.cv_cm_per_s = 0.1 / slope_ms_per_um;  // 1 um/ms = 0.1 cm/s
  fit.r_squared = vyy > 0 ? vxy * vxy / (vxx * vyy) : 1.0;
  return fit;
}

}  // namespace fibrodem
