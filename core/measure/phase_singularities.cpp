#include "measure/phase_singularities.hpp"

#include <cmath>
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

int triangle_charge(const std::array<int, 3>& t, const std::vector<double>& phase) {
  const double pa = phase[t[0]], pb = phase[t[1]], pc = phase[t[2]];
  if (!std::isfinite(pa) || !std::isfinite(pb) || !std::isfinite(pc)) return 0;
  const double turn = wrap_phase(pb - pa) + wrap_phase(pc - pb) + wrap_phase(pa - pc);
  return static_cast<int>(std::lround(turn / (2 * std::numbers::pi)));
}

std::vector<PhaseSingularity> find_phase_singularities(const Tissue& tissue,
                                                       const std::vector<std::array<int, 3>>& triangles,
                                                       const std::vector<double>& phase_rad) {
  std::vector<PhaseSingularity> found;
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    const int charge = triangle_charge(triangles[k], phase_rad);
    if (charge != 1 && charge != -1) continue;
    const auto& t = triangles[k];
    found.push_back({(tissue.x_um[t[0]] + tissue.x_um[t[1]] + tissue.x_um[t[2]]) / 3000.0,
                     (tissue.y_um[t[0]] + tissue.y_um[t[1]] + tissue.y_um[t[2]]) / 3000.0, charge,
                     static_cast<int>(k)});
  }
  return found;
}

}  // namespace fibrodem
