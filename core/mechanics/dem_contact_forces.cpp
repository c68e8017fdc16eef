// The DEM's contact forces (dem_solver.hpp, "Contacts" and "Threads"): each
// contact's kinematics and law, block by block, into per-contact arrays; then
// each body's sum of them in a fixed order, and the step's closing half kick.
#include <algorithm>
#include <cmath>

#include "mechanics/dem_solver.hpp"
#include "mechanics/dem_step_inline.hpp"

namespace fibrodem {

// Forces per contact in parallel (blocks of bonds, then of contacts), then
// their sums per body, each from its own contacts in a fixed order, and the
// closing half kick of h_s with them (bodies in parts of equal contact work:
// partition_force_sums).
void DemSolver::compute_forces_and_kick(double dt_s, double h_s) {
  const std::size_t bond_blocks = (bonds_.size() + kBlock - 1) / kBlock;
  const std::size_t blocks = bond_blocks + (contacts_.size() + kBlock - 1) / kBlock;
#pragma omp parallel
  {
    BlockScratch scratch;
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < blocks; ++k) {
      const bool bond = k < bond_blocks;
      BondSet& set = bond ? bonds_ : contacts_;
      const std::size_t begin = (bond ? k : k - bond_blocks) * kBlock;
      const std::size_t number = bond ? begin : bonds_.size() + begin;
      contact_block(set, begin, std::min(kBlock, set.size() - begin), number, dt_s, scratch);
    }
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = sum_part_first_body_[k]; b < sum_part_first_body_[k + 1]; ++b) {
        sum_forces_on_body(b);
        kick_body(b, h_s);
      }
  }
}

// Contacts [begin, begin + count) of a set, numbered from `number` on: their
// kinematics, the law, and the forces and moments they put on their ends.
void DemSolver::contact_block(BondSet& set, std::size_t begin, std::size_t count, std::size_t number,
                              double dt_s, BlockScratch& s) {
  const int* const P = set.p.data() + begin;
  const int* const Q = set.q.data() + begin;
  const double *const x = px_.data(), *const y = py_.data(), *const r = pr_.data();
  const double *const vx = pvx_.data(), *const vy = pvy_.data(), *const w = pw_.data();
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
  ContactForce* const out = contact_force_.data() + number;
  for (std::size_t j = 0; j < count; ++j) {
    out[j].fx = s.fn[j] * s.nx[j] - s.fs[j] * s.ny[j];
    out[j].fy = s.fn[j] * s.ny[j] + s.fs[j] * s.nx[j];
    out[j].moment[0] = -s.mt[j] - s.lp[j] * s.fs[j];
    out[j].moment[1] = s.mt[j] - s.lq[j] * s.fs[j];
  }
}

// Body b's force and moment about its centroid from all its contacts.
void DemSolver::sum_forces_on_body(std::size_t b) {
  double f[3];
  sum_body_contacts(b, bx_[b], by_[b], kEveryContact, f);
  bfx_[b] = f[0];
  bfy_[b] = f[1];
  btq_[b] = f[2];
}

}  // namespace fibrodem
