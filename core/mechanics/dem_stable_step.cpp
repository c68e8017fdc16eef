// The DEM's stable step (dem_solver.hpp, "Stable step"): the critical step of
// each free body on its contacts' stiffness, the least of them, with the
// spec's safety factor.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {

// Each contact's stiffness on its two bodies (in parallel), summed per body
// in contact order (body_contacts).
void DemContacts::stiffness_on_bodies(const DemBodies& bodies) {
  const std::vector<double> &px = bodies.px, &py = bodies.py, &br = bodies.br;
  const std::size_t nbonds = bonds.size(), n = nbonds + contacts.size();
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < n; ++c) {
    const BondSet& set = c < nbonds ? bonds : contacts;
    const std::size_t k = c < nbonds ? c : c - nbonds;
    const int p = set.p[k], q = set.q[k];
    const double kn = law_->stable_step_stiffness(set.kn[k], false);
    const double ks = law_->stable_step_stiffness(set.ks[k], true);
    const double dx = px[q] - px[p], dy = py[q] - py[p];
    const double d = std::hypot(dx, dy);
    const double nx = d > 0 ? dx / d : 1.0, ny = d > 0 ? dy / d : 0.0;
    const int bp = bodies.pbody[p], bq = bodies.pbody[q];
    const double gap = d - br[bp] - br[bq];
    const double cx = px[p] + (br[bp] + 0.5 * gap) * nx, cy = py[p] + (br[bp] + 0.5 * gap) * ny;
    contact_kt[c] = kn + ks;
    for (int end : {0, 1}) {
      const int b = end ? bq : bp;
      const double rx = cx - bodies.bx[b], ry = cy - bodies.by[b];
      const double rn = rx * ny - ry * nx;  // rho x n
      const double rt = rx * nx + ry * ny;  // rho x t, t = (-ny, nx)
      contact_kr[2 * c + end] = kn * rn * rn + ks * rt * rt + set.kb[k];
    }
  }
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    double kt = 0, kr = 0;
    for (const int* e = body_contacts.begin(b); e != body_contacts.end(b); ++e) {
      kt += contact_kt[ContactIncidence::contact(*e)];
      kr += contact_kr[*e];
    }
    body_kt[b] = kt;
    body_kr[b] = kr;
  }
}

// The stiffness on each body, the bodies' masses scaled for it
// (dem_mass_scaling.hpp), then the smallest critical step.
void DemSolver::compute_stable_step() {
  contacts_.stiffness_on_bodies(bodies_);
  mass_scaling_.apply(bodies_, contacts_.body_kt, contacts_.body_kr);
  const DemBodies& B = bodies_;
  const std::vector<double> &body_kt = contacts_.body_kt, &body_kr = contacts_.body_kr;
  // (Multirate: the heavy and the light bodies' least critical steps apart.)
  double tmin = std::numeric_limits<double>::infinity(), tmin_light = tmin, tmin_clump = tmin;
  const bool multirate = multirate_.on();
  const std::vector<std::uint8_t>& light = multirate_.light();
#pragma omp parallel for schedule(static) reduction(min : tmin, tmin_light, tmin_clump)
  for (std::size_t b = 0; b < B.size(); ++b) {
    if (B.bfixed[b]) continue;
    const double t = critical_step_s(B.mass[b], B.inertia[b], body_kt[b], body_kr[b]);
    if (multirate && light[b])
      tmin_light = std::min(tmin_light, t);
    else
      tmin = std::min(tmin, t);
    if (B.bclump[b]) tmin_clump = std::min(tmin_clump, t);
  }
  // Bodies without contacts have no stiffness limit: cap the step (PFC also
  // bounds it kinematically), so that a lone contracting clump still moves and
  // free bodies cannot cross a contact skin between two checks of the list.
  stable_step_ms_ = std::min(spec_.safety_factor * tmin * 1e3, kLongestStep_ms);
  if (multirate)
    multirate_.fit_steps(stable_step_ms_, spec_.safety_factor, tmin, tmin_clump, tmin_light, bodies_, contacts_);
}

}  // namespace fibrodem
