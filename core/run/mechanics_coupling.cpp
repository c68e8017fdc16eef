#include "run/mechanics_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

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
}

// A cell step of the adaptive method may span many DEM steps: each takes the
// lengths at its own end.
void MechanicsCoupling::advance(double t, const std::vector<double>& length_ratio_by_cell) {
  const auto start = std::chrono::steady_clock::now();
  length_ratio_to_ = length_ratio_by_cell;
  const double span = t - length_ratio_from_ms_;
  for (double h = solver_->step_ms(); time_ms_ + h <= t + kTimeEpsilon_ms; h = solver_->step_ms()) {
    const double w = span > 0 ? std::clamp((time_ms_ + h - length_ratio_from_ms_) / span, 0.0, 1.0) : 1.0;
    for (std::size_t cell = 0; cell < length_ratio_.size(); ++cell)
      length_ratio_[cell] = length_ratio_from_[cell] + w * (length_ratio_to_[cell] - length_ratio_from_[cell]);
    solver_->set_cell_length_ratios(length_ratio_);
    solver_->step(h);
    time_ms_ += h;
    step_ms_ = std::min(step_ms_, h);
    const auto strain = solver_->strain();
    for (int k = 0; k < 3; ++k)
      if (std::abs(strain[k]) > std::abs(peak_strain_[k])) peak_strain_[k] = strain[k];
  }
  std::swap(length_ratio_from_, length_ratio_to_);
  length_ratio_from_ms_ = t;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void MechanicsCoupling::save(CheckpointFields& f) const {
  solver_->save(f);
  f.put("run.mechanics", std::vector<double>{time_ms_, step_ms_, length_ratio_from_ms_, peak_strain_[0],
                                             peak_strain_[1], peak_strain_[2]});
  f.put("run.length_ratio_from", length_ratio_from_);
  f.put("run.length_ratio_to", length_ratio_to_);
}

void MechanicsCoupling::restore(const CheckpointFields& f, double start_ms) {
  solver_->load(f);
  const auto m = f.numbers("run.mechanics", 6);
  time_ms_ = m[0], step_ms_ = m[1], length_ratio_from_ms_ = m[2];
  // The mechanics is at most one of its steps behind the cells.
  if (!(time_ms_ <= start_ms + kTimeEpsilon_ms && time_ms_ >= start_ms - 1.0 && length_ratio_from_ms_ == start_ms))
    throw CheckpointError("its mechanics' time does not match its cells'");
  peak_strain_ = {m[3], m[4], m[5]};
  f.read_into("run.length_ratio_from", length_ratio_from_);
  f.read_into("run.length_ratio_to", length_ratio_to_);
}

}  // namespace fibrodem
