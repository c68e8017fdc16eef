#include "measure/conduction_velocity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fibrodem {

std::optional<ConductionFit> fit_conduction_velocity(const std::vector<ConductionSample>& cells,
                                                     double margin_fraction, int minimum_cells) {
  // The stimulated region along the fibre, and which way the wave runs.
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
  // Distance from the stimulated region towards the farther tissue edge.
  const bool downwards = (stim_lo - lo) > (hi - stim_hi);
  const double length = downwards ? stim_lo - lo : hi - stim_hi;
  if (length <= 0) return std::nullopt;
  ConductionFit fit;
  fit.from_um = margin_fraction * length;
  fit.to_um = (1 - margin_fraction) * length;

  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (const auto& c : cells) {
    if (c.stimulated || !c.activated) continue;
    const double d = downwards ? stim_lo - c.position_um : c.position_um - stim_hi;
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
