#include "measure/phase_singularities.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace fibrodem {

double embedding_phase(double V_mV, double V_delayed_mV, double V_star_mV) {
  return std::atan2(V_delayed_mV - V_star_mV, V_mV - V_star_mV);
}

double wrap_phase(double d) {
  constexpr double two_pi = 2 * std::numbers::pi;
  d = std::fmod(d, two_pi);  // (-2 pi, 2 pi)
  if (d > std::numbers::pi) d -= two_pi;
  else if (d <= -std::numbers::pi) d += two_pi;
  return d;
}

namespace {
// The phase's turns around a closed loop (sum of wrapped differences / 2 pi); NaN if a phase is.
double turns_around(std::span<const int> loop, const std::vector<double>& phase) {
  double turn = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const double a = phase[loop[i]], b = phase[loop[(i + 1) % loop.size()]];
    if (!std::isfinite(a) || !std::isfinite(b)) return std::numeric_limits<double>::quiet_NaN();
    turn += wrap_phase(b - a);
  }
  return turn / (2 * std::numbers::pi);
}

int rounded(double turns) { return std::isfinite(turns) ? static_cast<int>(std::lround(turns)) : 0; }
}  // namespace

int loop_charge(std::span<const int> loop, const std::vector<double>& phase) {
  return rounded(turns_around(loop, phase));
}

int triangle_charge(const std::array<int, 3>& t, const std::vector<double>& phase) {
  return loop_charge(std::span<const int>(t), phase);
}

int hole_charge(const CellHole& hole, const std::vector<double>& phase) {
  // Each loop's winding is a whole number of turns up to rounding: rounded
  // loop by loop, their difference is one too.
  const double rim = turns_around(hole.rim, phase);
  if (!std::isfinite(rim)) return 0;
  int charge = rounded(rim);
  for (const auto& island : hole.islands) {
    const double turns = turns_around(island, phase);
    if (!std::isfinite(turns)) return 0;
    charge -= rounded(turns);
  }
  return charge;
}

std::vector<PhaseSingularity> find_phase_singularities(const Tissue& tissue,
                                                       const std::vector<std::array<int, 3>>& triangles,
                                                       const std::vector<double>& phase_rad,
                                                       const std::vector<CellHole>& holes) {
  std::vector<PhaseSingularity> found;
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    const int charge = triangle_charge(triangles[k], phase_rad);
    if (charge != 1 && charge != -1) continue;
    const auto& t = triangles[k];
    PhaseSingularity ps;
    ps.x_mm = (tissue.x_um[t[0]] + tissue.x_um[t[1]] + tissue.x_um[t[2]]) / 3000.0;
    ps.y_mm = (tissue.y_um[t[0]] + tissue.y_um[t[1]] + tissue.y_um[t[2]]) / 3000.0;
    ps.chirality = charge;
    ps.triangle = static_cast<int>(k);
    found.push_back(ps);
  }
  for (std::size_t h = 0; h < holes.size(); ++h) {
    const int charge = hole_charge(holes[h], phase_rad);
    PhaseSingularity ps;
    ps.x_mm = holes[h].x_mm, ps.y_mm = holes[h].y_mm;
    ps.reach_mm = holes[h].reach_mm;
    ps.chirality = charge > 0 ? 1 : -1;
    ps.hole = static_cast<int>(h);
    for (int n = 0; n < std::abs(charge); ++n) found.push_back(ps);
  }
  return found;
}

std::span<const int> cells_around(const PhaseSingularity& ps, const std::vector<std::array<int, 3>>& triangles,
                                  const std::vector<CellHole>& holes) {
  if (ps.hole >= 0) return holes[static_cast<std::size_t>(ps.hole)].rim;
  return triangles[static_cast<std::size_t>(ps.triangle)];
}

}  // namespace fibrodem
