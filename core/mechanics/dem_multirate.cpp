// Multirate DEM stepping's classes and order (dem_multirate.hpp): which
// bodies are light, the fast contacts first, the boundary, the steps.
//
// Light and heavy are classified on the contacts and masses at the start
// (mass scaling, if set, included: it makes the light bodies heavier, so
// fewer substeps); a heavy disk whose new contacts take its critical step
// below the clumps' becomes light at the end of that step (loose disks in
// interstitial tissue pick up contacts as it contracts, and would otherwise
// halve H), never back. H and h follow each contact list as the native step
// does, H a whole number of light steps (the substeps at the light bodies'
// full stable step) when that costs less. The fast contacts come first in
// both contact sets, so a substep's work is contiguous blocks.
#include "mechanics/dem_multirate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fibrodem {

namespace {

// The least critical step of the free clumps (infinite without one in contact).
double clump_critical_step_s(const DemBodies& bodies, const DemContacts& contacts) {
  double clump_crit = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies.bclump[b] && !bodies.bfixed[b])
      clump_crit = std::min(clump_crit, critical_step_s(bodies.mass[b], bodies.inertia[b], contacts.body_kt[b],
                                                        contacts.body_kr[b]));
  return clump_crit;
}

// A free disk below the clumps' critical step.
bool light_disk(const DemBodies& bodies, const DemContacts& contacts, std::size_t b, double clump_crit) {
  return !bodies.bclump[b] && !bodies.bfixed[b] &&
         critical_step_s(bodies.mass[b], bodies.inertia[b], contacts.body_kt[b], contacts.body_kr[b]) < clump_crit;
}

}  // namespace

bool DemMultirate::start(const DemBodies& bodies, DemContacts& contacts) {
  const std::size_t nb = bodies.size();
  const double clump_crit = clump_critical_step_s(bodies, contacts);
  if (!std::isfinite(clump_crit)) return false;
  std::vector<std::uint8_t> light(nb, 0);
  for (std::size_t b = 0; b < nb; ++b) light[b] = light_disk(bodies, contacts, b, clump_crit);
  if (std::find(light.begin(), light.end(), 1) == light.end()) return false;
  light_ = std::move(light);
  list_light_bodies(bodies);
  fast_bonds_ = contacts.reorder(order(bodies));
  for (auto* v : {&bx_start_, &by_start_, &br_start_, &fast_fx_, &fast_fy_, &fast_tq_}) v->assign(nb, 0.0);
  px_end_.assign(bodies.particle_count(), 0.0);
  py_end_.assign(bodies.particle_count(), 0.0);
  return true;
}

// (Light bodies are never clumps, so each is a fibroblast's disk: one
// particle at its centre, which move_light_disk relies on.)
void DemMultirate::list_light_bodies(const DemBodies& bodies) {
  light_bodies_.clear();
  light_particle_.clear();
  for (std::size_t b = 0; b < light_.size(); ++b)
    if (light_[b]) {
      light_bodies_.push_back(static_cast<int>(b));
      light_particle_.push_back(bodies.body_particle[bodies.body_particle_start[b]]);
    }
}

// The light step; a heavy disk below the clumps marked for reclassify; and
// the step either the heavy bodies' stable one (substeps a little shorter
// than the light step, n = ceil(H / h)) or cut to a whole number of light
// steps, whichever costs less per ms, a contact or a body counting one
// (interstitial tissue: cut, since the substeps are most of the work;
// in-series, with H / h ~ 1.15: not cut).
void DemMultirate::fit_steps(double& stable_step_ms, double safety_factor, double heavy_crit_s, double clump_crit_s,
                             double light_crit_s, const DemBodies& bodies, const DemContacts& contacts) {
  light_step_s_ = safety_factor * light_crit_s;
  reclassify_pending_ = heavy_crit_s < clump_crit_s;
  const double light_ms = light_step_s_ * 1e3, ratio = stable_step_ms / light_ms;
  if (!(std::isfinite(ratio) && ratio >= 1)) return;
  const double fast = static_cast<double>(fast_bonds_ + fast_contacts_ + light_bodies_.size());
  const double slow = static_cast<double>(contacts.bonds.size() + contacts.contacts.size() + bodies.size()) - fast;
  const double whole = std::floor(ratio);
  const double cost_cut = (slow + fast * whole) / (whole * light_ms);
  const double cost_heavy = (slow + fast * std::ceil(ratio)) / stable_step_ms;
  if (cost_cut <= cost_heavy) stable_step_ms = whole * light_ms;
}

// At the end of a step (every body's force complete, whichever its class).
// Rare (a disk at a time, as contacts come): the only place a step may allocate.
bool DemMultirate::reclassify(const DemBodies& bodies, DemContacts& contacts) {
  reclassify_pending_ = false;
  const double clump_crit = clump_critical_step_s(bodies, contacts);
  bool changed = false;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (!light_[b] && light_disk(bodies, contacts, b, clump_crit)) {
      light_[b] = 1;
      changed = true;
    }
  if (!changed) return false;
  list_light_bodies(bodies);
  fast_bonds_ = contacts.reorder(order(bodies));
  return true;
}

// How many unbonded contacts are fast; the heavy bodies that have a fast
// contact (the boundary), their particles that have one (which the
// substeps place), and each boundary body's fast contacts (so a substep
// reads those alone); the parts of the loops over the heavy bodies alone
// (move_heavy_bodies, heavy_forces_and_kick), where a light body only has
// its pose copied or is passed over. (The interstitial tissue lists its
// myocytes, heavy, first: the parts of the whole step would put nearly all
// of that work on one thread.)
void DemMultirate::index(const DemBodies& bodies, const DemContacts& contacts) {
  if (!on()) return;
  const ContactOrder o = order(bodies);
  const BondSet& set = contacts.contacts;
  fast_contacts_ = 0;
  while (fast_contacts_ < set.size() && o.fast(set.p[fast_contacts_], set.q[fast_contacts_])) ++fast_contacts_;
  boundary_bodies_.clear();
  boundary_particles_.clear();
  boundary_entry_start_.assign(1, 0);
  boundary_entry_.clear();
  boundary_entry_particle_.clear();
  const std::size_t nbonds = contacts.bonds.size();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (light_[b]) continue;
    for (int k = bodies.body_particle_start[b]; k < bodies.body_particle_start[b + 1]; ++k) {
      const int i = bodies.body_particle[k];
      const std::size_t entries_before = boundary_entry_.size();
      for (const int* e = contacts.particle_contacts.begin(i); e != contacts.particle_contacts.end(i); ++e)
        if (fast_index(static_cast<std::size_t>(ContactIncidence::contact(*e)), nbonds)) {
          boundary_entry_.push_back(*e);
          boundary_entry_particle_.push_back(i);
        }
      if (boundary_entry_.size() > entries_before) boundary_particles_.push_back(i);
    }
    if (boundary_entry_.size() > static_cast<std::size_t>(boundary_entry_start_.back())) {
      boundary_bodies_.push_back(static_cast<int>(b));
      boundary_entry_start_.push_back(static_cast<int>(boundary_entry_.size()));
    }
  }
  constexpr double kPoseCopyWork = 0.2, kPassWork = 0.1;
  const ContactIncidence& incidence = contacts.particle_contacts;
  heavy_part_first_body_ = parts_of_bodies(bodies.size(), DemBodies::kStepParts, [&](std::size_t b) {
    return light_[b] ? kPoseCopyWork : bodies.move_work(b);
  });
  heavy_sum_part_first_body_ = parts_of_bodies(bodies.size(), DemBodies::kStepParts, [&](std::size_t b) {
    return light_[b] ? kPassWork : bodies.sum_work(b, incidence);
  });
}

// The light bodies' step, set with the contact list (the substeps' state
// lives inside a step: nothing else to carry).
void DemMultirate::save(CheckpointFields& fields) const {
  fields.put("dem.multirate", std::vector<double>{light_step_s_, static_cast<double>(substeps_)});
  fields.put_bytes("dem.multirate.light", light_.data(), light_.size());
}

void DemMultirate::load(const CheckpointFields& fields, const DemBodies& bodies, DemContacts& contacts) {
  if (!fields.has("dem.multirate"))
    throw CheckpointError("it was written without mechanics.multirate, which this run sets");
  const auto m = fields.numbers("dem.multirate", 2);
  if (!(m[0] > 0) || !(m[1] >= 0 && m[1] < 1e18)) throw CheckpointError("its DEM multirate state is out of range");
  light_step_s_ = m[0];
  substeps_ = static_cast<std::size_t>(m[1]);
  fields.bytes("dem.multirate.light", light_.data(), light_.size());
  for (std::size_t b = 0; b < light_.size(); ++b)
    if (light_[b] > 1 || (light_[b] && (bodies.bclump[b] || bodies.bfixed[b])))
      throw CheckpointError("its DEM body " + std::to_string(b) + " is marked light but is a clump, fixed, or not 0/1");
  list_light_bodies(bodies);
  fast_bonds_ = contacts.reorder(order(bodies));
}

}  // namespace fibrodem
