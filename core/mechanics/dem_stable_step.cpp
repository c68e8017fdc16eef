// The DEM's stable step (dem_solver.hpp, "Stable step"): the critical step of
// each free body on its contacts' stiffness, the least of them, with the
// spec's safety factor.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {
// Each contact's stiffness on its two bodies (in parallel), summed per body
// in contact order (body_contacts_), the bodies' masses scaled for them
// (dem_mass_scaling.cpp), then the smallest critical step.
void DemSolver::compute_stable_step() {
  const std::size_t nbonds = bonds_.size(), n = nbonds + contacts_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < n; ++c) {
    const BondSet& set = c < nbonds ? bonds_ : contacts_;
    const std::size_t k = c < nbonds ? c : c - nbonds;
    const int p = set.p[k], q = set.q[k];
    const double kn = law_->stable_step_stiffness(set.kn[k], false);
    const double ks = law_->stable_step_stiffness(set.ks[k], true);
    const double dx = px_[q] - px_[p], dy = py_[q] - py_[p];
    const double d = std::hypot(dx, dy);
    const double nx = d > 0 ? dx / d : 1.0, ny = d > 0 ? dy / d : 0.0;
    const int bp = pbody_[p], bq = pbody_[q];
    const double gap = d - br_[bp] - br_[bq];
    const double cx = px_[p] + (br_[bp] + 0.5 * gap) * nx, cy = py_[p] + (br_[bp] + 0.5 * gap) * ny;
    contact_kt_[c] = kn + ks;
    for (int end : {0, 1}) {
      const int b = end ? bq : bp;
      const double rx = cx - bx_[b], ry = cy - by_[b];
      const double rn = rx * ny - ry * nx;    // rho x n
      const double rt = rx * nx + ry * ny;    // rho x t, t = (-ny, nx)
      contact_kr_[2 * c + end] = kn * rn * rn + ks * rt * rt + set.kb[k];
    }
  }
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    double kt = 0, kr = 0;
    for (const int* e = body_contacts_.begin(b); e != body_contacts_.end(b); ++e) {
      kt += contact_kt_[ContactIncidence::contact(*e)];
      kr += contact_kr_[*e];
    }
    body_kt_[b] = kt;
    body_kr_[b] = kr;
  }
  scale_masses();
  // (Multirate: the heavy and the light bodies' least critical steps apart.)
  double tmin = std::numeric_limits<double>::infinity(), tmin_light = tmin, tmin_clump = tmin;
  const bool multirate = !blight_.empty();
#pragma omp parallel for schedule(static) reduction(min : tmin, tmin_light, tmin_clump)
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    if (bfixed_[b]) continue;
    double t = std::numeric_limits<double>::infinity();
    if (body_kt_[b] > 0) t = std::min(t, std::sqrt(mass_[b] / body_kt_[b]));
    if (body_kr_[b] > 0) t = std::min(t, std::sqrt(inertia_[b] / body_kr_[b]));
    if (multirate && blight_[b])
      tmin_light = std::min(tmin_light, t);
    else
      tmin = std::min(tmin, t);
    if (bclump_[b]) tmin_clump = std::min(tmin_clump, t);
  }
  // Bodies without contacts have no stiffness limit: cap the step (PFC also
  // bounds it kinematically), so that a lone contracting clump still moves and
  // free bodies cannot cross a contact skin between two checks of the list.
  stable_step_ms_ = std::min(spec_.safety_factor * tmin * 1e3, kLongestStep_ms);
  if (multirate) fit_multirate_steps(tmin, tmin_clump, tmin_light);
}

}  // namespace fibrodem
