// A small tissue's DEM driven through a twitch, and the acceptance bounds of
// a faster mechanics scheme against the native one (mass scaling,
// tests/mechanics/test_dem_mass_scaling.cpp; multirate, tests/mechanics/test_dem_multirate.cpp):
// peak eps_xx and eps_yy within 1 %, the strain's time course within 2 % RMS
// of the peak (docs/topics/mechanics.md).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mechanics/dem_solver.hpp"
#include "support/scenes.hpp"

namespace fibrodem::test {

using testing::build_tissue;

// The small tissues of both layouts the schemes are checked on.
inline Tissue small_in_series_tissue() {
  return build_tissue({{"builder", "in_series"}, {"width_mm", 0.2}, {"height_mm", 0.6}, {"fm_ratio", 0.41}}, 3);
}
inline Tissue small_interstitial_tissue() {
  return build_tissue({{"builder", "interstitial"}, {"width_mm", 0.3}, {"height_mm", 1.2}}, 2);
}

// A twitch of every myocyte's length: lambda = 1 - 0.1 (t/tau) e^(1 - t/tau),
// shortest (0.9) at tau = 40 ms, near rest again by 150 ms (a Rice twitch's shape).
inline double twitch_lambda(double t_ms) {
  const double tau = 40;
  return 1 - 0.1 * (t_ms / tau) * std::exp(1 - t_ms / tau);
}

// Sets every myocyte's length ratio for the end of the next step and takes it.
inline void twitch_step(const Tissue& t, DemSolver& dem, std::vector<double>& ratio) {
  const double t_end = dem.time_ms() + dem.step_ms();
  for (std::size_t c = 0; c < t.cell_count(); ++c)
    if (t.type[c] == CellType::myocyte) ratio[c] = twitch_lambda(t_end);
  dem.set_cell_length_ratios(ratio);
  dem.step(dem.step_ms());
}

struct StrainCourse {
  std::vector<double> xx, yy;  // every 0.5 ms from 0.5 ms, interpolated between steps
  double step_ms = 0;
  std::size_t steps = 0, substeps = 0, light_bodies = 0;
};

// The strain's course of `dem` (built for t) through the twitch.
inline StrainCourse twitch_of(const Tissue& t, DemSolver& dem, double until_ms) {
  StrainCourse out;
  out.step_ms = dem.step_ms();
  std::vector<double> ratio(t.cell_count(), 1.0);
  double t_prev = 0;
  std::array<double, 3> e_prev{0, 0, 0};
  double sample = 0.5;
  while (sample <= until_ms) {
    twitch_step(t, dem, ratio);
    const auto e = dem.strain();
    for (; sample <= dem.time_ms() && sample <= until_ms; sample += 0.5) {
      const double w = (sample - t_prev) / (dem.time_ms() - t_prev);
      out.xx.push_back(e_prev[0] + w * (e[0] - e_prev[0]));
      out.yy.push_back(e_prev[1] + w * (e[1] - e_prev[1]));
    }
    t_prev = dem.time_ms();
    e_prev = e;
  }
  out.steps = dem.steps();
  out.substeps = dem.substeps();
  out.light_bodies = dem.light_bodies();
  return out;
}

inline StrainCourse twitch(const Tissue& t, const DemSpec& spec, double until_ms) {
  DemSolver dem(t, spec);
  const StrainCourse out = twitch_of(t, dem, until_ms);
  MESSAGE(dem.report());
  return out;
}

inline double peak(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
}

inline double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t k = 0; k < a.size(); ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

// The acceptance bounds: peaks within 1 %, course within 2 % RMS of the peak.
inline void check_within_bounds(const StrainCourse& run, const StrainCourse& native) {
  REQUIRE(run.xx.size() == native.xx.size());
  for (int k : {0, 1}) {
    const auto& s = k ? run.yy : run.xx;
    const auto& n = k ? native.yy : native.xx;
    const double p_native = peak(n), p_run = peak(s);
    const double peak_error = std::abs(p_run - p_native) / std::abs(p_native);
    const double rms = rms_difference(s, n) / std::abs(p_native);
    MESSAGE((k ? "eps_yy" : "eps_xx"), ": peak ", p_run, " against ", p_native, " native (", 100 * peak_error,
            " %), RMS difference ", 100 * rms, " % of the peak");
    CHECK(std::abs(p_native) > 0.02);  // the twitch did strain the tissue
    CHECK(peak_error < 0.01);
    CHECK(rms < 0.02);
  }
}

}  // namespace fibrodem::test
