// The DEM's mass scaling (dem_solver.hpp, "Stable step"): PFC's density
// scaling for quasi-static loading (Itasca PFC 6, "Timestep Determination").
// A body's critical step is sqrt(m / kt) (and sqrt(I / kr)); the lightest,
// stiffest bodies (the interstitial tissue's 1-4 um fibroblast particles on
// 26 N/m bonds) set a step ~10x below the myocytes'. Giving each body below a
// target step H the mass kt H^2 lifts the step to H; H is the longest for
// which the mass and the inertia added are at most the fraction
// `mass_scaling` of the tissue's at the start. The tissue's own motion gets
// that much heavier: measured on the Fig. 3 interstitial twitch, its peak
// strain falls by ~0.8 f (docs/mechanics.md), so f stays small.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {
namespace {

struct Added {
  double mass = 0, inertia = 0;
};

}  // namespace

// The target critical step H once, from the stiffness on each body at the
// start (body_kt_, body_kr_: the bonds and the contacts listed); then, with
// each contact list, every body's mass and inertia for H on its contacts
// now (contacts that come raise a body's, those that go lower it back,
// never below its density's). Bodies in index order: the same bits on any
// number of threads.
void DemSolver::scale_masses() {
  const double f = spec_.mass_scaling;
  if (!(f > 0)) return;
  if (!(scaling_step_s_ > 0)) scaling_step_s_ = scaling_target_step_s(f);
  const double h2 = scaling_step_s_ * scaling_step_s_;
  double total_mass = 0, total_inertia = 0;
  Added a;
  scaled_bodies_ = 0;
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    total_mass += density_mass_[b];
    total_inertia += density_inertia_[b];
    if (bfixed_[b]) continue;
    const double m = std::max(density_mass_[b], body_kt_[b] * h2);
    const double i = std::max(density_inertia_[b], body_kr_[b] * h2);
    mass_[b] = m;
    inertia_[b] = i;
    inv_m_[b] = 1 / m;
    inv_i_[b] = 1 / i;
    if (m == density_mass_[b] && i == density_inertia_[b]) continue;
    ++scaled_bodies_;
    a.mass += m - density_mass_[b];
    a.inertia += i - density_inertia_[b];
  }
  added_mass_fraction_ = a.mass / total_mass;
  added_inertia_fraction_ = a.inertia / total_inertia;
}

// The longest critical step H [s] (the stable step is safety x H) for which
// the mass and the inertia the bodies below it need are at most f of the
// tissue's: bisection, the added mass and inertia growing with H.
double DemSolver::scaling_target_step_s(double f) const {
  const std::size_t nb = bx_.size();
  double total_mass = 0, total_inertia = 0, h_low = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < nb; ++b) {
    total_mass += density_mass_[b];
    total_inertia += density_inertia_[b];
    if (bfixed_[b]) continue;
    if (body_kt_[b] > 0) h_low = std::min(h_low, std::sqrt(density_mass_[b] / body_kt_[b]));
    if (body_kr_[b] > 0) h_low = std::min(h_low, std::sqrt(density_inertia_[b] / body_kr_[b]));
  }
  if (!std::isfinite(h_low)) return 0;  // no body has contacts: nothing to scale
  auto within = [&](double h) {
    Added a;
    for (std::size_t b = 0; b < nb; ++b) {
      if (bfixed_[b]) continue;
      a.mass += std::max(0.0, body_kt_[b] * h * h - density_mass_[b]);
      a.inertia += std::max(0.0, body_kr_[b] * h * h - density_inertia_[b]);
    }
    return a.mass <= f * total_mass && a.inertia <= f * total_inertia;
  };
  double h_high = kLongestStep_ms * 1e-3 / spec_.safety_factor;
  if (within(h_high)) return h_high;
  double lo = h_low;
  for (int k = 0; k < 200 && h_high - lo > 1e-12 * h_high; ++k) {
    const double mid = 0.5 * (lo + h_high);
    (within(mid) ? lo : h_high) = mid;
  }
  return lo;
}

}  // namespace fibrodem
