// The DEM's contacts (dem_contacts.hpp): the tissue's bonds, the Verlet list
// of unbonded contacts, their constants, and the indexes the force sums and
// the stable step read them by.
#include "mechanics/dem_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mechanics/dem_units.hpp"

namespace fibrodem {

namespace {

template <class T>
void permute(std::vector<T>& v, const std::vector<std::size_t>& order) {
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
  v.swap(out);
}

}  // namespace

DemContacts::DemContacts(const DemSpec& spec) : spec_(spec), law_(make_contact_law(spec)) {}

// Bonds: formed at the start, unloaded (reference gap = the gap now); the
// tissue's bonds, then its bonds through collagen.
void DemContacts::form_bonds(const Tissue& t, const DemBodies& bodies) {
  const std::vector<int>& pbody = bodies.pbody;
  const std::vector<double> &px = bodies.px, &py = bodies.py, &br = bodies.br;
  const std::size_t np = pbody.size();
  const std::size_t n = t.bonds.size() + t.collagen_bonds.size();
  bonds.resize(n);
  bond_id.resize(n);
  std::vector<std::pair<int, int>> bonded(n);
  for (std::size_t k = 0; k < n; ++k) {
    const bool collagen = k >= t.bonds.size();
    const Bond& bond = collagen ? t.collagen_bonds[k - t.bonds.size()] : t.bonds[k];
    const int p = bond.p, q = bond.q;
    if (p < 0 || q < 0 || static_cast<std::size_t>(p) >= np || static_cast<std::size_t>(q) >= np || p == q)
      throw std::invalid_argument("bond " + std::to_string(k) + " joins invalid particles");
    if (pbody[p] == pbody[q])
      throw std::invalid_argument("bond " + std::to_string(k) + " joins two particles of one clump");
    set_constants(bonds, k, p, q, bodies, collagen);
    bond_id[k] = static_cast<int>(k);
    bonds.ref_gap[k] = std::hypot(px[q] - px[p], py[q] - py[p]) - br[pbody[p]] - br[pbody[q]];
    bonds.kb[k] = law_->bending_stiffness(bonds.kn[k], br[pbody[p]], br[pbody[q]]);
    bonds.intact[k] = 1;
    bonded[k] = {p, q};
  }
  law_->prepare(bonds);
  if (spec_.contact_detection)
    detector_ = std::make_unique<ContactDetector>(pbody, bonded, spec_.contact_skin_um * kUm);
}

// Stiffness by inheritance and cell types (collagen's where either end is a
// collagen particle or the bond runs through collagen, else fibroblasts'
// where either end is a fibroblast), effective mass of the two bodies (a
// fixed body's partner alone); state zeroed, reference gap 0 and no bending
// (a contact).
void DemContacts::set_constants(BondSet& set, std::size_t k, int p, int q, const DemBodies& bodies,
                                bool through_collagen) const {
  const double series = spec_.stiffness_inheritance == StiffnessInheritance::series ? 0.5 : 1.0;
  const int bp = bodies.pbody[p], bq = bodies.pbody[q];
  const bool collagen = through_collagen || bodies.bcell[bp] < 0 || bodies.bcell[bq] < 0;
  const bool fib = !bodies.bclump[bp] || !bodies.bclump[bq];
  const double factor = series * (collagen ? spec_.collagen_stiffness_factor
                                  : fib    ? spec_.fibroblast_stiffness_factor
                                           : 1.0);
  set.p[k] = p;
  set.q[k] = q;
  set.kn[k] = spec_.kn_N_per_m * factor;
  set.ks[k] = spec_.ks_N_per_m * factor;
  const double mp = bodies.density_mass[bp], mq = bodies.density_mass[bq];
  const bool fixed_p = bodies.bfixed[bp], fixed_q = bodies.bfixed[bq];
  set.m_eff[k] = fixed_p && !fixed_q ? mq : fixed_q && !fixed_p ? mp : mp * mq / (mp + mq);
  set.ref_gap[k] = 0;
  set.kb[k] = 0;
  set.fn[k] = 0;
  set.fs[k] = 0;
  set.mb[k] = 0;
  set.intact[k] = 0;
}

// A new Verlet list of unbonded contacts; a pair on the old list keeps its
// shear force (both lists in `order`, merged).
void DemContacts::rebuild_list(const DemBodies& bodies, const ContactOrder& order) {
  detector_->build(bodies.px.data(), bodies.py.data(), bodies.pr.data(), candidate_pairs_);
  if (order.light) {  // (the detector lists them by (p, q): the fast ones moved first)
    candidate_scratch_.clear();
    for (const auto& [p, q] : candidate_pairs_)
      if (order.fast(p, q)) candidate_scratch_.emplace_back(p, q);
    for (const auto& [p, q] : candidate_pairs_)
      if (!order.fast(p, q)) candidate_scratch_.emplace_back(p, q);
    candidate_pairs_.swap(candidate_scratch_);
  }
  const std::size_t n = candidate_pairs_.size();
  next_contacts_.resize(n);
  std::size_t old = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto [p, q] = candidate_pairs_[k];
    set_constants(next_contacts_, k, p, q, bodies);
    while (old < contacts.size() && order.less(contacts.p[old], contacts.q[old], p, q)) ++old;
    if (old < contacts.size() && contacts.p[old] == p && contacts.q[old] == q) {
      next_contacts_.fn[k] = contacts.fn[old];
      next_contacts_.fs[k] = contacts.fs[old];
    }
  }
  law_->prepare(next_contacts_);
  std::swap(contacts, next_contacts_);
}

// A set's fast contacts moved first, both parts in their order (by_pairs:
// in `order`'s, which rebuild_list's merge needs); returns how many are
// fast. (At the start, a reclassification and a checkpoint's load.)
std::size_t DemContacts::reorder(const ContactOrder& order) {
  auto fast_first = [&order](const BondSet& set) {
    std::vector<std::size_t> perm(set.size());
    std::iota(perm.begin(), perm.end(), std::size_t{0});
    std::stable_partition(perm.begin(), perm.end(), [&](std::size_t k) { return order.fast(set.p[k], set.q[k]); });
    return perm;
  };
  permute_bonds(fast_first(bonds));
  std::vector<std::size_t> perm(contacts.size());
  std::iota(perm.begin(), perm.end(), std::size_t{0});
  std::sort(perm.begin(), perm.end(), [&](std::size_t a, std::size_t b) {
    return order.less(contacts.p[a], contacts.q[a], contacts.p[b], contacts.q[b]);
  });
  permute_set(contacts, perm);
  std::size_t fast_bonds = 0;
  while (fast_bonds < bonds.size() && order.fast(bonds.p[fast_bonds], bonds.q[fast_bonds])) ++fast_bonds;
  return fast_bonds;
}

DemContacts::TissueOrder DemContacts::tissue_order() const {
  TissueOrder order{std::vector<std::size_t>(bonds.size()), std::vector<std::size_t>(contacts.size())};
  std::iota(order.bonds.begin(), order.bonds.end(), std::size_t{0});
  std::sort(order.bonds.begin(), order.bonds.end(),
            [&](std::size_t a, std::size_t b) { return bond_id[a] < bond_id[b]; });
  std::iota(order.contacts.begin(), order.contacts.end(), std::size_t{0});
  std::sort(order.contacts.begin(), order.contacts.end(), [&](std::size_t a, std::size_t b) {
    return std::pair(contacts.p[a], contacts.q[a]) < std::pair(contacts.p[b], contacts.q[b]);
  });
  return order;
}

void DemContacts::permute_bonds(const std::vector<std::size_t>& perm) {
  permute_set(bonds, perm);
  permute(bond_id, perm);
}

void DemContacts::permute_set(BondSet& set, const std::vector<std::size_t>& perm) {
  permute(set.p, perm), permute(set.q, perm), permute(set.kn, perm), permute(set.ks, perm);
  permute(set.m_eff, perm), permute(set.ref_gap, perm), permute(set.cn, perm), permute(set.cs, perm);
  permute(set.kb, perm), permute(set.fn, perm), permute(set.fs, perm), permute(set.mb, perm);
  permute(set.intact, perm);
}

void DemContacts::index(const DemBodies& bodies) {
  const std::size_t n = bonds.size() + contacts.size();
  force.resize(n);
  contact_kt.resize(n);
  contact_kr.resize(2 * n);
  body_kt.resize(bodies.size());
  body_kr.resize(bodies.size());
  particle_contacts.build(bodies.particle_count(), bonds, contacts);
  body_contacts.build(bodies.size(), bonds, contacts, bodies.pbody.data());
}

namespace {
bool counted(const DemBodies* own_of, const BondSet& set, std::size_t k) {
  return !own_of || own_of->steps(static_cast<std::size_t>(own_of->pbody[set.p[k]]));
}
}  // namespace

std::size_t DemContacts::broken_bonds(const DemBodies* own_of) const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < bonds.size(); ++k) n += counted(own_of, bonds, k) && !bonds.intact[k];
  return n;
}

std::size_t DemContacts::touching_contacts(const DemBodies* own_of) const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < contacts.size(); ++k) n += counted(own_of, contacts, k) && contacts.fn[k] > 0;
  return n;
}

double DemContacts::elastic_energy_J() const {
  double e = 0;
  for (const BondSet* set : {&bonds, &contacts})
    for (std::size_t k = 0; k < set->size(); ++k) {
      e += 0.5 * set->fn[k] * set->fn[k] / set->kn[k];
      if (set->ks[k] > 0) e += 0.5 * set->fs[k] * set->fs[k] / set->ks[k];
      if (set->kb[k] > 0) e += 0.5 * set->mb[k] * set->mb[k] / set->kb[k];
    }
  return e;
}

}  // namespace fibrodem
