// Multirate DEM stepping (spec `multirate`; dem_solver.hpp, "Multirate";
// dem_multirate.hpp): the scheme's step.
//
// The stable step is set by the lightest, stiffest bodies: in interstitial
// tissue the 1-4 um fibroblast disks on 26 N/m bonds, ~10x below the
// myocyte clumps' critical step. Here the bodies whose own critical step is
// below every clump's (light: disks only) take n = ceil(H / h_light)
// substeps of h = H / n within each step H, the others (heavy: clumps and
// the disks as slow as they) one velocity Verlet step of H:
//
//   1. heavy bodies: half kick (force at t), drift to t + H, particles placed;
//   2. n times: light bodies' velocity Verlet substep of h; the particles of
//      heavy bodies that touch a light one placed on the straight line from
//      their place at t to that at t + H (their velocity: the step's
//      half-step velocity); the contacts that touch a light body (fast
//      contacts) evaluated; light bodies kicked; each heavy body's share of
//      those forces summed;
//   3. contacts between heavy bodies evaluated once, at t + H; each heavy
//      body's force is theirs plus the mean of its fast contacts' forces over
//      the n substeps; closing half kick.
//
// A fast contact's impulse h sum_j F_j goes to the light body in its
// substeps and to the heavy body as H x the mean: equal and opposite over a
// run, so momentum is kept (up to the half step by which the heavy body's
// share lags). This is the multiple-time-step idea of r-RESPA (Tuckerman,
// Berne & Martyna 1992, J Chem Phys 97:1990) with the split by bodies rather
// than by forces: r-RESPA gives every body the slow forces as impulses at the
// long step's ends and the fast ones each substep; here the heavy bodies move
// once per long step on the time average of the fast forces they feel (the
// fast force's impulse over H), and only the light bodies see them each
// substep, against heavy neighbours interpolated over the step.
//
// Every sum is per body in a fixed order: the same bits for any number of
// threads; nothing allocated per step.
#include <algorithm>
#include <cmath>

#include "mechanics/dem_multirate.hpp"
#include "mechanics/dem_step_inline.hpp"

namespace fibrodem {

// (Light bodies without contacts: a light step of 0, one substep.)
std::size_t DemMultirate::substeps_of(double dt_s, double light_step_s) {
  const double ratio = dt_s / light_step_s;
  return static_cast<std::size_t>(std::max(1.0, std::ceil(ratio * (1 - 1e-12))));
}

// Every body's pose at the step's start kept; the heavy ones' first half
// kick, drift and particles (their places at t + H kept for the substeps).
void DemMultirate::move_heavy_bodies(DemBodies& bodies, double dt_s) {
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < DemBodies::kStepParts; ++k)
    for (std::size_t b = heavy_part_first_body_[k]; b < heavy_part_first_body_[k + 1]; ++b) {
      bx_start_[b] = bodies.bx[b];
      by_start_[b] = bodies.by[b];
      br_start_[b] = bodies.br[b];
      if (light_[b]) continue;
      bodies.kick(b, 0.5 * dt_s);
      bodies.drift_and_reshape(b, dt_s);
      bodies.place_particles_of(b);
      for (int j = bodies.body_particle_start[b]; j < bodies.body_particle_start[b + 1]; ++j) {
        const auto i = static_cast<std::size_t>(bodies.body_particle[j]);
        px_end_[i] = bodies.px[i];
        py_end_[i] = bodies.py[i];
      }
    }
}

// Light body k's half kick and drift over a substep of h_s, and its
// particle placed: kick, drift_and_reshape and place_particles_of for a
// disk, whose particle sits at its centre and whose shape never changes.
[[gnu::always_inline]] inline void DemMultirate::move_light_disk(DemBodies& bodies, std::size_t k, double h_s) const {
  const auto b = static_cast<std::size_t>(light_bodies_[k]);
  const auto i = static_cast<std::size_t>(light_particle_[k]);
  bodies.kick(b, 0.5 * h_s);
  const double vx = bodies.bvx[b], vy = bodies.bvy[b], w = bodies.bw[b];
  bodies.bx[b] += vx * h_s;
  bodies.by[b] += vy * h_s;
  bodies.bth[b] += w * h_s;
  bodies.px[i] = bodies.bx[b];
  bodies.py[i] = bodies.by[b];
  bodies.pvx[i] = vx;
  bodies.pvy[i] = vy;
  bodies.pw[i] = w;
}

// Light body k's force and moment, its particle's contacts summed as
// sum_body sums them (all of a light body's contacts are fast; its
// particle's arm is 0), and its closing half kick over h_s.
[[gnu::always_inline]] inline void DemMultirate::sum_forces_and_kick_light_disk(DemBodies& bodies,
                                                                              const DemContacts& contacts,
                                                                              std::size_t k, double h_s) const {
  const auto b = static_cast<std::size_t>(light_bodies_[k]);
  const auto i = static_cast<std::size_t>(light_particle_[k]);
  double fx, fy, tq;  // (locals: references into bfx could alias the contacts' forces)
  contacts.sum_particle(i, kEveryContact, fx, fy, tq);
  bodies.bfx[b] = fx;
  bodies.bfy[b] = fy;
  bodies.btq[b] = tq;
  bodies.kick(b, 0.5 * h_s);
}

// Substep j of n (ending at t + j h): the light bodies' velocity Verlet
// substep against the boundary's heavy particles at t + j h.
void DemMultirate::light_substep(DemBodies& bodies, DemContacts& contacts, std::size_t j, std::size_t n,
                                 double h_s) {
  // (The last substep puts the heavy particles at their places at t + H
  // exactly, not x0 + 1.0 (x1 - x0).)
  const bool last = j == n;
  const double w = static_cast<double>(j) / static_cast<double>(n);
  const std::size_t nlight = light_bodies_.size(), nboundary = boundary_bodies_.size();
  const std::size_t nplaced = boundary_particles_.size();
#pragma omp parallel
  {
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < nlight; ++k) move_light_disk(bodies, k, h_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < nplaced; ++k) {
      const auto i = static_cast<std::size_t>(boundary_particles_[k]);
      const auto b = static_cast<std::size_t>(bodies.pbody[i]);
      bodies.px[i] = last ? px_end_[i] : bodies.px_old[i] + w * (px_end_[i] - bodies.px_old[i]);
      bodies.py[i] = last ? py_end_[i] : bodies.py_old[i] + w * (py_end_[i] - bodies.py_old[i]);
      bodies.pr[i] = last ? bodies.br[b] : br_start_[b] + w * (bodies.br[b] - br_start_[b]);
    }
    contacts.forces_of_range(bodies, 0, fast_bonds_, 0, fast_contacts_, h_s);
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < nlight; ++k) sum_forces_and_kick_light_disk(bodies, contacts, k, h_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < nboundary; ++k) add_fast_forces_of_boundary(bodies, contacts, k, w, last);
  }
}

// Boundary body k's force and moment (about its centroid at the substep's
// end) from its fast contacts, added to its sums over the step.
void DemMultirate::add_fast_forces_of_boundary(const DemBodies& bodies, const DemContacts& contacts, std::size_t k,
                                               double w, bool last) {
  const auto b = static_cast<std::size_t>(boundary_bodies_[k]);
  const double gx = last ? bodies.bx[b] : bx_start_[b] + w * (bodies.bx[b] - bx_start_[b]);
  const double gy = last ? bodies.by[b] : by_start_[b] + w * (bodies.by[b] - by_start_[b]);
  double fx = 0, fy = 0, tq = 0;
  for (int m = boundary_entry_start_[k]; m < boundary_entry_start_[k + 1]; ++m) {
    const int e = boundary_entry_[m];
    const auto i = static_cast<std::size_t>(boundary_entry_particle_[m]);
    const DemContacts::Force& cf = contacts.force[ContactIncidence::contact(e)];
    const bool q = ContactIncidence::is_q(e);
    const double sign = q ? 1.0 : -1.0;
    fx += sign * cf.fx;
    fy += sign * cf.fy;
    tq += cf.moment[q] + (bodies.px[i] - gx) * sign * cf.fy - (bodies.py[i] - gy) * sign * cf.fx;
  }
  fast_fx_[b] += fx;
  fast_fy_[b] += fy;
  fast_tq_[b] += tq;
}

// The contacts between heavy bodies at t + H; each heavy body's force is
// theirs plus the mean of its fast contacts' over the n substeps (their
// impulse over the step, divided by H); the heavy bodies' closing half kick.
void DemMultirate::heavy_forces_and_kick(DemBodies& bodies, DemContacts& contacts, double dt_s, std::size_t n) {
  const double inv_n = 1 / static_cast<double>(n);
  const std::size_t nbonds = contacts.bonds.size();
#pragma omp parallel
  {
    contacts.forces_of_range(bodies, fast_bonds_, nbonds, fast_contacts_, contacts.contacts.size(), dt_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < DemBodies::kStepParts; ++k)
      for (std::size_t b = heavy_sum_part_first_body_[k]; b < heavy_sum_part_first_body_[k + 1]; ++b) {
        if (light_[b]) continue;
        double f[3];
        contacts.sum_body(bodies, b, bodies.bx[b], bodies.by[b],
                          [this, nbonds](std::size_t c) { return !fast_index(c, nbonds); }, f);
        bodies.bfx[b] = f[0] + fast_fx_[b] * inv_n;
        bodies.bfy[b] = f[1] + fast_fy_[b] * inv_n;
        bodies.btq[b] = f[2] + fast_tq_[b] * inv_n;
        fast_fx_[b] = fast_fy_[b] = fast_tq_[b] = 0;
        bodies.kick(b, 0.5 * dt_s);
      }
  }
}

}  // namespace fibrodem
