// A DEM step (dem_solver.hpp, "Motion" and "Threads"): the fused move loop,
// the contact list's check, the strain, then the forces and the closing kick;
// under multirate, the heavy bodies' step around the light ones' substeps.
#include "mechanics/dem_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "mechanics/dem_step_inline.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

DemSolver::DemSolver(const Tissue& t, const DemSpec& spec)
    : spec_(spec),
      contacts_(spec),
      bodies_(t, spec),
      mass_scaling_(spec.mass_scaling, kLongestStep_ms * 1e-3 / spec.safety_factor) {
  contacts_.form_bonds(t, bodies_);
  if (contacts_.detects())
    rebuild_contacts();
  else {
    index_contacts();
    compute_stable_step();
  }
  if (spec_.multirate && multirate_.start(bodies_, contacts_)) {
    index_contacts();
    compute_stable_step();
  }
  bonded_stable_step_ms_ = stable_step_ms_;
  if (spec_.dt_ms > stable_step_ms_)
    throw std::invalid_argument("mechanics.dt_ms " + significant_digits(spec_.dt_ms, 6) +
                                " ms exceeds the stable DEM step " + significant_digits(stable_step_ms_, 6) + " ms");
}

void DemSolver::step(double dt_ms) {
  if (!(dt_ms > 0) || dt_ms > stable_step_ms_ * (1 + 1e-12))
    throw std::invalid_argument("mechanics step " + significant_digits(dt_ms, 6) +
                                " ms refused: the stable DEM step is " + significant_digits(stable_step_ms_, 6) +
                                " ms");
  const double dt = dt_ms * 1e-3;
  if (multirate_.on()) {
    step_multirate(dt);
    return;
  }
  // Half kick with the forces of the present state, drift, new geometry
  // (length ratios at the end of the step), particles.
  bodies_.px_old.swap(bodies_.px);
  bodies_.py_old.swap(bodies_.py);
  StepSums sums = move_and_sum<true>(dt);
  if (split_) {
    split_->refresh_ghosts(bodies_);
    reduce_over_ranks(sums);
  }
  update_list_and_strain(sums, dt);
  compute_forces_and_kick(dt, 0.5 * dt);
  time_s_ += dt;
  ++steps_;
  out_dirty_ = true;
}

// The multirate scheme's step (dem_multirate_step.cpp): the heavy bodies'
// first half, the light bodies' n substeps, the sums over the step, the
// heavy bodies' forces and closing half kick.
void DemSolver::step_multirate(double dt_s) {
  const std::size_t n = DemMultirate::substeps_of(dt_s, multirate_.light_step_s());
  bodies_.px_old.swap(bodies_.px);
  bodies_.py_old.swap(bodies_.py);
  multirate_.move_heavy_bodies(bodies_, dt_s);
  for (std::size_t j = 1; j <= n; ++j)
    multirate_.light_substep(bodies_, contacts_, j, n, dt_s / static_cast<double>(n));
  update_list_and_strain(move_and_sum<false>(dt_s), dt_s);
  multirate_.heavy_forces_and_kick(bodies_, contacts_, dt_s, n);
  if (multirate_.reclassify_pending() && multirate_.reclassify(bodies_, contacts_)) {
    index_contacts();
    compute_stable_step();
  }
  time_s_ += dt_s;
  ++steps_;
  multirate_.count_substeps(n);
  out_dirty_ = true;
}

// The first half of a velocity Verlet step for every body (kMove; under
// multirate the bodies have moved already), and the sums over the new
// particles (or bodies) of the strain's least-squares fit and of the contact
// list's affine fit: one pass over each body and its particles, in
// kStepParts fixed parts (equal work), each part summed in order and the
// parts in part order, so the sums have the same bits for any number of
// threads. (One pass, not one per stage: kick, drift, shape, axis,
// particles and the two fits would be eight passes over the bodies or
// particles, each ended by a wait for all threads.) A body's own velocity
// over the step: its half-step one (kMove), else from its pose at the
// step's start (a light body's velocity now is its last substep's).
template <bool kMove>
DemSolver::StepSums DemSolver::move_and_sum(double dt_s) {
  const bool by_particle = spec_.strain_bodies == StrainBodies::particles;
  const double h = 0.5 * dt_s, inv_dt = 1 / dt_s;
  DemBodies& B = bodies_;
  const ContactDetector* const detector = contacts_.detector();
  const double ox = B.origin_x, oy = B.origin_y;
  std::array<StepSums, kStepParts> part;
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kStepParts; ++k) {
    StepSums sum{};  // (in registers: part[k] could alias the arrays read)
    for (std::size_t b = B.part_first_body[k]; b < B.part_first_body[k + 1]; ++b) {
      if (!B.steps(b)) continue;  // another rank's
      if constexpr (kMove) {
        B.kick(b, h);
        B.drift_and_reshape(b, dt_s);
        B.place_particles_of(b);
      }
      // (Two loops over the body's particles, which are in L1 by now: the
      // two fits' 17 sums at once would not fit in registers.)
      const int first = B.body_particle_start[b], last = B.body_particle_start[b + 1];
      if (detector)
        detector->add_fit_terms(B.body_particle.data() + first, last - first, B.px.data(), B.py.data(), ox, oy,
                                sum.fit);
      if (by_particle)
        for (int j = first; j < last; ++j) {
          const auto i = static_cast<std::size_t>(B.body_particle[j]);
          DemStrainFit::add_terms(sum.strain, 0.5 * (B.px[i] + B.px_old[i]) - ox, 0.5 * (B.py[i] + B.py_old[i]) - oy,
                                  (B.px[i] - B.px_old[i]) * inv_dt, (B.py[i] - B.py_old[i]) * inv_dt);
        }
      else if constexpr (kMove)
        DemStrainFit::add_terms(sum.strain, B.bx[b] - h * B.bvx[b] - ox, B.by[b] - h * B.bvy[b] - oy, B.bvx[b],
                                B.bvy[b]);
      else {
        const std::vector<double> &x0 = multirate_.bx_start(), &y0 = multirate_.by_start();
        DemStrainFit::add_terms(sum.strain, 0.5 * (B.bx[b] + x0[b]) - ox, 0.5 * (B.by[b] + y0[b]) - oy,
                                (B.bx[b] - x0[b]) * inv_dt, (B.by[b] - y0[b]) * inv_dt);
      }
    }
    part[k] = sum;
  }
  StepSums total{};
  for (const auto& p : part) {
    for (std::size_t j = 0; j < total.strain.size(); ++j) total.strain[j] += p.strain[j];
    for (std::size_t j = 0; j < total.fit.size(); ++j) total.fit[j] += p.fit[j];
  }
  return total;
}

// From the move loop's sums: the contact list rebuilt if some pair may have
// come into contact, and the strain over the step of dt_s.
void DemSolver::update_list_and_strain(const StepSums& sums, double dt_s) {
  if (list_needs_rebuild(sums)) {
    if (split_) split_->share_bodies(bodies_);  // (every rank builds the whole tissue's list)
    rebuild_contacts();
  }
  const bool by_particle = spec_.strain_bodies == StrainBodies::particles;
  strain_fit_.add(sums.strain, by_particle ? bodies_.particle_count() : bodies_.size(), dt_s,
                  (time_s_ + dt_s) * 1e3);
}

// In one process from every particle; split over ranks, from the sums over
// every rank's bodies and the maxima over every rank's particles.
bool DemSolver::list_needs_rebuild(const StepSums& sums) {
  const ContactDetector* detector = contacts_.detector();
  if (!detector) return false;
  const DemBodies& B = bodies_;
  if (!split_)
    return detector->needs_rebuild(sums.fit, B.origin_x, B.origin_y, B.px.data(), B.py.data(), B.pr.data());
  if (!detector->built()) return true;
  const ContactDetector::AffineFit fit = detector->affine_fit(sums.fit, B.origin_x, B.origin_y);
  return detector->beyond_skin(fit, split_->departure(*detector, fit, B));
}

// The move loop's sums over every rank's bodies, in one message.
void DemSolver::reduce_over_ranks(StepSums& sums) {
  constexpr std::size_t ns = std::tuple_size_v<DemStrainFit::Sums>, nf = std::tuple_size_v<ContactDetector::FitSums>;
  double values[ns + nf];
  std::copy(sums.strain.begin(), sums.strain.end(), values);
  std::copy(sums.fit.begin(), sums.fit.end(), values + ns);
  split_->sum(values, ns + nf);
  std::copy(values, values + ns, sums.strain.begin());
  std::copy(values + ns, values + ns + nf, sums.fit.begin());
}

// Forces per contact in parallel (blocks of bonds, then of contacts), then
// their sums per body, each from its own contacts in a fixed order, and the
// closing half kick of h_s with them (bodies in parts of equal contact work:
// DemBodies::partition_force_sums).
void DemSolver::compute_forces_and_kick(double dt_s, double h_s) {
  DemBodies& B = bodies_;
  // (Split over ranks: the contacts that touch this rank's bodies, listed first.)
  const std::size_t bonds = split_ ? split_->own_bonds() : contacts_.bonds.size();
  const std::size_t contacts = split_ ? split_->own_contacts() : contacts_.contacts.size();
#pragma omp parallel
  {
    contacts_.forces_of_range(B, 0, bonds, 0, contacts, dt_s);
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < kStepParts; ++k)
      for (std::size_t b = B.sum_part_first_body[k]; b < B.sum_part_first_body[k + 1]; ++b) {
        if (!B.steps(b)) continue;
        double f[3];
        contacts_.sum_body(B, b, B.bx[b], B.by[b], kEveryContact, f);
        B.bfx[b] = f[0];
        B.bfy[b] = f[1];
        B.btq[b] = f[2];
        B.kick(b, h_s);
      }
  }
}

// A new Verlet list of unbonded contacts, then the stable step.
void DemSolver::rebuild_contacts() {
  contacts_.rebuild_list(bodies_, contact_order());
  index_contacts();
  compute_stable_step();
  if (spec_.dt_ms > stable_step_ms_ && steps_ > 0)
    throw std::invalid_argument("at t = " + significant_digits(time_ms(), 6) +
                                " ms new contacts lower the stable DEM step to " +
                                significant_digits(stable_step_ms_, 6) + " ms, below mechanics.dt_ms " +
                                significant_digits(spec_.dt_ms, 6) +
                                " ms: lower mechanics.dt_ms, or leave it out (automatic step)");
}

// Everything indexed by the contacts, after they changed: their arrays and
// incidences, the force sums' parts, the multirate boundary.
void DemSolver::index_contacts() {
  contacts_.index(bodies_);
  bodies_.partition_force_sums(contacts_.particle_contacts);
  multirate_.index(bodies_, contacts_);
  if (split_) split_->plan_halo(bodies_, contacts_);
}

// The contacts' order in their sets: multirate's (fast first), the split's
// (this rank's first), else by pairs.
ContactOrder DemSolver::contact_order() const {
  return split_ ? split_->order(bodies_) : multirate_.order(bodies_);
}

void DemSolver::split_over_ranks(RankGroup& ranks, const std::vector<int>& cell_rank) {
  if (multirate_.on())
    throw std::invalid_argument("mechanics.multirate cannot be split over ranks (its substeps are not split)");
  split_ = std::make_unique<DemSplit>(ranks, cell_rank, bodies_, contacts_);
  contacts_.reorder(contact_order());
  index_contacts();
}

void DemSolver::gather_on_rank0(bool whole_state) {
  if (!split_) return;
  split_->gather_bodies(bodies_, whole_state);
  if (whole_state) split_->gather_contacts(contacts_, bodies_);
  out_dirty_ = true;
}

// Each contact counted by the rank of its particle p's body, as the
// gather of every contact's state takes it from there.
void DemSolver::count_on_rank0() {
  if (!split_) return;
  double counts[2] = {static_cast<double>(contacts_.broken_bonds(&bodies_)),
                       static_cast<double>(contacts_.touching_contacts(&bodies_))};
  split_->sum(counts, 2);
  counted_ = {static_cast<std::size_t>(counts[0]), static_cast<std::size_t>(counts[1])};
  counted_at_step_ = steps_;
}

void DemSolver::set_cell_length_ratios(const std::vector<double>& ratio) { bodies_.set_cell_length_ratios(ratio); }

const std::vector<Particle>& DemSolver::particles() const {
  if (out_dirty_) {
    bodies_.export_particles(out_);
    out_dirty_ = false;
  }
  return out_;
}

DemSolver::BodyState DemSolver::body(std::size_t b) const {
  const DemBodies& B = bodies_;
  return {B.bx[b], B.by[b], B.bth[b], B.bvx[b], B.bvy[b], B.bw[b], B.mass[b], B.inertia[b],
          B.bcell[b], B.bclump[b] != 0, B.bfixed[b] != 0};
}

void DemSolver::set_body_velocity(std::size_t b, double vx, double vy, double w) {
  if (bodies_.bfixed[b]) return;
  bodies_.bvx[b] = vx;
  bodies_.bvy[b] = vy;
  bodies_.bw[b] = w;
}

MechanicsSolver::Motion DemSolver::fastest_motion() const {
  Motion m = bodies_.fastest_motion();
  if (!split_) return m;
  double values[2] = {m.speed_m_per_s, m.acceleration_m_per_s2};
  split_->max(values, 2);
  return {values[0], values[1]};
}

std::string DemSolver::report() const {
  std::string r = std::to_string(steps_) + " steps, stable step now " + significant_digits(stable_step_ms_, 6) +
                  " ms; " + std::to_string(contacts_.bonds.size()) + " bonds (" + std::to_string(broken_bonds()) +
                  " broken)";
  if (scaled_bodies() > 0)
    r += "; mass scaling: " + std::to_string(scaled_bodies()) + " bodies heavier, +" +
         significant_digits(100 * added_mass_fraction(), 6) + " % of the mass, +" +
         significant_digits(100 * added_inertia_fraction(), 6) + " % of the inertia";
  if (multirate_.on())
    r += "; multirate: " + std::to_string(light_bodies()) + " light bodies at a step of " +
         significant_digits(light_step_ms(), 6) + " ms, " + std::to_string(substeps()) + " substeps, " +
         std::to_string(multirate_.fast_bonds() + multirate_.fast_contacts()) + " of the " +
         std::to_string(contacts_.bonds.size() + contacts_.contacts.size()) + " contacts in them";
  if (contacts_.detects())
    r += "; unbonded contacts: " + std::to_string(touching_contacts()) + " touching of " +
         std::to_string(contacts_.contacts.size()) + " listed, list built " + std::to_string(contact_list_builds()) +
         " times";
  else
    r += "; no contact detection";
  return r;
}

std::unique_ptr<MechanicsSolver> make_mechanics_solver(const Tissue& tissue, const DemSpec& spec) {
  if (spec.solver != "dem") throw std::invalid_argument("unknown mechanics solver '" + spec.solver + "'");
  return std::make_unique<DemSolver>(tissue, spec);
}

}  // namespace fibrodem
