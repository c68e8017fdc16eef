#include "run/mechanics_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "util/manifest_error.hpp"
#include "stimulus/stimulus.hpp"

namespace fibrodem {

MechanicsCoupling::MechanicsCoupling(const Tissue& tissue, const DemSpec& spec) {
  try {
    solver_ = make_mechanics_solver(tissue, spec);
  } catch (const std::invalid_argument& e) {
    throw ManifestError("mechanics", e.what());
  }
  step_ms_ = solver_->step_ms();
  length_ratio_.assign(tissue.cell_count(), 1.0);
  length_ratio_from_ = length_ratio_to_ = length_ratio_;
  skip_at_rest_ = spec.skip_at_rest;
  double smallest_radius_um = 0;
  for (const auto& p : tissue.particles)
    if (smallest_radius_um == 0 || p.r_um < smallest_radius_um) smallest_radius_um = p.r_um;
  rest_distance_m_ = kRestDistance * smallest_radius_um * 1e-6;
}

// A cell step of the adaptive method may span many DEM steps: each takes the
// lengths at its own end.
void MechanicsCoupling::advance(double t, const std::vector<double>& length_ratio_by_cell) {
  const auto start = std::chrono::steady_clock::now();
  length_ratio_to_ = length_ratio_by_cell;
  if (asleep_) {
    if (drive_unchanged(length_ratio_to_) && still_at_rest(t)) {
      skip_to(t);
    } else {
      // Resume with the lengths it last saw at the start of this cell step,
      // so its drive stays continuous (no jump of up to kDriveTolerance).
      asleep_ = false;
      if (skipped_this_sleep_ > 0) length_ratio_from_ = length_ratio_;
    }
  }
  const bool stepping = !asleep_;
  if (stepping) {
    step_to(t);
    fall_asleep_if_at_rest();
  }
  std::swap(length_ratio_from_, length_ratio_to_);
  length_ratio_from_ms_ = t;
  if (cell_strain_ && stepping) cell_strain_->compute(solver_->particles());  // (skipping, nothing moved)
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void MechanicsCoupling::track_fibre_stretch(const Tissue& tissue) {
  cell_strain_ = std::make_unique<CellStrain>(tissue);
  cell_strain_->compute(solver_->particles());
}

const std::vector<double>& MechanicsCoupling::fibre_stretch() const {
  static const std::vector<double> untracked;
  return cell_strain_ ? cell_strain_->field().fibre_stretch : untracked;
}

void MechanicsCoupling::step_to(double t) {
  const double span = t - length_ratio_from_ms_;
  for (double h = solver_->step_ms(); time_ms_ + h <= t + kTimeEpsilon_ms; h = solver_->step_ms()) {
    const double w = span > 0 ? std::clamp((time_ms_ + h - length_ratio_from_ms_) / span, 0.0, 1.0) : 1.0;
    for (std::size_t cell = 0; cell < length_ratio_.size(); ++cell)
      length_ratio_[cell] = length_ratio_from_[cell] + w * (length_ratio_to_[cell] - length_ratio_from_[cell]);
    solver_->set_cell_length_ratios(length_ratio_);
    solver_->step(h);
    motion_unknown_ = true;
    time_ms_ += h;
    step_ms_ = std::min(step_ms_, h);
    const auto strain = solver_->strain();
    for (int k = 0; k < 3; ++k)
      if (std::abs(strain[k]) > std::abs(peak_strain_[k])) peak_strain_[k] = strain[k];
  }
}

// The clock moves by the steps an uninterrupted run would take (one addition
// each, the same step times); nothing else does.
void MechanicsCoupling::skip_to(double t) {
  for (const double h = solver_->step_ms(); time_ms_ + h <= t + kTimeEpsilon_ms;) {
    time_ms_ += h;
    slept_ms_ += h;
    ++skipped_steps_;
    ++skipped_this_sleep_;
  }
}

// (Split over ranks, each rank's cells hold its own lengths only: every
// rank's answer, reduced.)
bool MechanicsCoupling::drive_unchanged(const std::vector<double>& length_ratio) const {
  double changed = 0;
  for (std::size_t cell = 0; cell < length_ratio.size(); ++cell)
    if (!(std::abs(length_ratio[cell] - length_ratio_[cell]) <= kDriveTolerance)) {
      changed = 1;
      break;
    }
  if (ranks_) {
    ranks_->gather_all(&changed, 1, every_rank_.data());
    changed = *std::max_element(every_rank_.begin(), every_rank_.end());
  }
  return changed == 0;
}

void MechanicsCoupling::split_over_ranks(RankGroup& ranks, const RankLayout& layout) {
  std::vector<int> cell_rank(layout.cell_count());
  for (int r = 0; r < ranks.size(); ++r)
    for (const int cell : layout.cells_of(r)) cell_rank[static_cast<std::size_t>(cell)] = r;
  try {
    solver_->split_over_ranks(ranks, cell_rank);
  } catch (const std::invalid_argument& e) {
    throw ManifestError("mechanics", e.what());
  }
  ranks_ = &ranks;
  every_rank_.assign(static_cast<std::size_t>(ranks.size()), 0.0);
  layout_ = &layout;
}

// Split over ranks, a rank's lengths of other ranks' cells stay at rest
// (1), as the cells it steps give them (CellSystem::stretch_by_cell), so
// that only its own cells' lengths move its drive.
void MechanicsCoupling::keep_own_lengths() {
  std::vector<char> own(length_ratio_.size(), 0);
  for (const int cell : layout_->cells_of(ranks_->rank())) own[static_cast<std::size_t>(cell)] = 1;
  for (auto* v : {&length_ratio_from_, &length_ratio_to_, &length_ratio_})
    for (std::size_t c = 0; c < v->size(); ++c)
      if (!own[c]) (*v)[c] = 1.0;
}

// Split over ranks: every cell's value from its own rank, on rank 0 (by
// tissue number; empty elsewhere). Collective.
std::vector<double> MechanicsCoupling::on_rank0(const std::vector<double>& by_cell) const {
  std::vector<double> mine, gathered, out;
  gather_by_cell(*ranks_, *layout_, by_cell, mine, gathered, out);
  return out;
}

// Whether no body could have moved rest_distance_m_ between falling asleep
// and t at the speed and acceleration it had then.
bool MechanicsCoupling::still_at_rest(double t) const {
  const double T_s = (t - asleep_since_ms_) * 1e-3;
  return asleep_motion_.speed_m_per_s * T_s + 0.5 * asleep_motion_.acceleration_m_per_s2 * T_s * T_s <=
         rest_distance_m_;
}

// Asked only when the drive has not changed and the DEM has stepped since it
// was last asked: its motion is one pass over the bodies.
void MechanicsCoupling::fall_asleep_if_at_rest() {
  if (!skip_at_rest_ || !motion_unknown_ || !drive_unchanged(length_ratio_to_)) return;
  asleep_motion_ = solver_->fastest_motion();
  motion_unknown_ = false;
  asleep_since_ms_ = time_ms_;
  skipped_this_sleep_ = 0;
  // At least its next step must be skippable, or it would only wake again.
  asleep_ = still_at_rest(time_ms_ + solver_->step_ms());
}

std::string MechanicsCoupling::report() const {
  std::string r = solver_->report();
  if (!skip_at_rest_) return r + "; skip_at_rest off";
  return r + fmt::format("; at rest: {} steps skipped ({:.6g} ms asleep)", skipped_steps_, slept_ms_);
}

void MechanicsCoupling::save(CheckpointFields& f) const {
  std::vector<double> from = length_ratio_from_, to = length_ratio_to_, seen = length_ratio_;
  if (ranks_) {
    solver_->gather_on_rank0(true);
    from = on_rank0(from), to = on_rank0(to), seen = on_rank0(seen);
    if (ranks_->rank() != 0) return;
  }
  solver_->save(f);
  f.put("run.mechanics", std::vector<double>{time_ms_, step_ms_, length_ratio_from_ms_, peak_strain_[0],
                                             peak_strain_[1], peak_strain_[2]});
  f.put("run.length_ratio_from", from);
  f.put("run.length_ratio_to", to);
  f.put("run.length_ratio_seen", seen);
  f.put("run.mechanics_rest",
        std::vector<double>{motion_unknown_ ? 1.0 : 0.0, asleep_ ? 1.0 : 0.0, asleep_since_ms_,
                            asleep_motion_.speed_m_per_s, asleep_motion_.acceleration_m_per_s2,
                            static_cast<double>(skipped_steps_), static_cast<double>(skipped_this_sleep_), slept_ms_});
}

void MechanicsCoupling::restore(const CheckpointFields& f, double start_ms) {
  solver_->load(f);
  const auto m = f.numbers("run.mechanics", 6);
  time_ms_ = m[0], step_ms_ = m[1], length_ratio_from_ms_ = m[2];
  // The mechanics is at most one of its steps behind the cells.
  if (!(time_ms_ <= start_ms + kTimeEpsilon_ms && time_ms_ >= start_ms - 1.0 && length_ratio_from_ms_ == start_ms))
    throw CheckpointError("its mechanics' time does not match its cells'");
  peak_strain_ = {m[3], m[4], m[5]};
  if (cell_strain_) cell_strain_->compute(solver_->particles());  // (a function of the particles restored)
  f.read_into("run.length_ratio_from", length_ratio_from_);
  f.read_into("run.length_ratio_to", length_ratio_to_);
  // A checkpoint written without the rest state resumes awake, as its run was.
  if (!f.has("run.mechanics_rest")) {
    length_ratio_ = length_ratio_from_;
    if (ranks_) keep_own_lengths();
    motion_unknown_ = true, asleep_ = false, skipped_steps_ = skipped_this_sleep_ = 0, slept_ms_ = 0;
    return;
  }
  f.read_into("run.length_ratio_seen", length_ratio_);
  if (ranks_) keep_own_lengths();
  const auto r = f.numbers("run.mechanics_rest", 8);
  if (!(r[5] >= 0 && r[5] < 1e18 && r[6] >= 0 && r[6] <= r[5] && r[7] >= 0 && r[3] >= 0 && r[4] >= 0))
    throw CheckpointError("its mechanics' rest state is out of range");
  motion_unknown_ = r[0] != 0, asleep_ = r[1] != 0, asleep_since_ms_ = r[2];
  asleep_motion_ = {r[3], r[4]};
  skipped_steps_ = static_cast<std::size_t>(r[5]), skipped_this_sleep_ = static_cast<std::size_t>(r[6]);
  slept_ms_ = r[7];
}

}  // namespace fibrodem
