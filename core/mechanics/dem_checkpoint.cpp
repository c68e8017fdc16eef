// The DEM's checkpoint (MechanicsSolver::save and load): every array that
// evolves, both contact sets whole, the contact list's state and the clock.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mechanics/dem_solver.hpp"

namespace fibrodem {

template <class Self, class F>
void DemSolver::for_each_evolving_array(Self& self, F&& f) {
  // Bodies: pose, velocity, force, and the clump's shape on its way to the target.
  f("dem.body.x", self.bx_), f("dem.body.y", self.by_), f("dem.body.theta", self.bth_);
  f("dem.body.vx", self.bvx_), f("dem.body.vy", self.bvy_), f("dem.body.omega", self.bw_);
  f("dem.body.fx", self.bfx_), f("dem.body.fy", self.bfy_), f("dem.body.torque", self.btq_);
  f("dem.body.r", self.br_), f("dem.body.s", self.bs_), f("dem.body.sdot", self.bsdot_), f("dem.body.lambda", self.blambda_);
  f("dem.body.target_r", self.btarget_r_), f("dem.body.target_s", self.btarget_s_), f("dem.body.ux", self.bux_), f("dem.body.uy", self.buy_);
  // Particles, now and a step ago (the strain's half-step velocities).
  f("dem.particle.x", self.px_), f("dem.particle.y", self.py_), f("dem.particle.x_old", self.px_old_), f("dem.particle.y_old", self.py_old_);
  f("dem.particle.vx", self.pvx_), f("dem.particle.vy", self.pvy_), f("dem.particle.r", self.pr_), f("dem.particle.omega", self.pw_);
}

namespace {

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

}  // namespace

void DemSolver::save(CheckpointFields& fields) const {
  for_each_evolving_array(*this, [&](const std::string& name, const std::vector<double>& v) { fields.put(name, v); });
  for_each_bond_array(bonds_, "dem.bond.", [&](const std::string& name, const auto& v) { put_array(fields, name, v); });
  for_each_bond_array(contacts_, "dem.contact.",
                      [&](const std::string& name, const auto& v) { put_array(fields, name, v); });
  if (detector_) detector_->save(fields);
  // Masses of motion: mass scaling sets them for the contacts listed (without
  // it they are the density's, and a checkpoint needs none).
  if (scaling_step_s_ > 0) {
    fields.put("dem.body.mass", mass_);
    fields.put("dem.body.inertia", inertia_);
  }
  // Multirate: the light bodies' step, set with the contact list (the
  // substeps' state lives inside a step: nothing else to carry).
  if (!blight_.empty()) {
    fields.put("dem.multirate", std::vector<double>{light_step_s_, static_cast<double>(substeps_)});
    fields.put_bytes("dem.multirate.light", blight_.data(), blight_.size());
  }
  const std::array<double, 3>& eps = strain_fit_.strain();
  fields.put("dem.clock", std::vector<double>{time_s_, static_cast<double>(steps_), stable_step_ms_, eps[0], eps[1], eps[2]});
}

// The light bodies, their step and the substep count; the contacts put in the
// multirate order (a no-op on a checkpoint written with multirate).
void DemSolver::load_multirate(const CheckpointFields& fields) {
  if (!fields.has("dem.multirate"))
    throw CheckpointError("it was written without mechanics.multirate, which this run sets");
  const auto m = fields.numbers("dem.multirate", 2);
  if (!(m[0] > 0) || !(m[1] >= 0 && m[1] < 1e18)) throw CheckpointError("its DEM multirate state is out of range");
  light_step_s_ = m[0];
  substeps_ = static_cast<std::size_t>(m[1]);
  fields.bytes("dem.multirate.light", blight_.data(), blight_.size());
  for (std::size_t b = 0; b < blight_.size(); ++b)
    if (blight_[b] > 1 || (blight_[b] && (bclump_[b] || bfixed_[b])))
      throw CheckpointError("its DEM body " + std::to_string(b) + " is marked light but is a clump, fixed, or not 0/1");
  list_light_bodies();
  fast_bonds_ = order_fast_first(bonds_, false);
  order_fast_first(contacts_, true);
}

void DemSolver::load(const CheckpointFields& fields) {
  for_each_evolving_array(*this, [&](const std::string& name, std::vector<double>& v) { fields.read_into(name, v); });
  const long long bonds = static_cast<long long>(bonds_.size());
  for_each_bond_array(bonds_, "dem.bond.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, bonds); });
  const long long contacts = static_cast<long long>(fields.integers("dem.contact.p").size());
  for_each_bond_array(contacts_, "dem.contact.",
                      [&](const std::string& name, auto& v) { get_array(fields, name, v, contacts); });
  const long long particles = static_cast<long long>(px_.size());
  for (std::size_t k = 0; k < bonds_.size() + contacts_.size(); ++k) {
    const BondSet& set = k < bonds_.size() ? bonds_ : contacts_;
    const std::size_t i = k < bonds_.size() ? k : k - bonds_.size();
    if (set.p[i] < 0 || set.p[i] >= particles || set.q[i] < 0 || set.q[i] >= particles)
      throw CheckpointError("its DEM contact " + std::to_string(k) + " joins particles outside the tissue");
  }
  if (detector_) detector_->load(fields);
  const auto clock = fields.numbers("dem.clock", 6);
  // (A stable step far below the bonded tissue's own would stall the run:
  // contacts never lower it that much.)
  if (!(clock[2] >= 0.1 * bonded_stable_step_ms_ && clock[2] <= 1e3) || !(clock[1] >= 0 && clock[1] < 1e18))
    throw CheckpointError("its DEM clock (steps, stable step) is out of range");
  time_s_ = clock[0];
  steps_ = static_cast<std::size_t>(clock[1]);
  stable_step_ms_ = clock[2];
  strain_fit_.set_strain({clock[3], clock[4], clock[5]});
  if (fields.has("dem.body.mass")) {
    fields.read_into("dem.body.mass", mass_);
    fields.read_into("dem.body.inertia", inertia_);
  }
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    if (bfixed_[b]) continue;
    if (!(mass_[b] >= density_mass_[b] && inertia_[b] >= density_inertia_[b] && std::isfinite(mass_[b] + inertia_[b])))
      throw CheckpointError("its DEM body " + std::to_string(b) + " is lighter than its density makes it");
    inv_m_[b] = 1 / mass_[b];
    inv_i_[b] = 1 / inertia_[b];
  }
  if (!blight_.empty()) load_multirate(fields);
  index_contacts();
  out_dirty_ = true;
}

}  // namespace fibrodem
