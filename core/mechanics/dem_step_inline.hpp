// The per-body and per-particle pieces of a DEM step, defined here so that
// the step's loops (the fused move loop in dem_solver.cpp, the closing kick
// in dem_contact_forces.cpp) inline them. They are forced inline: GCC 12
// kept them as calls, one per body or particle.
#pragma once

#include <cmath>
#include <cstddef>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {

// One block of contacts' kinematics, in and out of the law (per thread).
struct DemSolver::BlockScratch {
  alignas(64) double gap[kBlock], dn[kBlock], ds[kBlock], dth[kBlock], nx[kBlock], ny[kBlock];
  alignas(64) double lp[kBlock], lq[kBlock], fn[kBlock], fs[kBlock], mt[kBlock];
};

// v += (F - alpha |F| sign(v)) / m * h for each degree of freedom (PFC's
// local damping; alpha 0: plain Newton).
[[gnu::always_inline]] inline void DemSolver::kick_body(std::size_t b, double h_s) {
  if (bfixed_[b]) return;
  const double alpha = spec_.local_damping;
  auto damped = [alpha](double f, double v) {
    return v > 0 ? f - alpha * std::abs(f) : v < 0 ? f + alpha * std::abs(f) : f;
  };
  bvx_[b] += damped(bfx_[b], bvx_[b]) * inv_m_[b] * h_s;
  bvy_[b] += damped(bfy_[b], bvy_[b]) * inv_m_[b] * h_s;
  bw_[b] += damped(btq_[b], bw_[b]) * inv_i_[b] * h_s;
}

// Drift at the half-step velocity, then the clump's shape at the length ratio
// set for the step's end (its spacing's rate for the pebbles' slide) and its axis.
[[gnu::always_inline]] inline void DemSolver::drift_and_reshape(std::size_t b, double dt_s) {
  if (!bfixed_[b]) {
    bx_[b] += bvx_[b] * dt_s;
    by_[b] += bvy_[b] * dt_s;
    bth_[b] += bw_[b] * dt_s;
  }
  bsdot_[b] = 0;
  if (btarget_s_[b] != bs_[b] || btarget_r_[b] != br_[b]) {
    bsdot_[b] = (btarget_s_[b] - bs_[b]) / dt_s;
    bs_[b] = btarget_s_[b];
    br_[b] = btarget_r_[b];
  }
  if (brest_[b].n < 2) return;  // a disk has no axis (its particle sits at its centre)
  double sin_th, cos_th;
  ::sincos(bth_[b], &sin_th, &cos_th);  // glibc: the same bits as sin() and cos(), in one call
  bux_[b] = -sin_th;
  buy_[b] = cos_th;
}

// Body b's particles at its pose and shape (the body's values read once:
// stores to the particles' arrays could otherwise alias them).
[[gnu::always_inline]] inline void DemSolver::place_particles_of(std::size_t b) {
  const double x = bx_[b], y = by_[b], ux = bux_[b], uy = buy_[b], s = bs_[b], sdot = bsdot_[b];
  const double vx = bvx_[b], vy = bvy_[b], w = bw_[b], r = br_[b];
  for (int j = body_particle_start_[b]; j < body_particle_start_[b + 1]; ++j) {
    const auto i = static_cast<std::size_t>(body_particle_[j]);
    const double ox = pa_[i] * s * ux, oy = pa_[i] * s * uy;
    px_[i] = x + ox;
    py_[i] = y + oy;
    // Velocity of the particle's centre: rigid motion plus its slide along the axis.
    const double slide = pa_[i] * sdot;
    pvx_[i] = vx - w * oy + slide * ux;
    pvy_[i] = vy + w * ox + slide * uy;
    pr_[i] = r;
    pw_[i] = w;
  }
}

// Counts every contact (sum_particle_contacts, sum_body_contacts).
inline constexpr auto kEveryContact = [](std::size_t) { return true; };

// Particle i's force and moment from those of its contacts `counted` takes
// (a contact's index -> bool), summed in their order (contact_incidence.hpp):
// on q the contact's force, on p minus it.
template <class Counted>
[[gnu::always_inline]] inline void DemSolver::sum_particle_contacts(std::size_t i, Counted counted, double& fx,
                                                                    double& fy, double& tq) const {
  fx = fy = tq = 0;
  for (const int* e = particle_contacts_.begin(i); e != particle_contacts_.end(i); ++e) {
    const auto c = static_cast<std::size_t>(ContactIncidence::contact(*e));
    if (!counted(c)) continue;
    const ContactForce& f = contact_force_[c];
    const bool q = ContactIncidence::is_q(*e);
    const double sign = q ? 1.0 : -1.0;
    fx += sign * f.fx;
    fy += sign * f.fy;
    tq += f.moment[q];
  }
}

// Body b's force and moment about (gx, gy) from the contacts `counted` takes:
// F = sum f, T = sum (t_p + (x_p - g) x f_p) over its particles, each
// particle's f and t summed over its contacts in their order.
template <class Counted>
[[gnu::always_inline]] inline void DemSolver::sum_body_contacts(std::size_t b, double gx, double gy, Counted counted,
                                                                double (&f)[3]) const {
  double fx = 0, fy = 0, tq = 0;
  for (int k = body_particle_start_[b]; k < body_particle_start_[b + 1]; ++k) {
    const auto i = static_cast<std::size_t>(body_particle_[k]);
    double pfx, pfy, ptq;
    sum_particle_contacts(i, counted, pfx, pfy, ptq);
    fx += pfx;
    fy += pfy;
    tq += ptq + (px_[i] - gx) * pfy - (py_[i] - gy) * pfx;
  }
  f[0] = fx;
  f[1] = fy;
  f[2] = tq;
}

}  // namespace fibrodem
