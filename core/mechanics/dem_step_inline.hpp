// The per-body and per-particle pieces of a DEM step (DemBodies' kick,
// drift_and_reshape and place_particles_of; DemContacts' force sums),
// defined here so that the step's loops (dem_solver.cpp,
// dem_multirate_step.cpp) inline them. They are forced inline: GCC 12 kept
// them as calls, one per body or particle.
#pragma once

#include <cmath>
#include <cstddef>

#include "mechanics/dem_bodies.hpp"
#include "mechanics/dem_contacts.hpp"

namespace fibrodem {

// v += (F - alpha |F| sign(v)) / m * h for each degree of freedom (PFC's
// local damping; alpha 0: plain Newton).
[[gnu::always_inline]] inline void DemBodies::kick(std::size_t b, double h_s) {
  if (bfixed[b]) return;
  const double alpha = local_damping;
  auto damped = [alpha](double f, double v) {
    return v > 0 ? f - alpha * std::abs(f) : v < 0 ? f + alpha * std::abs(f) : f;
  };
  bvx[b] += damped(bfx[b], bvx[b]) * inv_m[b] * h_s;
  bvy[b] += damped(bfy[b], bvy[b]) * inv_m[b] * h_s;
  bw[b] += damped(btq[b], bw[b]) * inv_i[b] * h_s;
}

// Drift at the half-step velocity, then the clump's shape at the length ratio
// set for the step's end (its spacing's rate for the pebbles' slide) and its axis.
[[gnu::always_inline]] inline void DemBodies::drift_and_reshape(std::size_t b, double dt_s) {
  if (!bfixed[b]) {
    bx[b] += bvx[b] * dt_s;
    by[b] += bvy[b] * dt_s;
    bth[b] += bw[b] * dt_s;
  }
  bsdot[b] = 0;
  if (btarget_s[b] != bs[b] || btarget_r[b] != br[b]) {
    bsdot[b] = (btarget_s[b] - bs[b]) / dt_s;
    bs[b] = btarget_s[b];
    br[b] = btarget_r[b];
  }
  if (brest[b].n < 2) return;  // a disk has no axis (its particle sits at its centre)
  double sin_th, cos_th;
  ::sincos(bth[b], &sin_th, &cos_th);  // glibc: the same bits as sin() and cos(), in one call
  bux[b] = -sin_th;
  buy[b] = cos_th;
}

// Body b's particles at its pose and shape (the body's values read once:
// stores to the particles' arrays could otherwise alias them).
[[gnu::always_inline]] inline void DemBodies::place_particles_of(std::size_t b) {
  const double x = bx[b], y = by[b], ux = bux[b], uy = buy[b], s = bs[b], sdot = bsdot[b];
  const double vx = bvx[b], vy = bvy[b], w = bw[b], r = br[b];
  for (int j = body_particle_start[b]; j < body_particle_start[b + 1]; ++j) {
    const auto i = static_cast<std::size_t>(body_particle[j]);
    const double ox = pa[i] * s * ux, oy = pa[i] * s * uy;
    px[i] = x + ox;
    py[i] = y + oy;
    // Velocity of the particle's centre: rigid motion plus its slide along the axis.
    const double slide = pa[i] * sdot;
    pvx[i] = vx - w * oy + slide * ux;
    pvy[i] = vy + w * ox + slide * uy;
    pr[i] = r;
    pw[i] = w;
  }
}

// Summed in their order (contact_incidence.hpp): on q the contact's force,
// on p minus it.
template <class Counted>
[[gnu::always_inline]] inline void DemContacts::sum_particle(std::size_t i, Counted counted, double& fx, double& fy,
                                                             double& tq) const {
  fx = fy = tq = 0;
  for (const int* e = particle_contacts.begin(i); e != particle_contacts.end(i); ++e) {
    const auto c = static_cast<std::size_t>(ContactIncidence::contact(*e));
    if (!counted(c)) continue;
    const Force& f = force[c];
    const bool q = ContactIncidence::is_q(*e);
    const double sign = q ? 1.0 : -1.0;
    fx += sign * f.fx;
    fy += sign * f.fy;
    tq += f.moment[q];
  }
}

// F = sum f, T = sum (t_p + (x_p - g) x f_p) over the body's particles, each
// particle's f and t summed over its contacts in their order.
template <class Counted>
[[gnu::always_inline]] inline void DemContacts::sum_body(const DemBodies& bodies, std::size_t b, double gx, double gy,
                                                         Counted counted, double (&f)[3]) const {
  double fx = 0, fy = 0, tq = 0;
  for (int k = bodies.body_particle_start[b]; k < bodies.body_particle_start[b + 1]; ++k) {
    const auto i = static_cast<std::size_t>(bodies.body_particle[k]);
    double pfx, pfy, ptq;
    sum_particle(i, counted, pfx, pfy, ptq);
    fx += pfx;
    fy += pfy;
    tq += ptq + (bodies.px[i] - gx) * pfy - (bodies.py[i] - gy) * pfx;
  }
  f[0] = fx;
  f[1] = fy;
  f[2] = tq;
}

}  // namespace fibrodem
