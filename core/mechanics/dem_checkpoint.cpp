// The DEM's checkpoint (MechanicsSolver::save and load): every array that
// evolves, both contact sets whole, the contact list's state and the clock.
#include <array>
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {

namespace {

// Each evolving array of the bodies and their particles with its checkpoint
// field's name, for save and load alike (Bodies: DemBodies or const DemBodies).
template <class Bodies, class F>
void for_each_evolving_array(Bodies& b, F&& f) {
  for_each_evolving_body_array(b, f);
  // Particles, now and a step ago (the strain's half-step velocities).
  f("dem.particle.x", b.px), f("dem.particle.y", b.py), f("dem.particle.x_old", b.px_old);
  f("dem.particle.y_old", b.py_old), f("dem.particle.vx", b.pvx), f("dem.particle.vy", b.pvy);
  f("dem.particle.r", b.pr), f("dem.particle.omega", b.pw);
}

// A BondSet's every array (constants too: contacts come and go with the list).
template <class Set, class F>
void for_each_bond_array(Set& set, const std::string& prefix, F&& f) {
  f(prefix + "p", set.p), f(prefix + "q", set.q), f(prefix + "kn", set.kn), f(prefix + "ks", set.ks);
  f(prefix + "m_eff", set.m_eff), f(prefix + "ref_gap", set.ref_gap), f(prefix + "cn", set.cn), f(prefix + "cs", set.cs);
  f(prefix + "kb", set.kb), f(prefix + "fn", set.fn), f(prefix + "fs", set.fs), f(prefix + "mb", set.mb);
  f(prefix + "intact", set.intact);
}

void put_array(CheckpointFields& fields, const std::string& name, const std::vector<double>& v) { fields.put(name, v); }
void put_array(CheckpointFields& fields, const std::string& name, const std::vector<int>& v) { fields.put(name, v); }
void put_array(CheckpointFields& fields, const std::string& name, const std::vector<std::uint8_t>& v) {
  fields.put_bytes(name, v.data(), v.size());
}

// Reads a field of `count` values (count < 0: as many as it has).
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<double>& v, long long count) {
  v = fields.numbers(name, count);
}
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<int>& v, long long count) {
  v = fields.ints(name, count);
}
void get_array(const CheckpointFields& fields, const std::string& name, std::vector<std::uint8_t>& v,
               long long count) {
  v.resize(static_cast<std::size_t>(count));
  fields.bytes(name, v.data(), v.size());
}

template <class T>
std::vector<T> in_order(const std::vector<T>& v, const std::vector<std::size_t>& order) {
  std::vector<T> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = v[order[k]];
  return out;
}

}  // namespace

// Split over ranks, rank 0 writes it, once gather_on_rank0(true) gave it
// every body's and contact's state, with the sets in one process's order
// (any number of ranks then reads it); else the sets as they are.
void DemSolver::save(CheckpointFields& fields) const {
  for_each_evolving_array(bodies_, [&](const std::string& name, const std::vector<double>& v) { fields.put(name, v); });
  const DemContacts::TissueOrder order = split_ ? contacts_.tissue_order() : DemContacts::TissueOrder{};
  auto put_set = [&](const BondSet& set, const std::string& prefix, const std::vector<std::size_t>& set_order) {
    for_each_bond_array(set, prefix, [&](const std::string& name, const auto& v) {
      if (split_) put_array(fields, name, in_order(v, set_order));
      else put_array(fields, name, v);
    });
  };
  put_set(contacts_.bonds, "dem.bond.", order.bonds);
  put_set(contacts_.contacts, "dem.contact.", order.contacts);
  if (contacts_.detects()) contacts_.detector()->save(fields);
  // Masses of motion: mass scaling sets them for the contacts listed (without
  // it they are the density's, and a checkpoint needs none).
  if (mass_scaling_.active()) {
    fields.put("dem.body.mass", bodies_.mass);
    fields.put("dem.body.inertia", bodies_.inertia);
  }
  if (multirate_.on()) multirate_.save(fields);
  const std::array<double, 3>& eps = strain_fit_.strain();
  fields.put("dem.clock",
             std::vector<double>{time_s_, static_cast<double>(steps_), stable_step_ms_, eps[0], eps[1], eps[2]});
}

void DemSolver::load(const CheckpointFields& fields) {
  for_each_evolving_array(bodies_, [&](const std::string& name, std::vector<double>& v) { fields.read_into(name, v); });
  BondSet &bonds = contacts_.bonds, &contacts = contacts_.contacts;
  const long long nbonds = static_cast<long long>(bonds.size());
  for_each_bond_array(bonds, "dem.bond.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, nbonds); });
  const long long ncontacts = static_cast<long long>(fields.integers("dem.contact.p").size());
  for_each_bond_array(contacts, "dem.contact.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, ncontacts); });
  const long long particles = static_cast<long long>(bodies_.particle_count());
  for (std::size_t k = 0; k < bonds.size() + contacts.size(); ++k) {
    const BondSet& set = k < bonds.size() ? bonds : contacts;
    const std::size_t i = k < bonds.size() ? k : k - bonds.size();
    if (set.p[i] < 0 || set.p[i] >= particles || set.q[i] < 0 || set.q[i] >= particles)
      throw CheckpointError("its DEM contact " + std::to_string(k) + " joins particles outside the tissue");
  }
  if (contacts_.detects()) contacts_.detector()->load(fields);
  const auto clock = fields.numbers("dem.clock", 6);
  // (A stable step far below the bonded tissue's own would stall the run:
  // contacts never lower it that much.)
  if (!(clock[2] >= 0.1 * bonded_stable_step_ms_ && clock[2] <= 1e3) || !(clock[1] >= 0 && clock[1] < 1e18))
    throw CheckpointError("its DEM clock (steps, stable step) is out of range");
  time_s_ = clock[0];
  steps_ = static_cast<std::size_t>(clock[1]);
  stable_step_ms_ = clock[2];
  strain_fit_.set_strain({clock[3], clock[4], clock[5]});
  DemBodies& B = bodies_;
  if (fields.has("dem.body.mass")) {
    fields.read_into("dem.body.mass", B.mass);
    fields.read_into("dem.body.inertia", B.inertia);
  }
  for (std::size_t b = 0; b < B.size(); ++b) {
    if (B.bfixed[b]) continue;
    if (!(B.mass[b] >= B.density_mass[b] && B.inertia[b] >= B.density_inertia[b] &&
          std::isfinite(B.mass[b] + B.inertia[b])))
      throw CheckpointError("its DEM body " + std::to_string(b) + " is lighter than its density makes it");
    B.inv_m[b] = 1 / B.mass[b];
    B.inv_i[b] = 1 / B.inertia[b];
  }
  if (multirate_.on()) multirate_.load(fields, bodies_, contacts_);
  if (split_) {  // (the sets in tissue order: this rank's contacts first again)
    std::iota(contacts_.bond_id.begin(), contacts_.bond_id.end(), 0);
    contacts_.reorder(contact_order());
  }
  index_contacts();
  out_dirty_ = true;
}

}  // namespace fibrodem
