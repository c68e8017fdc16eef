// The DEM's contacts (dem_solver.hpp, "Contacts"): the tissue's bonds, the
// Verlet list of unbonded contacts, their constants, and the indexes the
// force sums and the stable step read them by.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mechanics/dem_solver.hpp"
#include "mechanics/dem_units.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

// Bonds: formed at the start, unloaded (reference gap = the gap now).
// Returns each bond's particles (the pairs contact detection passes over).
std::vector<std::pair<int, int>> DemSolver::form_bonds(const Tissue& t) {
  const std::size_t np = pbody_.size();
  bonds_.resize(t.bonds.size());
  std::vector<std::pair<int, int>> bonded(t.bonds.size());
  for (std::size_t k = 0; k < t.bonds.size(); ++k) {
    const int p = t.bonds[k].p, q = t.bonds[k].q;
    if (p < 0 || q < 0 || static_cast<std::size_t>(p) >= np || static_cast<std::size_t>(q) >= np || p == q)
      throw std::invalid_argument("bond " + std::to_string(k) + " joins invalid particles");
    if (pbody_[p] == pbody_[q])
      throw std::invalid_argument("bond " + std::to_string(k) + " joins two particles of one clump");
    set_contact_constants(bonds_, k, p, q);
    bonds_.ref_gap[k] = std::hypot(px_[q] - px_[p], py_[q] - py_[p]) - br_[pbody_[p]] - br_[pbody_[q]];
    bonds_.kb[k] = law_->bending_stiffness(bonds_.kn[k], br_[pbody_[p]], br_[pbody_[q]]);
    bonds_.intact[k] = 1;
    bonded[k] = {p, q};
  }
  return bonded;
}

// Stiffness by inheritance and cell types, effective mass of the two bodies (a
// fixed body's partner alone); state zeroed, reference gap 0 and no bending
// (a contact).
void DemSolver::set_contact_constants(BondSet& set, std::size_t k, int p, int q) const {
  const double series = spec_.stiffness_inheritance == StiffnessInheritance::series ? 0.5 : 1.0;
  const int bp = pbody_[p], bq = pbody_[q];
  const bool fib = !bclump_[bp] || !bclump_[bq];
  const double factor = series * (fib ? spec_.fibroblast_stiffness_factor : 1.0);
  set.p[k] = p;
  set.q[k] = q;
  set.kn[k] = spec_.kn_N_per_m * factor;
  set.ks[k] = spec_.ks_N_per_m * factor;
  const double mp = density_mass_[bp], mq = density_mass_[bq];
  set.m_eff[k] = bfixed_[bp] && !bfixed_[bq]   ? mq
                 : bfixed_[bq] && !bfixed_[bp] ? mp
                                               : mp * mq / (mp + mq);
  set.ref_gap[k] = 0;
  set.kb[k] = 0;
  set.fn[k] = 0;
  set.fs[k] = 0;
  set.mb[k] = 0;
  set.intact[k] = 0;
}

// A new Verlet list of unbonded contacts; a pair on the old list keeps its
// shear force (both lists in contact_order_less's order, merged); the stable
// step follows.
void DemSolver::rebuild_contacts() {
  detector_->build(px_.data(), py_.data(), pr_.data(), candidate_pairs_);
  partition_candidates_fast_first();  // (multirate only)
  const std::size_t n = candidate_pairs_.size();
  next_contacts_.resize(n);
  std::size_t old = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto [p, q] = candidate_pairs_[k];
    set_contact_constants(next_contacts_, k, p, q);
    while (old < contacts_.size() && contact_order_less(contacts_.p[old], contacts_.q[old], p, q)) ++old;
    if (old < contacts_.size() && contacts_.p[old] == p && contacts_.q[old] == q) {
      next_contacts_.fn[k] = contacts_.fn[old];
      next_contacts_.fs[k] = contacts_.fs[old];
    }
  }
  law_->prepare(next_contacts_);
  std::swap(contacts_, next_contacts_);
  index_contacts();
  compute_stable_step();
  if (spec_.dt_ms > stable_step_ms_ && steps_ > 0)
    throw std::invalid_argument("at t = " + significant_digits(time_ms(), 6) + " ms new contacts lower the stable DEM step to " +
                                significant_digits(stable_step_ms_, 6) + " ms, below mechanics.dt_ms " + significant_digits(spec_.dt_ms, 6) +
                                " ms: lower mechanics.dt_ms, or leave it out (automatic step)");
}

// The per-contact force arrays and each particle's list of contacts, after
// the contacts changed.
void DemSolver::index_contacts() {
  const std::size_t n = bonds_.size() + contacts_.size();
  contact_force_.resize(n);
  contact_kt_.resize(n);
  contact_kr_.resize(2 * n);
  body_kt_.resize(bx_.size());
  body_kr_.resize(bx_.size());
  particle_contacts_.build(px_.size(), bonds_, contacts_);
  body_contacts_.build(bx_.size(), bonds_, contacts_, pbody_.data());
  partition_force_sums();
  index_multirate();
}

std::size_t DemSolver::broken_bonds() const {
  return static_cast<std::size_t>(std::count(bonds_.intact.begin(), bonds_.intact.end(), 0));
}

std::size_t DemSolver::touching_contacts() const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < contacts_.size(); ++k) n += contacts_.fn[k] > 0;
  return n;
}

double DemSolver::elastic_energy_J() const {
  double e = 0;
  for (const BondSet* set : {&bonds_, &contacts_})
    for (std::size_t k = 0; k < set->size(); ++k) {
      e += 0.5 * set->fn[k] * set->fn[k] / set->kn[k];
      if (set->ks[k] > 0) e += 0.5 * set->fs[k] * set->fs[k] / set->ks[k];
      if (set->kb[k] > 0) e += 0.5 * set->mb[k] * set->mb[k] / set->kb[k];
    }
  return e;
}

}  // namespace fibrodem
