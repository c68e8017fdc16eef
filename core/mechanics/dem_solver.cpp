// A DEM step (dem_solver.hpp, "Motion" and "Threads"): the fused move loop,
// the contact list's check, the strain, then the forces and the closing kick.
#include "mechanics/dem_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mechanics/dem_step_inline.hpp"
#include "mechanics/dem_units.hpp"
#include "util/number_text.hpp"

namespace fibrodem {

void DemSolver::step(double dt_ms) {
  if (!(dt_ms > 0) || dt_ms > stable_step_ms_ * (1 + 1e-12))
    throw std::invalid_argument("mechanics step " + significant_digits(dt_ms, 6) + " ms refused: the stable DEM step is " +
                                significant_digits(stable_step_ms_, 6) + " ms");
  const double dt = dt_ms * 1e-3;
  if (!blight_.empty()) {
    step_multirate(dt);
    return;
  }
  // Half kick with the forces of the present state, drift, new geometry
  // (length ratios at the end of the step), particles.
  px_old_.swap(px_);
  py_old_.swap(py_);
  const StepSums sums = move_and_sum<true>(dt);
  if (detector_ && detector_->needs_rebuild(sums.fit, origin_x_, origin_y_, px_.data(), py_.data(), pr_.data()))
    rebuild_contacts();
  add_strain(sums.strain, dt);
  compute_forces_and_kick(dt, 0.5 * dt);
  time_s_ += dt;
  ++steps_;
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
  std::array<StepSums, kStepParts> part;
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kStepParts; ++k) {
    StepSums sum{};  // (in registers: part[k] could alias the arrays read)
    for (std::size_t b = part_first_body_[k]; b < part_first_body_[k + 1]; ++b) {
      if constexpr (kMove) {
        kick_body(b, h);
        drift_and_reshape(b, dt_s);
        place_particles_of(b);
      }
      // (Two loops over the body's particles, which are in L1 by now: the
      // two fits' 17 sums at once would not fit in registers.)
      const int first = body_particle_start_[b], last = body_particle_start_[b + 1];
      if (detector_)
        detector_->add_fit_terms(body_particle_.data() + first, last - first, px_.data(), py_.data(), origin_x_,
                                 origin_y_, sum.fit);
      if (by_particle)
        for (int j = first; j < last; ++j) {
          const auto i = static_cast<std::size_t>(body_particle_[j]);
          DemStrainFit::add_terms(sum.strain, 0.5 * (px_[i] + px_old_[i]) - origin_x_,
                                  0.5 * (py_[i] + py_old_[i]) - origin_y_, (px_[i] - px_old_[i]) * inv_dt,
                                  (py_[i] - py_old_[i]) * inv_dt);
        }
      else if constexpr (kMove)
        DemStrainFit::add_terms(sum.strain, bx_[b] - h * bvx_[b] - origin_x_, by_[b] - h * bvy_[b] - origin_y_,
                                bvx_[b], bvy_[b]);
      else
        DemStrainFit::add_terms(sum.strain, 0.5 * (bx_[b] + bx_start_[b]) - origin_x_,
                                0.5 * (by_[b] + by_start_[b]) - origin_y_, (bx_[b] - bx_start_[b]) * inv_dt,
                                (by_[b] - by_start_[b]) * inv_dt);
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

template DemSolver::StepSums DemSolver::move_and_sum<false>(double dt_s);

// The strain over a step of dt_s, from the move loop's sums.
void DemSolver::add_strain(const DemStrainFit::Sums& sums, double dt_s) {
  const std::size_t n = spec_.strain_bodies == StrainBodies::particles ? px_.size() : bx_.size();
  strain_fit_.add(sums, n, dt_s, (time_s_ + dt_s) * 1e3);
}

// Reach of a body: its farthest particle's edge from its centroid (a
// clump's end pebbles; a disk's radius), at its present shape.
MechanicsSolver::Motion DemSolver::fastest_motion() const {
  Motion m;
  for (std::size_t b = 0; b < bx_.size(); ++b) {
    if (bfixed_[b]) continue;
    const double reach = 0.5 * (brest_[b].n - 1) * bs_[b] + br_[b];
    const double speed = std::hypot(bvx_[b], bvy_[b]) + std::abs(bw_[b]) * reach;
    const double accel = std::hypot(bfx_[b], bfy_[b]) * inv_m_[b] + std::abs(btq_[b]) * inv_i_[b] * reach;
    m.speed_m_per_s = std::max(m.speed_m_per_s, speed);
    m.acceleration_m_per_s2 = std::max(m.acceleration_m_per_s2, accel);
  }
  return m;
}

std::string DemSolver::report() const {
  std::string r = std::to_string(steps_) + " steps, stable step now " + significant_digits(stable_step_ms_, 6) + " ms; " +
                  std::to_string(bonds_.size()) + " bonds (" + std::to_string(broken_bonds()) + " broken)";
  if (scaled_bodies_ > 0)
    r += "; mass scaling: " + std::to_string(scaled_bodies_) + " bodies heavier, +" +
         significant_digits(100 * added_mass_fraction_, 6) + " % of the mass, +" + significant_digits(100 * added_inertia_fraction_, 6) +
         " % of the inertia";
  if (!blight_.empty())
    r += "; multirate: " + std::to_string(light_bodies_.size()) + " light bodies at a step of " +
         significant_digits(light_step_ms(), 6) + " ms, " + std::to_string(substeps_) + " substeps, " +
         std::to_string(fast_bonds_ + fast_contacts_) + " of the " + std::to_string(bonds_.size() + contacts_.size()) +
         " contacts in them";
  if (detector_)
    r += "; unbonded contacts: " + std::to_string(touching_contacts()) + " touching of " +
         std::to_string(contacts_.size()) + " listed, list built " + std::to_string(detector_->builds()) + " times";
  else
    r += "; no contact detection";
  return r;
}

std::unique_ptr<MechanicsSolver> make_mechanics_solver(const Tissue& tissue, const DemSpec& spec) {
  if (spec.solver != "dem") throw std::invalid_argument("unknown mechanics solver '" + spec.solver + "'");
  return std::make_unique<DemSolver>(tissue, spec);
}

}  // namespace fibrodem
