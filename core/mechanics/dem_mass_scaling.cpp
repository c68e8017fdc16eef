// The DEM's mass scaling (dem_mass_scaling.hpp): PFC's density scaling for
// quasi-static loading (Itasca PFC 6, "Timestep Determination").
// A body's critical step is sqrt(m / kt) (and sqrt(I / kr)); the lightest,
// stiffest bodies (the interstitial tissue's 1-4 um fibroblast particles on
// 26 N/m bonds) set a step ~10x below the myocytes'. Giving each body below a
// target step H the mass kt H^2 lifts the step to H; H is the longest for
// which the mass and the inertia added are at most the fraction
// `mass_scaling` of the tissue's at the start. The tissue's own motion gets
// that much heavier: measured on the Fig. 3 interstitial twitch, its peak
// strain falls by ~0.8 f (docs/topics/mechanics.md), so f stays small.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mechanics/dem_mass_scaling.hpp"

namespace fibrodem {
namespace {

struct Added {
  double mass = 0, inertia = 0;
};

}  // namespace

// The target critical step H once, from the stiffness on each body at the
// start (body_kt, body_kr: the bonds and the contacts listed); then, with
// each contact list, every body's mass and inertia for H on its contacts
// now (contacts that come raise a body's, those that go lower it back,
// never below its density's). Bodies in index order: the same bits on any
// number of threads.
void DemMassScaling::apply(DemBodies& bodies, const std::vector<double>& body_kt, const std::vector<double>& body_kr) {
  if (!(f_ > 0)) return;
  if (!(target_step_s_ > 0)) target_step_s_ = target_step_s(bodies, body_kt, body_kr);
  const double h2 = target_step_s_ * target_step_s_;
  double total_mass = 0, total_inertia = 0;
  Added a;
  scaled_bodies_ = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    total_mass += bodies.density_mass[b];
    total_inertia += bodies.density_inertia[b];
    if (bodies.bfixed[b]) continue;
    const double m = std::max(bodies.density_mass[b], body_kt[b] * h2);
    const double i = std::max(bodies.density_inertia[b], body_kr[b] * h2);
    bodies.mass[b] = m;
    bodies.inertia[b] = i;
    bodies.inv_m[b] = 1 / m;
    bodies.inv_i[b] = 1 / i;
    if (m == bodies.density_mass[b] && i == bodies.density_inertia[b]) continue;
    ++scaled_bodies_;
    a.mass += m - bodies.density_mass[b];
    a.inertia += i - bodies.density_inertia[b];
  }
  added_mass_fraction_ = a.mass / total_mass;
  added_inertia_fraction_ = a.inertia / total_inertia;
}

// The longest critical step H [s] (the stable step is safety x H) for which
// the mass and the inertia the bodies below it need are at most f of the
// tissue's: bisection, the added mass and inertia growing with H.
double DemMassScaling::target_step_s(const DemBodies& bodies, const std::vector<double>& body_kt,
                                     const std::vector<double>& body_kr) const {
  const double f = f_;
  const std::size_t nb = bodies.size();
  double total_mass = 0, total_inertia = 0, h_low = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < nb; ++b) {
    total_mass += bodies.density_mass[b];
    total_inertia += bodies.density_inertia[b];
    if (bodies.bfixed[b]) continue;
    if (body_kt[b] > 0) h_low = std::min(h_low, std::sqrt(bodies.density_mass[b] / body_kt[b]));
    if (body_kr[b] > 0) h_low = std::min(h_low, std::sqrt(bodies.density_inertia[b] / body_kr[b]));
  }
  if (!std::isfinite(h_low)) return 0;  // no body has contacts: nothing to scale
  auto within = [&](double h) {
    Added a;
    for (std::size_t b = 0; b < nb; ++b) {
      if (bodies.bfixed[b]) continue;
      a.mass += std::max(0.0, body_kt[b] * h * h - bodies.density_mass[b]);
      a.inertia += std::max(0.0, body_kr[b] * h * h - bodies.density_inertia[b]);
    }
    return a.mass <= f * total_mass && a.inertia <= f * total_inertia;
  };
  double h_high = longest_s_;
  if (within(h_high)) return h_high;
  double lo = h_low;
  for (int k = 0; k < 200 && h_high - lo > 1e-12 * h_high; ++k) {
    const double mid = 0.5 * (lo + h_high);
    (within(mid) ? lo : h_high) = mid;
  }
  return lo;
}

}  // namespace fibrodem
