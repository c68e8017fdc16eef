// The cells driving the DEM tissue mechanics: the mechanics steps at its own
// step up to the end of each cell step, each DEM step given the cells'
// lengths relative to rest (SL / SL_rest) interpolated linearly in time
// across the cell step; nothing flows back to the cells. It keeps the peak
// strain and the smallest DEM step taken, for summary.json.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "integrate/cell_system.hpp"
#include "io/checkpoint_file.hpp"
#include "mechanics/mechanics_solver.hpp"
#include "tissue/tissue.hpp"

namespace fibrodem {

class MechanicsCoupling {
 public:
  // Throws ManifestError at "mechanics" for a tissue or spec the solver cannot take.
  MechanicsCoupling(const Tissue& tissue, const DemSpec& spec);

  // Mechanics at its own step up to t_ms (the end of a cell step).
  void advance(double t_ms, const CellSystem& system) { advance(t_ms, system.stretch_by_cell()); }
  // The same from every cell's length relative to rest at t_ms (by tissue
  // number): what a run split over ranks gathers on rank 0
  // (run/mechanics_over_ranks.hpp).
  void advance(double t_ms, const std::vector<double>& length_ratio_by_cell);

  // The coupling's state and the solver's, for a checkpoint at the cells'
  // time; restore() throws CheckpointError if the mechanics' time does not
  // match start_ms.
  void save(CheckpointFields& fields) const;
  void restore(const CheckpointFields& fields, double start_ms);

  MechanicsSolver& solver() { return *solver_; }
  const MechanicsSolver& solver() const { return *solver_; }
  double smallest_step_ms() const { return step_ms_; }
  double seconds() const { return seconds_; }  // wall time in advance()
  const std::array<double, 3>& peak_strain() const { return peak_strain_; }

 private:
  std::unique_ptr<MechanicsSolver> solver_;
  double step_ms_ = 0, time_ms_ = 0, seconds_ = 0;
  // Cells' lengths relative to rest at the last cell step's start and end,
  // and as handed to a DEM step between them.
  std::vector<double> length_ratio_from_, length_ratio_to_, length_ratio_;
  double length_ratio_from_ms_ = 0;
  std::array<double, 3> peak_strain_{0, 0, 0};
};

}  // namespace fibrodem
