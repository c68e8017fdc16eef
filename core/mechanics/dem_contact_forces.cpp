// The DEM's contact forces (dem_contacts.hpp; dem_solver.hpp, "Contacts" and
// "Threads"): each contact's kinematics and law, block by block, into
// per-contact arrays (each body's sum of them: dem_step_inline.hpp).
#include <algorithm>
#include <cmath>

#include "mechanics/dem_contacts.hpp"

namespace fibrodem {

void DemContacts::forces_of_range(const DemBodies& bodies, std::size_t bond_begin, std::size_t bond_end,
                                  std::size_t contact_begin, std::size_t contact_end, double dt_s) {
  BlockScratch scratch;
  const std::size_t bond_blocks = (bond_end - bond_begin + kBlock - 1) / kBlock;
  const std::size_t blocks = bond_blocks + (contact_end - contact_begin + kBlock - 1) / kBlock;
#pragma omp for schedule(static)
  for (std::size_t k = 0; k < blocks; ++k) {
    const bool bond = k < bond_blocks;
    BondSet& set = bond ? bonds : contacts;
    const std::size_t begin = bond ? bond_begin + k * kBlock : contact_begin + (k - bond_blocks) * kBlock;
    const std::size_t end = bond ? bond_end : contact_end;
    const std::size_t number = bond ? begin : bonds.size() + begin;
    block(bodies, set, begin, std::min(kBlock, end - begin), number, dt_s, scratch);
  }
}

// Contacts [begin, begin + count) of a set, numbered from `number` on: their
// kinematics, the law, and the forces and moments they put on their ends.
void DemContacts::block(const DemBodies& bodies, BondSet& set, std::size_t begin, std::size_t count,
                        std::size_t number, double dt_s, BlockScratch& s) {
  const int* const P = set.p.data() + begin;
  const int* const Q = set.q.data() + begin;
  const double *const x = bodies.px.data(), *const y = bodies.py.data(), *const r = bodies.pr.data();
  const double *const vx = bodies.pvx.data(), *const vy = bodies.pvy.data(), *const w = bodies.pw.data();
#pragma omp simd
  for (std::size_t j = 0; j < count; ++j) {
    const int p = P[j], q = Q[j];
    const double dx = x[q] - x[p], dy = y[q] - y[p];
    const double d = std::sqrt(dx * dx + dy * dy);
    const double d_or_1 = d > 0 ? d : 1.0;  // divide unconditionally (SIMD lanes), select after
    const double nx = d > 0 ? dx / d_or_1 : 1.0, ny = d > 0 ? dy / d_or_1 : 0.0;
    const double gap = d - r[p] - r[q];
    // Contact point relative to each centre: lp n and -lq n.
    const double lp = r[p] + 0.5 * gap, lq = r[q] + 0.5 * gap;
    // v_c = v_centre + w x (c - centre); w x (l n) = l w (-ny, nx) = l w t.
    const double dvx = (vx[q] - vx[p]) - (lq * w[q] + lp * w[p]) * (-ny);
    const double dvy = (vy[q] - vy[p]) - (lq * w[q] + lp * w[p]) * nx;
    s.gap[j] = gap;
    s.nx[j] = nx;
    s.ny[j] = ny;
    s.lp[j] = lp;
    s.lq[j] = lq;
    s.dn[j] = (dvx * nx + dvy * ny) * dt_s;
    s.ds[j] = (-dvx * ny + dvy * nx) * dt_s;
    s.dth[j] = (w[q] - w[p]) * dt_s;
    s.mt[j] = 0;
  }
  law_->update(set, BondBlock{begin, count, s.gap, s.dn, s.ds, s.dth, s.fn, s.fs, s.mt}, dt_s);
  // Force on q (minus on p); moments on each end: the law's, and the shear
  // force's about the centre: (c - x_q) x f = -lq fs, (c - x_p) x (-f) = -lp fs.
  Force* const out = force.data() + number;
  for (std::size_t j = 0; j < count; ++j) {
    out[j].fx = s.fn[j] * s.nx[j] - s.fs[j] * s.ny[j];
    out[j].fy = s.fn[j] * s.ny[j] + s.fs[j] * s.nx[j];
    out[j].moment[0] = -s.mt[j] - s.lp[j] * s.fs[j];
    out[j].moment[1] = s.mt[j] - s.lq[j] * s.fs[j];
  }
}

}  // namespace fibrodem
