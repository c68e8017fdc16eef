// Multirate DEM stepping (spec `multirate`; dem_solver.hpp, "Multirate").
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
// Light and heavy are classified on the contacts and masses at the start
// (mass scaling, if set, included: it makes the light bodies heavier, so
// fewer substeps); a heavy disk whose new contacts take its critical step
// below the clumps' becomes light at the end of that step (loose disks in
// interstitial tissue pick up contacts as it contracts, and would otherwise
// halve H), never back. H and h follow each contact list as the native step
// does, H a whole number of light steps (the substeps at the light bodies'
// full stable step) when that costs less. The fast contacts come first in
// both contact sets, so a substep's work is contiguous blocks. Every sum is
// per body in a fixed order: the same bits for any number of threads;
// nothing allocated per step (but in a reclassification, which is rare).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "mechanics/dem_solver.hpp"
#include "mechanics/dem_step_inline.hpp"

namespace fibrodem {

namespace {

// The critical step of a body of mass m, inertia i on stiffnesses kt, kr
// (infinite without contacts).
double critical_step_s(double m, double i, double kt, double kr) {
  double t = std::numeric_limits<double>::infinity();
  if (kt > 0) t = std::min(t, std::sqrt(m / kt));
  if (kr > 0) t = std::min(t, std::sqrt(i / kr));
  return t;
}

template <class T>
void permute(std::vector<T>& v, const std::vector<std::size_t>& order) {
  std::vector<T> out(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
  v.swap(out);
}

}  // namespace

// Light: free disks whose critical step (at the start's contacts and masses,
// just computed by compute_stable_step) is below the least of the free
// clumps'. Without such a disk, or without a clump in contact, the solver
// keeps one rate.
void DemSolver::start_multirate() {
  const std::size_t nb = bx_.size();
  double clump_crit = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < nb; ++b)
    if (bclump_[b] && !bfixed_[b])
      clump_crit = std::min(clump_crit, critical_step_s(mass_[b], inertia_[b], body_kt_[b], body_kr_[b]));
  if (!std::isfinite(clump_crit)) return;
  std::vector<std::uint8_t> light(nb, 0);
  for (std::size_t b = 0; b < nb; ++b)
    light[b] = !bclump_[b] && !bfixed_[b] &&
               critical_step_s(mass_[b], inertia_[b], body_kt_[b], body_kr_[b]) < clump_crit;
  if (std::find(light.begin(), light.end(), 1) == light.end()) return;
  blight_ = std::move(light);
  list_light_bodies();
  fast_bonds_ = order_fast_first(bonds_, false);
  order_fast_first(contacts_, true);
  for (auto* v : {&bx_start_, &by_start_, &br_start_, &fast_fx_, &fast_fy_, &fast_tq_}) v->assign(nb, 0.0);
  px_end_.assign(px_.size(), 0.0);
  py_end_.assign(px_.size(), 0.0);
  index_contacts();
  compute_stable_step();
}

// (Light bodies are never clumps, so each is a fibroblast's disk: one
// particle at its centre, which move_light_disk relies on.)
void DemSolver::list_light_bodies() {
  light_bodies_.clear();
  light_particle_.clear();
  for (std::size_t b = 0; b < blight_.size(); ++b)
    if (blight_[b]) {
      light_bodies_.push_back(static_cast<int>(b));
      light_particle_.push_back(body_particle_[body_particle_start_[b]]);
    }
}

// The steps from the least critical steps of the heavy bodies, the clumps
// and the light bodies (compute_stable_step set the step from the heavy
// ones'): the light step; a heavy disk below the clumps marked for
// reclassify_heavy_disks; and the step either the heavy bodies' stable one
// (substeps a little shorter than the light step, n = ceil(H / h)) or cut
// to a whole number of light steps, whichever costs less per ms, a contact
// or a body counting one (interstitial tissue: cut, since the substeps are
// most of the work; in-series, with H / h ~ 1.15: not cut).
void DemSolver::fit_multirate_steps(double heavy_crit_s, double clump_crit_s, double light_crit_s) {
  light_step_s_ = spec_.safety_factor * light_crit_s;
  reclassify_pending_ = heavy_crit_s < clump_crit_s;
  const double light_ms = light_step_s_ * 1e3, ratio = stable_step_ms_ / light_ms;
  if (!(std::isfinite(ratio) && ratio >= 1)) return;
  const double fast = static_cast<double>(fast_bonds_ + fast_contacts_ + light_bodies_.size());
  const double slow = static_cast<double>(bonds_.size() + contacts_.size() + bx_.size()) - fast;
  const double whole = std::floor(ratio);
  const double cost_cut = (slow + fast * whole) / (whole * light_ms);
  const double cost_heavy = (slow + fast * std::ceil(ratio)) / stable_step_ms_;
  if (cost_cut <= cost_heavy) stable_step_ms_ = whole * light_ms;
}

// At the end of a step (every body's force complete, whichever its class):
// the heavy disks whose critical step fell below the clumps' become light,
// the contacts reordered, the steps set again. Rare (a disk at a time, as
// contacts come): the only place a step may allocate.
void DemSolver::reclassify_heavy_disks() {
  reclassify_pending_ = false;
  double clump_crit = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b < bx_.size(); ++b)
    if (bclump_[b] && !bfixed_[b])
      clump_crit = std::min(clump_crit, critical_step_s(mass_[b], inertia_[b], body_kt_[b], body_kr_[b]));
  bool changed = false;
  for (std::size_t b = 0; b < bx_.size(); ++b)
    if (!blight_[b] && !bclump_[b] && !bfixed_[b] &&
        critical_step_s(mass_[b], inertia_[b], body_kt_[b], body_kr_[b]) < clump_crit) {
      blight_[b] = 1;
      changed = true;
    }
  if (!changed) return;
  list_light_bodies();
  fast_bonds_ = order_fast_first(bonds_, false);
  order_fast_first(contacts_, true);
  index_contacts();
  compute_stable_step();
}

// The contacts' order under multirate: fast contacts first, each part by
// (p, q) ascending (without multirate: (p, q) ascending).
bool DemSolver::contact_order_less(int p1, int q1, int p2, int q2) const {
  const bool fast1 = fast_contact(p1, q1), fast2 = fast_contact(p2, q2);
  if (fast1 != fast2) return fast1;
  return std::make_pair(p1, q1) < std::make_pair(p2, q2);
}

// A contact set's fast contacts moved first, both parts in their order
// (by_pairs: in contact_order_less's, which rebuild_contacts' merge needs);
// returns how many are fast. (At the start, a reclassification and a
// checkpoint's load.)
std::size_t DemSolver::order_fast_first(BondSet& set, bool by_pairs) const {
  std::vector<std::size_t> order(set.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto fast = [&](std::size_t k) { return fast_contact(set.p[k], set.q[k]); };
  if (by_pairs)
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return contact_order_less(set.p[a], set.q[a], set.p[b], set.q[b]);
    });
  else
    std::stable_partition(order.begin(), order.end(), fast);
  const auto mid = std::partition_point(order.begin(), order.end(), fast);
  permute(set.p, order), permute(set.q, order), permute(set.kn, order), permute(set.ks, order);
  permute(set.m_eff, order), permute(set.ref_gap, order), permute(set.cn, order), permute(set.cs, order);
  permute(set.kb, order), permute(set.fn, order), permute(set.fs, order), permute(set.mb, order);
  permute(set.intact, order);
  return static_cast<std::size_t>(mid - order.begin());
}

// The detector's candidate pairs (ascending) in contact_order_less's order.
void DemSolver::partition_candidates_fast_first() {
  if (blight_.empty()) return;
  candidate_scratch_.clear();
  for (const auto& [p, q] : candidate_pairs_)
    if (fast_contact(p, q)) candidate_scratch_.emplace_back(p, q);
  for (const auto& [p, q] : candidate_pairs_)
    if (!fast_contact(p, q)) candidate_scratch_.emplace_back(p, q);
  candidate_pairs_.swap(candidate_scratch_);
}

// After the contacts changed: how many unbonded contacts are fast; the
// heavy bodies that have a fast contact (the boundary), their particles
// that have one (which the substeps place), and each boundary body's fast
// contacts (so a substep reads those alone).
void DemSolver::index_multirate() {
  if (blight_.empty()) return;
  fast_contacts_ = 0;
  while (fast_contacts_ < contacts_.size() && fast_contact(contacts_.p[fast_contacts_], contacts_.q[fast_contacts_]))
    ++fast_contacts_;
  boundary_bodies_.clear();
  boundary_particles_.clear();
  boundary_entry_start_.assign(1, 0);
  boundary_entry_.clear();
  boundary_entry_particle_.clear();
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    if (blight_[b]) continue;
    for (int k = body_particle_start_[b]; k < body_particle_start_[b + 1]; ++k) {
      const int i = body_particle_[k];
      const std::size_t entries_before = boundary_entry_.size();
      for (const int* e = particle_contacts_.begin(i); e != particle_contacts_.end(i); ++e)
        if (fast_index(static_cast<std::size_t>(ContactIncidence::contact(*e)))) {
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
}

void DemSolver::step_multirate(double dt_s) {
  const double ratio = dt_s / light_step_s_;  // (light bodies without contacts: 0, one substep)
  const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(ratio * (1 - 1e-12))));
  px_old_.swap(px_);
  py_old_.swap(py_);
  move_heavy_bodies(dt_s);
  for (std::size_t j = 1; j <= n; ++j) light_substep(j, n, dt_s / static_cast<double>(n));
  const StepSums sums = move_and_sum<false>(dt_s);
  if (detector_ && detector_->needs_rebuild(sums.fit, origin_x_, origin_y_, px_.data(), py_.data(), pr_.data()))
    rebuild_contacts();
  add_strain(sums.strain, dt_s);
  heavy_forces_and_kick(dt_s, n);
  if (reclassify_pending_) reclassify_heavy_disks();
  time_s_ += dt_s;
  ++steps_;
  substeps_ += n;
  out_dirty_ = true;
}

// Every body's pose at the step's start kept; the heavy ones' first half
// kick, drift and particles (their places at t + H kept for the substeps).
void DemSolver::move_heavy_bodies(double dt_s) {
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kStepParts; ++k)
    for (std::size_t b = heavy_part_first_body_[k]; b < heavy_part_first_body_[k + 1]; ++b) {
      bx_start_[b] = bx_[b];
      by_start_[b] = by_[b];
      br_start_[b] = br_[b];
      if (blight_[b]) continue;
      kick_body(b, 0.5 * dt_s);
      drift_and_reshape(b, dt_s);
      place_particles_of(b);
      for (int j = body_particle_start_[b]; j < body_particle_start_[b + 1]; ++j) {
        const auto i = static_cast<std::size_t>(body_particle_[j]);
        px_end_[i] = px_[i];
        py_end_[i] = py_[i];
      }
    }
}

// Light body k's half kick and drift over a substep of h_s, and its
// particle placed: kick_body, drift_and_reshape and place_particles_of for a
// disk, whose particle sits at its centre and whose shape never changes.
[[gnu::always_inline]] inline void DemSolver::move_light_disk(std::size_t k, double h_s) {
  const auto b = static_cast<std::size_t>(light_bodies_[k]);
  const auto i = static_cast<std::size_t>(light_particle_[k]);
  kick_body(b, 0.5 * h_s);
  const double vx = bvx_[b], vy = bvy_[b], w = bw_[b];
  bx_[b] += vx * h_s;
  by_[b] += vy * h_s;
  bth_[b] += w * h_s;
  px_[i] = bx_[b];
  py_[i] = by_[b];
  pvx_[i] = vx;
  pvy_[i] = vy;
  pw_[i] = w;
}

// Light body k's force and moment, its particle's contacts summed as
// sum_body_contacts sums them (all of a light body's contacts are fast;
// its particle's arm is 0), and its closing half kick over h_s.
[[gnu::always_inline]] inline void DemSolver::sum_forces_and_kick_light_disk(std::size_t k, double h_s) {
  const auto b = static_cast<std::size_t>(light_bodies_[k]);
  const auto i = static_cast<std::size_t>(light_particle_[k]);
  double fx, fy, tq;  // (locals: references into bfx_ could alias the contacts' forces)
  sum_particle_contacts(i, kEveryContact, fx, fy, tq);
  bfx_[b] = fx;
  bfy_[b] = fy;
  btq_[b] = tq;
  kick_body(b, 0.5 * h_s);
}

// Substep j of n (ending at t + j h): the light bodies' velocity Verlet
// substep against the boundary's heavy particles at t + j h.
void DemSolver::light_substep(std::size_t j, std::size_t n, double h_s) {
  // (The last substep puts the heavy particles at their places at t + H
  // exactly, not x0 + 1.0 (x1 - x0).)
  const bool last = j == n;
  const double w = static_cast<double>(j) / static_cast<double>(n);
  const std::size_t nlight = light_bodies_.size(), nboundary = boundary_bodies_.size();
  const std::size_t nplaced = boundary_particles_.size();
#pragma omp parallel
  {
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < nlight; ++k) move_light_disk(k, h_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < nplaced; ++k) {
      const auto i = static_cast<std::size_t>(boundary_particles_[k]);
      const auto b = static_cast<std::size_t>(pbody_[i]);
      px_[i] = last ? px_end_[i] : px_old_[i] + w * (px_end_[i] - px_old_[i]);
      py_[i] = last ? py_end_[i] : py_old_[i] + w * (py_end_[i] - py_old_[i]);
      pr_[i] = last ? br_[b] : br_start_[b] + w * (br_[b] - br_start_[b]);
    }
    forces_of_contact_range(0, fast_bonds_, 0, fast_contacts_, h_s);
#pragma omp for schedule(static) nowait
    for (std::size_t k = 0; k < nlight; ++k) sum_forces_and_kick_light_disk(k, h_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < nboundary; ++k) add_fast_forces_of_boundary(k, w, last);
  }
}

// Boundary body k's force and moment (about its centroid at the substep's
// end) from its fast contacts, added to its sums over the step.
void DemSolver::add_fast_forces_of_boundary(std::size_t k, double w, bool last) {
  const auto b = static_cast<std::size_t>(boundary_bodies_[k]);
  const double gx = last ? bx_[b] : bx_start_[b] + w * (bx_[b] - bx_start_[b]);
  const double gy = last ? by_[b] : by_start_[b] + w * (by_[b] - by_start_[b]);
  double fx = 0, fy = 0, tq = 0;
  for (int m = boundary_entry_start_[k]; m < boundary_entry_start_[k + 1]; ++m) {
    const int e = boundary_entry_[m];
    const auto i = static_cast<std::size_t>(boundary_entry_particle_[m]);
    const ContactForce& cf = contact_force_[ContactIncidence::contact(e)];
    const bool q = ContactIncidence::is_q(e);
    const double sign = q ? 1.0 : -1.0;
    fx += sign * cf.fx;
    fy += sign * cf.fy;
    tq += cf.moment[q] + (px_[i] - gx) * sign * cf.fy - (py_[i] - gy) * sign * cf.fx;
  }
  fast_fx_[b] += fx;
  fast_fy_[b] += fy;
  fast_tq_[b] += tq;
}

// The forces of bonds [bond_begin, bond_end) and unbonded contacts
// [contact_begin, contact_end) over a step dt_s, in blocks shared among the
// threads: called by every thread of a parallel region.
void DemSolver::forces_of_contact_range(std::size_t bond_begin, std::size_t bond_end, std::size_t contact_begin,
                                        std::size_t contact_end, double dt_s) {
  BlockScratch scratch;
  const std::size_t bond_blocks = (bond_end - bond_begin + kBlock - 1) / kBlock;
  const std::size_t blocks = bond_blocks + (contact_end - contact_begin + kBlock - 1) / kBlock;
#pragma omp for schedule(static)
  for (std::size_t k = 0; k < blocks; ++k) {
    const bool bond = k < bond_blocks;
    BondSet& set = bond ? bonds_ : contacts_;
    const std::size_t begin = bond ? bond_begin + k * kBlock : contact_begin + (k - bond_blocks) * kBlock;
    const std::size_t end = bond ? bond_end : contact_end;
    const std::size_t number = bond ? begin : bonds_.size() + begin;
    contact_block(set, begin, std::min(kBlock, end - begin), number, dt_s, scratch);
  }
}

// The contacts between heavy bodies at t + H; each heavy body's force is
// theirs plus the mean of its fast contacts' over the n substeps (their
// impulse over the step, divided by H); the heavy bodies' closing half kick.
void DemSolver::heavy_forces_and_kick(double dt_s, std::size_t n) {
  const double inv_n = 1 / static_cast<double>(n);
#pragma omp parallel
  {
    forces_of_contact_range(fast_bonds_, bonds_.size(), fast_contacts_, contacts_.size(), dt_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = heavy_sum_part_first_body_[k]; b < heavy_sum_part_first_body_[k + 1]; ++b) {
        if (blight_[b]) continue;
        double f[3];
        sum_body_contacts(b, bx_[b], by_[b], [this](std::size_t c) { return !fast_index(c); }, f);
        bfx_[b] = f[0] + fast_fx_[b] * inv_n;
        bfy_[b] = f[1] + fast_fy_[b] * inv_n;
        btq_[b] = f[2] + fast_tq_[b] * inv_n;
        fast_fx_[b] = fast_fy_[b] = fast_tq_[b] = 0;
        kick_body(b, 0.5 * dt_s);
      }
  }
}

}  // namespace fibrodem
